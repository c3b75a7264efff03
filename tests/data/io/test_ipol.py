"""IPOL gait data set (Voisard et al., IPOL 2023): two Xsens feet on one counter clock, labelled swings."""

from __future__ import annotations

import itertools
import json
import warnings

import numpy as np
import pytest

from footnav.core.errors import DataNotFoundError, DataQualityWarning, InvalidInputError
from footnav.core.types import GRAVITY_MPS2, stance_intervals
from footnav.data.datasets import data_dir
from footnav.data.io import guess_format, load, read_ipol

COLUMNS = ["PacketCounter", "Acc_X", "Acc_Y", "Acc_Z", "Gyr_X", "Gyr_Y", "Gyr_Z", "Mag_X", "Mag_Y", "Mag_Z"]


def _write_foot(path, counters, seed):
    rng = np.random.default_rng(seed)
    rows = []
    for c in counters:
        acc = [0.1, -0.2, GRAVITY_MPS2] + 0.01 * rng.standard_normal(3)
        gyr = 0.005 * rng.standard_normal(3)
        mag = [0.5, -0.3, 0.8]
        rows.append("\t".join([f"{c:.1f}"] + [repr(float(v)) for v in (*acc, *gyr, *mag)]))
    path.write_text("\n".join(["Acquisition frequency: 100 Hz", "\t".join(COLUMNS)] + rows) + "\n")


@pytest.fixture
def trial(tmp_path):
    """A tiny IPOL trial: left loses counters 3 and 4, right starts at counter 1 and loses 20."""
    left = [c for c in range(40) if c not in (3, 4)]
    right = [c for c in range(1, 38) if c != 20]
    _write_foot(tmp_path / "9-1_lf.txt", left, 0)
    _write_foot(tmp_path / "9-1_rf.txt", right, 1)
    info = {
        "Subject": 9,
        "Trial": 1,
        "Filename": "9-1",
        "Age": 30,
        "Gender": "M",
        "Height": 180.0,
        "Weight": 70.0,
        "TrialBoundaries": [5, 33],
        "UTurnBoundaries": [15, 22],
        # left swings: [8, 12], [20, 25]; right: [5, 9], [14, 20] (20 is lost), [26, 33], one after the end
        "LeftFootEvents": [[8, 12], [20, 25]],
        "RightFootEvents": [[5, 9], [14, 20], [26, 33], [34, 36]],
    }
    (tmp_path / "9-1.json").write_text(json.dumps(info))
    return tmp_path


def _read(path):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DataQualityWarning)  # lost packets are warned about by design
        return read_ipol(path)


def test_synthetic_trial_time_events_and_stance(trial):
    with pytest.warns(DataQualityWarning, match="lost packet"):
        rec = read_ipol(trial / "9-1.json")
    assert rec.n_feet == 2 and rec.name == "9-1" and rec.meta["format"] == "ipol"
    # time from the counter: the left's lost counters 3, 4 leave a 30 ms step
    np.testing.assert_allclose(rec.left.t[:5], [0.0, 0.01, 0.02, 0.05, 0.06])
    assert rec.right.t[0] == pytest.approx(0.01) and len(rec.left.t) == 38 and len(rec.right.t) == 36
    assert rec.left.has_mag and rec.left.meta["foot"] == "left"
    tl, tr = rec.truth_left, rec.truth_right
    # left row of counter c is c - 2 from counter 5 on
    np.testing.assert_array_equal(tl.events["toe_off"], [6, 18])
    np.testing.assert_array_equal(tl.events["heel_strike"], [10, 23])
    assert tl.meta["trial_boundaries"] == (3, 31)
    # right: row = counter - 1 below 20, counter - 2 above; counter 20 is lost: 19 and 21 are
    # equally near, the earlier row is taken
    np.testing.assert_array_equal(tr.events["toe_off"], [4, 13, 24, 32])
    np.testing.assert_array_equal(tr.events["heel_strike"], [8, 18, 31, 34])
    assert tr.meta["event_mapping_max_error_samples"] == 1
    np.testing.assert_array_equal(tr.meta["trial_boundaries"], (4, 31))
    assert tr.meta["swings_inside"].tolist() == [True, True, True, False]
    # stance = labelled and between swings; outside the boundaries nothing is labelled
    np.testing.assert_array_equal(stance_intervals(tl.stance), [[3, 6], [10, 18], [23, 31]])
    np.testing.assert_array_equal(stance_intervals(tr.stance), [[8, 13], [18, 24]])
    assert not tl.stance[~tl.meta["labelled"]].any()
    assert tl.meta["labelled"].sum() == 28 and len(tl.t) == 0 and tl.frame == "gait_events"
    assert rec.meta["subject"]["height_m"] == pytest.approx(1.8)


@pytest.mark.parametrize("name", ["9-1.json", "9-1_lf.txt", "9-1_rf.txt", "9-1"])
def test_any_trial_file_or_the_stem_reads_the_trial(trial, name):
    rec = _read(trial / name)
    assert rec.name == "9-1" and len(rec.left.t) == 38


def test_load_guesses_ipol_not_xsens(trial, tmp_path):
    for name in ("9-1.json", "9-1_lf.txt", "9-1_rf.txt"):
        assert guess_format(trial / name)[0] == "ipol"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DataQualityWarning)
        assert load(trial / "9-1_rf.txt").n_feet == 2
    # a lone foot file of the same layout is an Xsens export of one sensor
    lone = tmp_path / "lone"
    lone.mkdir()
    _write_foot(lone / "3-3_lf.txt", range(5), 0)
    assert guess_format(lone / "3-3_lf.txt")[0] == "xsens"


def test_missing_json_reads_without_truth(trial):
    (trial / "9-1.json").unlink()
    with pytest.warns(DataQualityWarning) as record:
        rec = read_ipol(trial / "9-1_lf.txt")
    assert any("without truth" in str(w.message) for w in record)
    assert rec.truth_left is None and rec.truth_right is None


def test_missing_foot(trial):
    (trial / "9-1_rf.txt").unlink()
    with pytest.raises(DataNotFoundError, match="_rf.txt"):
        read_ipol(trial / "9-1")


def test_bad_swings_name_field_and_index(trial):
    info = json.loads((trial / "9-1.json").read_text())
    info["LeftFootEvents"] = [[8, 12], [20, 18]]
    (trial / "9-1.json").write_text(json.dumps(info))
    with pytest.raises(InvalidInputError, match=r"LeftFootEvents.*index 1|index 1.*LeftFootEvents"):
        _read(trial / "9-1")
    info["LeftFootEvents"] = [[8, 22], [20, 25]]
    (trial / "9-1.json").write_text(json.dumps(info))
    with pytest.raises(InvalidInputError, match="disjoint"):
        _read(trial / "9-1")


# ---------------------------------------------------------------------------------------------
# the shared data
# ---------------------------------------------------------------------------------------------
@pytest.fixture
def ipol_dir():
    try:
        d = data_dir() / "ipol_dev"
    except DataNotFoundError as exc:
        pytest.skip(str(exc))
    if not d.is_dir():
        pytest.skip(f"{d} not found")
    return d


def test_real_trial_counter_gaps_and_feet(ipol_dir):
    rec = _read(ipol_dir / "1-1.json")
    for imu in (rec.left, rec.right):
        dt = np.diff(imu.t)
        # lost packets are time gaps, not shortened time: steps are whole multiples of 10 ms
        assert dt.max() > 0.015 and np.allclose(dt * 100, np.round(dt * 100))
        assert imu.meta["lost_packets"]["count"] > 0 and imu.has_mag
    # same row count, different spans: the row number is not time
    assert len(rec.left.t) == len(rec.right.t) == 2913
    assert rec.left.t[-1] == pytest.approx(29.98) and rec.right.t[-1] == pytest.approx(30.44)
    assert rec.meta["subject"]["age_years"] == 49


@pytest.mark.parametrize("stem", ["1-1", "1-6", "3-3", "8-5"])
def test_real_events_inside_file_and_stances_alternate_with_swings(ipol_dir, stem):
    rec = _read(ipol_dir / f"{stem}.json")
    if stem == "1-6":
        assert len(rec.left.t) != len(rec.right.t)
    for imu, truth in ((rec.left, rec.truth_left), (rec.right, rec.truth_right)):
        n = len(imu.t)
        to, hs = truth.events["toe_off"], truth.events["heel_strike"]
        assert len(to) == len(hs) > 10 and to.min() >= 0 and hs.max() < n and (to < hs).all()
        # every labelled counter was received, or is within a few lost packets
        assert truth.meta["event_mapping_max_error_samples"] <= 5
        start, end = truth.meta["trial_boundaries"]
        lab = truth.meta["labelled"]
        assert lab.sum() == end - start and lab[start] and not lab[end]
        # inside the boundaries: stance, swing, stance, ... -- each labelled swing is a gap
        # between two stances, except at the span's ends
        inside = truth.meta["swings_inside"]
        runs = stance_intervals(truth.stance)
        swings = np.column_stack((to, hs))[inside]
        assert len(runs) in (len(swings) - 1, len(swings), len(swings) + 1)
        for a, b in swings:
            assert not truth.stance[a:b].any()
        for (_, b0), (a1, _) in itertools.pairwise(runs):
            # between two stance runs lies exactly one labelled swing
            assert ((swings[:, 0] == b0) & (swings[:, 1] == a1)).sum() == 1
        # the swings are where the foot turns: more gyro energy than in the labelled stances
        g = np.linalg.norm(imu.gyr, axis=1)
        swing_mask = lab & ~truth.stance
        assert g[swing_mask].mean() > 1.3 * g[truth.stance].mean()


def test_real_feet_share_the_counter_clock(ipol_dir):
    # On one clock the two feet's swings do not overlap (walking keeps a double support).
    rec = _read(ipol_dir / "1-1.json")
    left = np.column_stack(
        (rec.left.t[rec.truth_left.events["toe_off"]], rec.left.t[rec.truth_left.events["heel_strike"]])
    )
    right = np.column_stack(
        (rec.right.t[rec.truth_right.events["toe_off"]], rec.right.t[rec.truth_right.events["heel_strike"]])
    )
    overlaps = sum(1 for a in left for b in right if a[0] < b[1] and b[0] < a[1])
    assert overlaps == 0
