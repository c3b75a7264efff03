"""The clock-synchronisation stage (footnav.pipeline.sync): both feet on one clock before detection.

References: the simulator's true clock (its right foot's stamps are ``(1 + drift) t + offset`` of
true time t, the left foot's are true time), and the same walk simulated without the offset.
"""

import json

import numpy as np
import pytest

import footnav
from footnav.cli import main
from footnav.core.errors import CompositionError, InvalidInputError, InvalidParameterError
from footnav.data.io.footnav_csv import write_footnav_csv
from footnav.pipeline.factory import load_pipeline, make_pipeline
from footnav.pipeline.sync import ClockSync, synchronise

OFFSET_S = 0.35
DRIFT_PPM = 80.0


@pytest.fixture(scope="module")
def walks():
    common = {"distance_m": 25.0, "seed": 3}
    on_time = footnav.simulate("straight", **common)
    offset = footnav.simulate(
        "straight", clock_offset_s=OFFSET_S, clock_drift_ppm=DRIFT_PPM, clock_exchanges=60, **common
    )
    return on_time, offset


def test_data_sync_maps_the_right_foot_onto_true_time(walks):
    on_time, offset = walks
    assert np.abs(offset.right.t - on_time.right.t).max() > 0.3  # the premise: the clocks differ
    # the simulator's walker sets off with the right foot (footnav.nav.clock_sync's example)
    synced, _ = synchronise(offset, ClockSync("data", drift=True, leading_foot="right"))
    err = np.abs(synced.right.t - on_time.right.t)
    assert err.max() < 0.005, err.max()  # half a 100 Hz sample
    assert synced.left is offset.left  # the reference foot is not touched
    assert synced.meta["sync"]["right"]["method"] == "data"
    assert synced.right.meta["clock"]["method"] == "data"


def test_exchange_sync_maps_onto_the_master_clock(walks):
    on_time, offset = walks
    synced, res = synchronise(offset, ClockSync("exchanges"))
    assert np.abs(synced.right.t - on_time.right.t).max() < 0.005
    # the left sensor has no exchanges: it is the master, kept and said so
    assert synced.left.t is offset.left.t
    assert synced.meta["sync"]["left"]["method"].startswith("master")
    # drift from the exchanges, against the simulated 80 ppm: the map's rate is 1 / (1 + 80e-6)
    assert res.clocks["right"].a == pytest.approx(1.0 / (1.0 + DRIFT_PPM * 1e-6), abs=2e-4)


def test_pipeline_with_sync_matches_the_walk_recorded_on_one_clock(walks):
    on_time, offset = walks
    reference = make_pipeline(fusion="range").run(on_time)
    synced = make_pipeline(fusion="range", sync="data").run(offset)
    b = synced.meta["sync"]["right"]["b_s"]
    assert b == pytest.approx(-OFFSET_S, abs=0.01)
    # same walk, same sensors: a sub-sample time error moves the feet by millimetres
    for foot in ("left", "right"):
        diff = np.abs(getattr(synced, foot).position[-1] - getattr(reference, foot).position[-1])
        assert diff.max() < 0.05, (foot, diff)


def test_sync_is_checked_before_any_work(walks):
    _, offset = walks
    with pytest.raises(CompositionError, match="needs both feet"):
        make_pipeline(sync="data").run(offset.left)
    with pytest.raises(InvalidInputError, match="clock_exchanges"):
        make_pipeline(sync="exchanges").run(footnav.simulate("straight", distance_m=10.0))
    with pytest.raises(InvalidParameterError, match="method"):
        make_pipeline(sync="gps")
    with pytest.raises(InvalidParameterError, match="max_offset_s"):
        make_pipeline(sync={"method": "data", "max_offset_s": -1.0})
    with pytest.raises(InvalidParameterError, match="no parameter 'drfit'"):
        make_pipeline(sync={"method": "data", "drfit": True})
    with pytest.raises(CompositionError, match="whole recording"):
        make_pipeline("threshold", sync="data").online()


def test_bad_exchanges_name_the_foot_and_field(walks):
    _, offset = walks
    bad = {"tm1": [0.0, 1.0], "ti": [5.0, 4.0], "tm2": [0.1, 1.1]}  # the IMU clock runs backwards
    with pytest.raises(InvalidInputError, match="right.clock_exchanges") as exc:
        ClockSync("exchanges").align(offset.left, offset.right, exchanges={"right": bad})
    assert exc.value.field == "right.clock_exchanges"
    with pytest.raises(InvalidInputError, match="mapping of arrays"):
        ClockSync("exchanges").align(offset.left, offset.right, exchanges={"left": [1, 2, 3]})


def test_sync_table_round_trips_through_toml(tmp_path):
    pipe = make_pipeline("threshold", sync={"method": "data", "drift": True, "smooth_s": 4.0})
    path = tmp_path / "p.toml"
    path.write_text(pipe.to_toml())
    assert "[sync]" in path.read_text()
    again = load_pipeline(path)
    assert again.config() == pipe.config()
    assert again.sync.drift is True and again.sync.smooth_s == 4.0
    assert "sync" not in make_pipeline().config()  # no stage, no table


def test_cli_run_sync_data(walks, tmp_path, capsys):
    _, offset = walks
    left, right = (
        write_footnav_csv(offset.left, tmp_path / "l.csv"),
        write_footnav_csv(offset.right, tmp_path / "r.csv"),
    )
    out = tmp_path / "res"
    args = ["run", "--left", str(left), "--right", str(right), "--sync", "data", "--out", str(out)]
    assert main(args) == 0
    toml = (out / "pipeline.toml").read_text()
    assert "[sync]" in toml and 'method = "data"' in toml
    doc = json.loads((out / "summary.json").read_text())
    assert json.dumps(doc).count("b_s") >= 1  # the applied map is in the provenance
