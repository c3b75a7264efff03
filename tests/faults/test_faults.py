"""Fault injection: good recordings broken on purpose, and what footnav must do with each.

Every case is either a specific error (type, field, first bad index, file and line where there is
one, and a message that says what to do) or a DataQualityWarning plus a record in ``meta`` of what
was done. The table of cases with their expected behaviour is in docs/reliability.md.
"""

from __future__ import annotations

import warnings
from dataclasses import replace

import numpy as np
import pytest

import footnav
from footnav import CompositionError, DataQualityWarning, InvalidInputError, StanceResult
from footnav.data.io import read_footnav_csv
from footnav.data.io.footnav_csv import write_footnav_csv

pytestmark = pytest.mark.fault

DETECTORS = [d for d in footnav.list_components()["detector"] if d != "example-gyro"]
ESTIMATORS = footnav.list_components()["estimator"]
FUSIONS = footnav.list_components()["fusion"]


@pytest.fixture(scope="module")
def walk():
    return footnav.simulate("straight", seed=3, distance_m=12.0)


def _arrays(imu):
    return imu.t.copy(), imu.acc.copy(), imu.gyr.copy()


# -- samples and time stamps, at the edge (from_arrays, every reader) ------------------------------
@pytest.mark.parametrize("bad, field", [(np.nan, "acc"), (np.inf, "acc"), (-np.inf, "gyr"), (np.nan, "gyr")])
def test_non_finite_sample_is_an_error_naming_field_and_index(walk, bad, field):
    t, acc, gyr = _arrays(walk.left)
    (acc if field == "acc" else gyr)[57, 1] = bad
    with pytest.raises(InvalidInputError) as err:
        footnav.ImuData.from_arrays(t, acc, gyr)
    assert err.value.field == field and err.value.index == 57


def test_nan_time_is_an_error(walk):
    t, acc, gyr = _arrays(walk.left)
    t[10] = np.nan
    with pytest.raises(InvalidInputError) as err:
        footnav.ImuData.from_arrays(t, acc, gyr)
    assert err.value.field == "t" and err.value.index == 10


def test_duplicated_time_stamps_are_an_error_or_dropped_and_recorded(walk):
    t, acc, gyr = _arrays(walk.left)
    t[101] = t[100]
    with pytest.raises(InvalidInputError, match="drop_duplicates") as err:
        footnav.ImuData.from_arrays(t, acc, gyr)
    assert err.value.index == 101
    with pytest.warns(DataQualityWarning) as caught:
        imu = footnav.ImuData.from_arrays(t, acc, gyr, drop_duplicates=True)
    # the dropped row leaves a double interval, which is reported as a gap too
    assert [("repeated time stamp" in str(w.message), "gap" in str(w.message)) for w in caught] == [
        (True, False),
        (False, True),
    ]
    assert imu.meta["duplicates_dropped"] == {"count": 1, "indices": [101]} and imu.n_samples == len(t) - 1


def test_backwards_time_is_an_error(walk):
    t, acc, gyr = _arrays(walk.left)
    t[200] = t[198]
    with pytest.raises(InvalidInputError, match="backwards") as err:
        footnav.ImuData.from_arrays(t, acc, gyr)
    assert err.value.index == 200


def test_dropped_packets_are_a_warning_and_listed(walk):
    t, acc, gyr = _arrays(walk.left)
    keep = np.ones(len(t), bool)
    keep[300:310] = False
    with pytest.warns(DataQualityWarning, match="gap"):
        imu = footnav.ImuData.from_arrays(t[keep], acc[keep], gyr[keep])
    assert imu.meta["gaps"][0][0] == 300
    with pytest.warns(DataQualityWarning, match="integrates across 1 sampling gap"):
        result = footnav.make_pipeline().run(imu)  # still runs; the gap is in the provenance
    assert any("gap" in w for w in result.meta["warnings"])
    assert result.left.meta["gaps_bridged"] == [(300, pytest.approx(0.11))]


@pytest.mark.parametrize(
    "declared, scale, unit", [("gyr", 180 / np.pi, "deg/s"), ("acc", 1 / footnav.GRAVITY_MPS2, "'g'")]
)
def test_units_declared_wrong_are_an_error(walk, declared, scale, unit):
    t, acc, gyr = _arrays(walk.left)
    if declared == "gyr":
        gyr = gyr * scale
    else:
        acc = acc * scale
    with pytest.raises(InvalidInputError, match=unit) as err:
        footnav.ImuData.from_arrays(t, acc, gyr)
    assert err.value.field == declared


def test_saturated_samples_are_a_warning_and_recorded(walk, tmp_path):
    t, acc, gyr = _arrays(walk.left)
    full_scale = 6.0  # rad/s (344 deg/s): the simulated swing peaks near 9 rad/s
    gyr = np.clip(gyr, -full_scale, full_scale)
    path = write_footnav_csv(footnav.ImuData(t, acc, gyr), tmp_path / "clipped.csv")
    with pytest.warns(DataQualityWarning, match="clipped|saturat"):
        imu = read_footnav_csv(path)
    assert imu.meta["clipped"]["gyr"] > 0


# -- files ----------------------------------------------------------------------------------------
@pytest.fixture
def csv_file(walk, tmp_path):
    return write_footnav_csv(walk.left, tmp_path / "walk.csv")


def test_truncated_file_names_file_and_line(csv_file):
    text = csv_file.read_text()
    csv_file.write_text(text[: len(text) // 2].rsplit(",", 2)[0])  # cut mid-row
    with pytest.raises(InvalidInputError) as err:
        read_footnav_csv(csv_file)
    assert err.value.path == str(csv_file) and err.value.line is not None


def test_empty_file_is_an_error(tmp_path):
    p = tmp_path / "empty.csv"
    p.write_text("")
    with pytest.raises(InvalidInputError, match="empty"):
        read_footnav_csv(p)


def test_wrong_column_count_names_the_line(csv_file):
    lines = csv_file.read_text().splitlines()
    lines[10] = lines[10] + ",1.0"
    csv_file.write_text("\n".join(lines) + "\n")
    with pytest.raises(InvalidInputError) as err:
        read_footnav_csv(csv_file)
    assert err.value.line == 11


def test_non_numeric_field_names_line_and_column(csv_file):
    lines = csv_file.read_text().splitlines()
    cells = lines[20].split(",")
    cells[3] = "abc"
    lines[20] = ",".join(cells)
    csv_file.write_text("\n".join(lines) + "\n")
    with pytest.raises(InvalidInputError, match="abc") as err:
        read_footnav_csv(csv_file)
    assert err.value.line == 21 and err.value.field == "acc_z"


# -- the walk itself: every detector, estimator and fusion -------------------------------------------
def _still(n=2000, rate=100.0, seed=0):
    rng = np.random.default_rng(seed)
    t = np.arange(n) / rate
    acc = np.array([0.0, 0.0, footnav.GRAVITY_MPS2]) + 0.01 * rng.standard_normal((n, 3))
    return footnav.ImuData(t, acc, 0.002 * rng.standard_normal((n, 3)))


def _spinning(rate=100.0):
    """A foot that never stops: a simulated walk with its stance samples cut out."""
    rec = footnav.simulate("straight", seed=4, distance_m=30.0, rate_hz=rate)
    moving = ~rec.truth_left.stance
    n = int(moving.sum())
    return footnav.ImuData(np.arange(n) / rate, rec.left.acc[moving], rec.left.gyr[moving])


def _detect(name, imu, other=None):
    det = footnav.make_detector(name)
    if det.needs_two_feet:
        return det.detect_pair(imu, other if other is not None else imu)[0]
    return det.detect(imu)


@pytest.mark.parametrize("name", DETECTORS)
def test_detector_on_all_standstill_is_an_error_or_one_stance(name):
    try:
        stance = _detect(name, _still())
    except InvalidInputError as err:
        assert "standstill" in str(err)
    else:
        assert stance.mask.mean() > 0.95  # documented: the whole recording is one stance


@pytest.mark.parametrize("name", DETECTORS)
def test_detector_on_no_standstill_is_an_error_or_empty(name):
    try:
        stance = _detect(name, _spinning())
    except InvalidInputError as err:
        assert "standstill" in str(err)
    else:
        assert not stance.mask.any()


@pytest.mark.parametrize("name", DETECTORS)
def test_detector_on_a_two_second_recording_is_an_error_or_a_result(name, walk):
    short = walk.left.slice(0, int(2 * walk.left.rate_hz))
    try:
        stance = _detect(name, short, walk.right.slice(0, int(2 * walk.right.rate_hz)))
    except InvalidInputError as err:
        assert str(err)
    else:
        assert len(stance.mask) == short.n_samples


@pytest.mark.parametrize("name", ESTIMATORS)
def test_estimator_without_initial_standstill_warns_and_records(name, walk):
    first_swing = int(np.flatnonzero(~walk.truth_left.stance)[0])
    imu = walk.left.slice(first_swing + 5, walk.left.n_samples)
    stance = StanceResult(walk.truth_left.stance[first_swing + 5 :])
    with pytest.warns(DataQualityWarning, match="does not start at standstill"):
        traj = footnav.make_estimator(name).estimate(imu, stance)
    assert traj.meta["estimate_start_index"] > 0 and np.isfinite(traj.position).all()


@pytest.mark.parametrize("name", ESTIMATORS)
def test_estimator_with_no_stance_is_an_error(name, walk):
    with pytest.raises(InvalidInputError, match="no stance") as err:
        footnav.make_estimator(name).estimate(walk.left, StanceResult(np.zeros(walk.left.n_samples, bool)))
    assert err.value.field == "stance.mask"


@pytest.mark.parametrize("name", ESTIMATORS)
def test_estimator_with_a_mask_of_the_wrong_length_is_an_error(name, walk):
    with pytest.raises(InvalidInputError, match="samples"):
        footnav.make_estimator(name).estimate(walk.left, StanceResult(walk.truth_left.stance[:-3]))


@pytest.mark.parametrize("name", [f for f in FUSIONS if footnav.make_fusion(f).needs_two_feet])
def test_two_foot_fusion_given_one_foot_fails_before_running(name, walk):
    with pytest.raises(CompositionError, match="two feet|both feet"):
        footnav.make_pipeline("threshold", "ekf", name).run(walk.left)


@pytest.mark.parametrize("name", FUSIONS)
def test_fusion_with_one_foot_much_shorter_runs_on_the_common_part(name, walk):
    right = walk.right.slice(0, walk.right.n_samples // 2)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DataQualityWarning)
        res = footnav.make_pipeline("threshold", "ekf", name).run(walk.left, right)
    assert res.right.position.shape[0] == right.n_samples and np.isfinite(res.left.position).all()
    assert np.isfinite(res.path.position).all() and res.path.t[-1] <= right.t[-1] + 1e-9


@pytest.mark.parametrize("name", FUSIONS)
def test_fusion_with_feet_at_different_rates(name):
    rec = footnav.simulate("straight", seed=5, distance_m=10.0, rate_hz=100.0)
    fast = footnav.simulate("straight", seed=5, distance_m=10.0, rate_hz=200.0)
    res = footnav.make_pipeline("threshold", "ekf", name).run(rec.left, fast.right)
    assert res.right.position.shape[0] == fast.right.n_samples
    assert np.linalg.norm(res.left.position[-1, :2] - res.right.position[-1, :2]) < 1.0


def test_feet_on_different_clocks_are_refused_by_the_two_foot_detector(walk):
    shifted = replace(walk.right, t=walk.right.t + 3600.0)
    with pytest.raises(InvalidInputError, match="one clock"):
        footnav.make_pipeline("dual-gait").run(walk.left, shifted)
