"""footnav.nav.strides: which strides are standstill ones, each reason alone, on hand-built
10 Hz masks (the expected strides worked out from the module's two rules).

Stride parameters: a hand-computed walk, the simulator's truth, the estimate, and the gaitmap
example's motion capture.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import footnav
from footnav.core.errors import InvalidInputError
from footnav.core.types import FootTrajectory
from footnav.nav import quaternion as quat
from footnav.nav.strides import STRIDE_COLUMNS, mid_stances, stride_parameters


def _strides(stances, n):
    t = np.arange(n) * 0.1
    mask = np.zeros(n, bool)
    for a, b in stances:
        mask[a:b] = True
    pos = np.zeros((n, 3))
    pos[:, 0] = np.cumsum(~mask) * 0.1  # 1 m/s while the foot swings
    return stride_parameters(_trajectory(t, pos, quat.from_yaw(np.zeros(n))), mask)


def test_a_stride_long_in_duration_alone_is_a_standstill_one():
    # mutant: strides-standstill-and. Stances of 0.5 s every 1.2 s; the swing between the 4th and
    # 5th lasts 3 s (a stance the detector missed): that stride (mid 3 -> mid 4) lasts 3.7 s, more
    # than 2 x the median 1.2 s, though no stance is long
    starts = [0, 12, 24, 36, 78, 90, 102]
    s = _strides([(a, a + 5) for a in starts], 110)
    assert len(s) == 6
    assert list(np.flatnonzero(s["standstill"])) == [3]


def test_a_long_stance_alone_makes_both_its_strides_standstill_ones():
    # mutant: strides-standstill-mean, strides-standstill-k0-side. Stances of 0.5 s; the 4th is
    # 1.0 s (2 x the median 0.5 s > 1.5 x), its strides are ~1.45 s (< 2 x 1.2 s); the mean stance
    # (0.57 s) x 1.5 = 0.86 s would still flag it, so a 0.8 s stance tells the mean from the median
    starts = [0, 12, 24, 36, 53, 65, 77]
    lengths = [5, 5, 5, 10, 5, 5, 5]
    s = _strides([(a, a + w) for a, w in zip(starts, lengths)], 85)
    assert list(np.flatnonzero(s["standstill"])) == [2, 3]
    lengths = [5, 5, 5, 8, 5, 5, 5, 5, 5, 5, 14, 14, 14]  # 0.8 s: > 1.5 x median 0.5 = 0.75 s
    starts = list(np.cumsum([0] + [w + 7 for w in lengths[:-1]]))
    s = _strides([(a, a + w) for a, w in zip(starts, lengths)], starts[-1] + 14)
    # median stance 0.5 s: stance 3 (0.8 s) and the three 1.4 s ones are long; the mean (0.73 s)
    # x 1.5 = 1.1 s would leave stance 3 out
    flagged = set(np.flatnonzero(s["standstill"]))
    assert {2, 3} <= flagged and {9, 10, 11} <= flagged and not {0, 1, 4, 5, 6, 7} & flagged


def test_a_stride_from_a_two_sample_stance_after_a_long_one_is_not_a_standstill_one():
    # mutant: strides-standstill-k0-side. Stances of 5 samples every 12; the 4th lasts 10 (long),
    # the 5th only 2, so its mid-stance is its first sample. The stride from the 5th stance to
    # the 6th touches no long stance: only the two strides touching the 4th are standstill ones
    starts = [0, 12, 24, 36, 53, 62, 74, 86]
    lengths = [5, 5, 5, 10, 2, 5, 5, 5]
    s = _strides([(a, a + w) for a, w in zip(starts, lengths)], 95)
    assert s["start_index"][4] == 53
    assert list(np.flatnonzero(s["standstill"])) == [2, 3]


def _trajectory(t, pos, q) -> FootTrajectory:
    n = len(t)
    return FootTrajectory(
        t=t,
        position=pos,
        velocity=np.zeros((n, 3)),
        quaternion=q,
        position_std=np.zeros((n, 3)),
        steps=np.empty((0, 2)),
    )


def _truth_trajectory(truth) -> FootTrajectory:
    return FootTrajectory(
        t=truth.t,
        position=truth.position,
        velocity=truth.velocity,
        quaternion=truth.quaternion,
        position_std=np.zeros_like(truth.position),
        steps=np.empty((0, 2)),
    )


def test_hand_computed_walk():
    # 10 Hz; stances [0, 10), [17, 27), [34, 44): mid-stances 4, 21, 38 (middle sample (a + b - 1) // 2)
    t = np.arange(44) * 0.1
    mask = np.zeros(44, bool)
    mask[0:10] = mask[17:27] = mask[34:44] = True
    feet = [(0.0, 0.0, 0.0, 0.0), (1.2, 0.0, 0.1, 30.0), (1.2, 1.0, 0.1, -170.0)]  # x, y, z, yaw deg
    pos, yaw = np.zeros((44, 3)), np.zeros(44)
    for (a, b), (x, y, z, yw) in zip(((0, 10), (17, 27), (34, 44)), feet):
        pos[a:b], yaw[a:b] = (x, y, z), np.radians(yw)
    for a, b, (p0, p1) in ((10, 17, (feet[0], feet[1])), (27, 34, (feet[1], feet[2]))):
        frac = np.linspace(0, 1, b - a + 2)[1:-1]
        pos[a:b] = np.outer(1 - frac, p0[:3]) + np.outer(frac, p1[:3])
        yaw[a:b] = np.radians(p0[3])
    pos[13, 2] += 0.15  # the first swing's highest point: z = 0.05 + 0.15 (halfway up, plus the bump)
    q = quat.from_euler(np.full(44, 0.05), np.full(44, -0.1), yaw)  # tilted sensor: the turn is still the yaw change
    s = stride_parameters(_trajectory(t, pos, q), mask, foot="right")
    assert list(s.dtype.names) == list(STRIDE_COLUMNS) and len(s) == 2
    assert list(s["start_index"]) == [4, 21] and list(s["end_index"]) == [21, 38]
    np.testing.assert_allclose(s["start_s"], [0.4, 2.1])
    np.testing.assert_allclose(s["duration_s"], [1.7, 1.7])
    np.testing.assert_allclose(s["length_m"], [1.2, 1.0])
    np.testing.assert_allclose(s["cadence_spm"], 120 / 1.7)
    np.testing.assert_allclose(s["swing_s"], [0.7, 0.7])  # samples 10..16, 27..33
    np.testing.assert_allclose(s["stance_s"], [1.0, 1.0])
    np.testing.assert_allclose(s["elevation_m"], [0.1, 0.0], atol=1e-12)
    # above the chord from (0.4 s, 0 m) to (2.1 s, 0.1 m), which is 0.1 * 0.9 / 1.7 m high at 1.3 s
    np.testing.assert_allclose(s["clearance_m"][0], 0.2 - 0.1 * 0.9 / 1.7, atol=1e-12)
    np.testing.assert_allclose(s["turn_rad"], np.radians([30.0, 160.0]))  # -170 - 30 = -200 deg wraps to +160
    assert set(s["foot"]) == {"right"}


def test_turn_is_wrapped_to_minus_pi_exclusive():
    from footnav.nav.strides import _turn

    q0 = quat.from_yaw(np.zeros(3))
    np.testing.assert_allclose(
        _turn(q0, quat.from_yaw(np.array([np.pi, -np.pi, 3 * np.pi / 2]))), [np.pi, np.pi, -np.pi / 2]
    )


def test_fewer_than_two_stances_give_no_strides_and_bad_input_is_named():
    t = np.arange(5) * 0.1
    traj = _trajectory(t, np.zeros((5, 3)), quat.from_yaw(np.zeros(5)))
    assert len(stride_parameters(traj, np.ones(5, bool))) == 0
    with pytest.raises(InvalidInputError, match="stance"):
        stride_parameters(traj, np.ones(4, bool))
    with pytest.raises(InvalidInputError, match="mid_stance"):
        stride_parameters(traj, np.ones(5, bool), mid_stance=[3, 1])
    assert list(mid_stances(np.array([1, 1, 0, 0, 1, 1, 1], bool))) == [0, 5]


@pytest.fixture(scope="module")
def straight():
    rec = footnav.simulate("straight", seed=3, distance_m=20.0)
    return rec, footnav.make_pipeline().run(rec.left, rec.right)


def test_simulator_truth_strides_have_the_walks_stride_length_and_duration(straight):
    rec, _ = straight
    for truth in (rec.truth_left, rec.truth_right):
        s = stride_parameters(_truth_trajectory(truth), truth.stance)
        full = s[1:-1]  # the first and last strides start or end with a half step
        np.testing.assert_allclose(full["length_m"], truth.meta["stride_length_m_actual"], atol=1e-3)
        period = np.diff(truth.meta["event_times_s"]["heel_strike"])
        np.testing.assert_allclose(full["duration_s"], np.median(period), atol=0.011)
        np.testing.assert_allclose(full["turn_rad"], 0.0, atol=1e-6)
        np.testing.assert_allclose(full["elevation_m"], 0.0, atol=1e-6)


def test_estimated_strides_match_the_truth(straight):
    rec, res = straight
    table = res.strides()
    assert list(table.columns) == list(STRIDE_COLUMNS)
    for foot, truth in (("left", rec.truth_left), ("right", rec.truth_right)):
        est = table[table["foot"] == foot]
        ref = stride_parameters(_truth_trajectory(truth), truth.stance, foot=foot)
        assert len(est) == len(ref)
        np.testing.assert_allclose(est["length_m"], ref["length_m"], atol=0.02)
        np.testing.assert_allclose(est["duration_s"], ref["duration_s"], atol=0.03)
        np.testing.assert_allclose(est["swing_s"], ref["swing_s"], atol=0.1)


@pytest.mark.parametrize("direction, sign", [("ccw", 1.0), ("cw", -1.0)])
def test_turns_round_the_rectangle_sum_to_a_full_turn(direction, sign):
    rec = footnav.simulate("rectangle", seed=1, width_m=8.0, height_m=5.0, direction=direction)
    res = footnav.make_pipeline().run(rec.left, rec.right)
    for truth, traj, stance in (
        (rec.truth_left, res.left, res.stance_left),
        (rec.truth_right, res.right, res.stance_right),
    ):
        assert stride_parameters(_truth_trajectory(truth), truth.stance)["turn_rad"].sum() == pytest.approx(
            sign * 2 * np.pi, abs=0.05
        )
        assert stride_parameters(traj, stance)["turn_rad"].sum() == pytest.approx(sign * 2 * np.pi, abs=0.15)


def test_strides_is_a_dataframe_and_to_dataframe_has_every_sample(straight):
    import pandas as pd

    _, res = straight
    frame = res.to_dataframe()
    assert (
        len(frame) == len(res.left.t) + len(res.right.t)
        and frame["stance"].sum() == res.stance_left.mask.sum() + res.stance_right.mask.sum()
    )
    np.testing.assert_array_equal(frame.loc[frame["foot"] == "right", "pos_x_m"], res.right.position[:, 0])
    table = res.strides()
    assert isinstance(table, pd.DataFrame) and tuple(table.columns) == STRIDE_COLUMNS
    assert table["first"].dtype == bool and table["standstill"].dtype == bool
    np.testing.assert_allclose(table["turn_deg"], np.degrees(table["turn_rad"]))


def test_first_last_and_standstill_strides_are_marked():
    # 10 Hz, stances of 0.5 s every 1.2 s, the third one 3 s long (a pause), and long rests at both ends
    stances = [(0, 30), (42, 47), (59, 64), (76, 106), (118, 123), (135, 140), (152, 157), (169, 199)]
    s = _strides(stances, 199)
    assert len(s) == len(stances) - 1
    assert list(np.flatnonzero(s["first"])) == [0] and list(np.flatnonzero(s["last"])) == [len(s) - 1]
    # the strides touching the 3 s rests at both ends and the pause in the middle (stance 3)
    assert list(np.flatnonzero(s["standstill"])) == [0, 2, 3, 6]


def test_write_results_writes_strides_csv(straight, tmp_path):
    from footnav.data.results import write_results

    _, res = straight
    out = write_results(res, tmp_path / "out")
    lines = (out / "strides.csv").read_text().splitlines()
    assert lines[0].startswith("foot,start_s,end_s,length_m,duration_s,")
    assert len(lines) == 1 + len(res.strides())
    assert lines[1].split(",")[0] == "left"
    import pandas as pd

    back = pd.read_csv(out / "strides.csv")
    assert tuple(back.columns) == STRIDE_COLUMNS and back["first"].dtype == bool and back["first"].iloc[0]
    steady = back[
        ~back["first"] & ~back["last"] & ~back["standstill"] & (back["turn_deg"].abs() < 20) & (back["kind"] == "level")
    ]
    assert 0 < len(steady) < len(back)


def mocap_stride_errors(rec, res, tolerance_s: float = 0.4):
    """footnav's strides matched to the mocap strides of the gaitmap example (gaitmap's ``min_vel``
    borders): per foot, (footnav length - heel marker displacement) of each matched stride, and
    the number of mocap strides."""
    out = {}
    table = res.strides()
    for foot, imu, truth in (("left", rec.left, rec.truth_left), ("right", rec.right, rec.truth_right)):
        borders = truth.meta["strides"]
        t0, t1 = imu.t[borders[:, 0]], imu.t[borders[:, 1]]
        heel = [np.stack([np.interp(tt, truth.t, truth.position[:, j]) for j in range(2)], axis=1) for tt in (t0, t1)]
        ref = np.linalg.norm(heel[1] - heel[0], axis=1)
        est = table[table["foot"] == foot]
        errors = []
        for a, b, length in zip(t0, t1, ref):
            k = int(np.argmin(np.abs(est["start_s"].to_numpy() - a) + np.abs(est["end_s"].to_numpy() - b)))
            if abs(est["start_s"].iloc[k] - a) < tolerance_s and abs(est["end_s"].iloc[k] - b) < tolerance_s:
                errors.append(est["length_m"].iloc[k] - length)
        out[foot] = (np.asarray(errors), len(ref))
    return out


def test_gaitmap_example_stride_length_against_motion_capture(shared_data):
    from footnav.data.datasets import load_dataset

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # clipping and stance checks are recorded in meta
        rec = load_dataset("gaitmap", shared_data)
        res = footnav.make_pipeline().run(rec.left, rec.right)
    errors = mocap_stride_errors(rec, res)
    for foot, (err, n_ref) in errors.items():
        assert len(err) >= n_ref - 2, foot  # all but the turn's strides are found
    pooled = np.concatenate([e for e, _ in errors.values()])
    # measured 2026-11-25: mean |error| 0.043 m (worst stride 0.109 m) against the mocap heel over
    # 56 strides; 5 cm is 3.6 % of a 1.4 m stride. A regression bound at 1.2x today's value, not
    # an independent figure: the gaitmap example publishes none for stride length
    assert np.mean(np.abs(pooled)) <= 0.05


@pytest.mark.filterwarnings("ignore::footnav.DataQualityWarning")
def test_stair_strides_are_marked_and_the_floor_index_follows_the_storey():
    segments = [(2.8, 0.0), ("stairs", 12, 0.17), (2.8, 180.0), ("stairs", 12, -0.17), (2.8, 0.0)]
    rec = footnav.simulate("path", seed=0, rate_hz=200.0, segments=segments)
    result = footnav.make_pipeline().run(rec.left, rec.right)
    table = result.strides()
    for foot in ("left", "right"):
        rows = table[table["foot"] == foot]
        kind = np.asarray(rows["kind"])
        stair = kind == "stair"
        # a foot on the simulator's stairs climbs two risers a stride (0.34 m; one at either end of
        # the flight), the rest is level
        assert np.all(np.abs(np.asarray(rows["elevation_m"])[stair]) > 0.15), rows
        assert np.all(np.abs(np.asarray(rows["elevation_m"])[~stair]) < 0.075)
        assert 10 <= stair.sum() <= 14 and set(kind) == {"level", "stair"}
        level = np.asarray(rows["level"])
        assert level[0] == 0 and level.max() == 1 and level[-1] == 0  # up a storey and down again
        assert np.all(level[np.asarray(rows["end_s"]) < 2.0] == 0)
    assert "kind" in STRIDE_COLUMNS and "level" in STRIDE_COLUMNS


def test_the_level_bound_of_the_trajectory_classifies_its_strides():
    t = np.arange(0.0, 4.0, 0.01)
    pos = np.zeros((len(t), 3))
    pos[:, 0] = t
    pos[:, 2] = np.where(t > 2.0, 0.05, 0.0)  # one 5 cm rise
    mask = np.zeros(len(t), bool)
    for a in (0, 100, 200, 300):
        mask[a : a + 50] = True
    traj = _trajectory(t, pos, np.tile([1.0, 0, 0, 0], (len(t), 1)))
    assert list(stride_parameters(traj, mask)["kind"]) == ["level", "level", "level"]
    strict = FootTrajectory(
        t=t,
        position=pos,
        velocity=traj.velocity,
        quaternion=traj.quaternion,
        position_std=traj.position_std,
        steps=traj.steps,
        meta={"vertical": {"level_rise_max_m": 0.04}},
    )
    assert list(stride_parameters(strict, mask)["kind"]) == ["level", "stair", "level"]


# mutant: strides-dt-prepend
# strides-dt-prepend: sample k's share of the time is t[k+1] - t[k]; with uneven sampling the swing
# of samples 2 and 3 lasts from t[2] to t[4] (the first stance sample after it)
def test_swing_time_with_uneven_sampling():
    from footnav.core.types import FootTrajectory
    from footnav.nav.strides import stride_parameters

    t = np.array([0.0, 0.1, 0.3, 0.6, 1.0, 1.5])
    n = len(t)
    traj = FootTrajectory(
        t=t,
        position=np.zeros((n, 3)),
        velocity=np.zeros((n, 3)),
        quaternion=np.tile([1.0, 0, 0, 0], (n, 1)),
        position_std=np.zeros((n, 3)),
        steps=np.empty((0, 2)),
    )
    mask = np.array([True, True, False, False, True, True])
    out = stride_parameters(traj, mask, mid_stance=[0, 5])
    assert out["swing_s"][0] == pytest.approx(0.7)
    assert out["stance_s"][0] == pytest.approx(0.8)
