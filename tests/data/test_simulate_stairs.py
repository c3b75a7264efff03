"""The simulator's stairs: footprints on treads, truth heights exact, signals consistent with the truth."""

from __future__ import annotations

import numpy as np
import pytest

from footnav.core.errors import InvalidParameterError
from footnav.core.types import GRAVITY_MPS2, stance_intervals
from footnav.data.simulate import simulate
from footnav.nav import quaternion as quat

G_N = np.array([0.0, 0.0, -GRAVITY_MPS2])
RISE_M, N_STAIRS, TREAD_M = 0.17, 12, 0.3
FLIGHT = [(1.4, 0.0), ("stairs", N_STAIRS, RISE_M), (1.4, 0.0)]


@pytest.mark.parametrize("rise", [RISE_M, -RISE_M])
def test_truth_height_changes_by_exactly_the_requested_height(rise):
    rec = simulate("path", noise=False, segments=[(1.4, 0.0), ("stairs", N_STAIRS, rise), (1.4, 0.0)])
    for truth in (rec.truth_left, rec.truth_right):  # both feet climb
        z = truth.position[:, 2]
        assert z[0] == 0.0
        assert z[-1] == pytest.approx(N_STAIRS * rise, abs=1e-12)
        # every stance stands on a tread: a whole number of risers up, within rounding
        heights = np.array([z[a] for a, _ in stance_intervals(truth.stance)])
        np.testing.assert_allclose(heights / rise, np.round(heights / rise), atol=1e-9)
        # step over step: a foot's successive stances are 0 or 2 risers apart (one: the first or
        # last swing of the flight, which starts or ends beside the other foot)
        risers = np.diff(np.round(heights / rise)).astype(int)
        assert set(risers) <= {0, 1, 2} and (risers == 2).sum() >= N_STAIRS // 2 - 1
    assert rec.meta["height_change_m"] == pytest.approx(N_STAIRS * rise, abs=1e-12)
    assert rec.meta["stairs"][0]["n_steps"] == N_STAIRS
    assert rec.truth_left.closed_loop is False


def test_each_footprint_fits_its_tread():
    # heel and toe of each stance on the flight lie within the tread its height belongs to
    rec = simulate("path", noise=False, segments=FLIGHT)
    geo = rec.truth_left.meta["foot_geometry_m"]
    start = rec.meta["stairs"][0]["start_m"]  # 1.4 m: the foot of the flight, footfall 0 of it
    for truth in (rec.truth_left, rec.truth_right):
        for a, _ in stance_intervals(truth.stance):
            x, z = truth.position[a, 0], truth.position[a, 2]
            i = round(z / RISE_M)
            if 0 < i <= N_STAIRS and x < start + (N_STAIRS + 0.5) * TREAD_M:  # not the top floor
                lo, hi = start + (i - 0.5) * TREAD_M, start + (i + 0.5) * TREAD_M
                assert lo < x + geo["heel"][0] and x + geo["toe"][0] < hi


def test_imu_signals_match_finite_differences_of_the_truth_on_stairs():
    # the climb is in the signals, not only in the truth: rate and specific force from the
    # truth's attitude and velocity by fourth-order central differences
    rate = 2000.0
    rec = simulate("path", rate_hz=rate, noise=False, segments=[("stairs", 4, RISE_M), ("stairs", 4, -RISE_M)])
    dt = 1.0 / rate
    top = []
    for imu, truth in ((rec.left, rec.truth_left), (rec.right, rec.truth_right)):
        q = truth.quaternion
        qdot = (q[2:] - q[:-2]) / (2 * dt)
        w_fd = 2.0 * quat.multiply(quat.conjugate(q[1:-1]), qdot)[:, 1:]
        np.testing.assert_allclose(w_fd, imu.gyr[1:-1], atol=1.5e-3)  # rad/s
        p, v = truth.position, truth.velocity
        v_fd = (8 * (p[3:-1] - p[1:-3]) - (p[4:] - p[:-4])) / (12 * dt)
        np.testing.assert_allclose(v_fd, v[2:-2], atol=2e-4)  # m/s
        phase = truth.meta["phases"]
        near = np.zeros(len(phase), dtype=bool)
        for i in np.flatnonzero(np.diff(phase) != 0):  # the jerk jumps at phase changes
            near[max(i - 2, 0) : i + 4] = True
        a_fd = (8 * (v[3:-1] - v[1:-3]) - (v[4:] - v[:-4])) / (12 * dt)
        a_imu = quat.rotate(q[2:-2], imu.acc[2:-2]) + G_N
        keep = ~near[2:-2]
        np.testing.assert_allclose(a_fd[keep], a_imu[keep], atol=2e-2)  # m/s^2
        # up and down the same number of stairs: back at the start height
        assert truth.position[-1, 2] == pytest.approx(0.0, abs=1e-12)
        top.append(truth.position[truth.stance, 2].max())
    # one foot stands on the top tread; the other steps over it (step over step)
    assert max(top) == pytest.approx(4 * RISE_M, abs=1e-12) and min(top) == pytest.approx(3 * RISE_M, abs=1e-12)


def test_a_path_without_stairs_has_no_stairs_meta():
    rec = simulate("path", noise=False, segments=[(3.0, 0.0)])
    assert "stairs" not in rec.meta and "height_change_m" not in rec.meta
    assert (rec.truth_left.position[rec.truth_left.stance, 2] == 0.0).all()


@pytest.mark.parametrize(
    "segment",
    [
        ("stairs", 0, 0.17),
        ("stairs", 3, 0.0),
        ("stairs", 3, 0.6),
        ("stairs", 3, 0.17, 0.2),
        ("stairs", 2.5, 0.17),
        ("stairs", True, 0.17),
        ("stairs", 3, float("nan")),
    ],
)
def test_bad_stairs_are_refused(segment):
    with pytest.raises(InvalidParameterError, match="segments"):
        simulate("path", segments=[(1.0, 0.0), segment])


def test_cli_segments_read_stairs(tmp_path):
    from footnav.cli import main
    from footnav.cli._parser import _segments

    assert _segments("1.4:0,stairs:12:0.17,stairs:3:-0.17:0.35,2:90") == [
        (1.4, 0.0),
        ("stairs", 12, 0.17),
        ("stairs", 3, -0.17, 0.35),
        (2.0, 90.0),
    ]
    out = tmp_path / "sim"
    assert main(["simulate", "path", "--segments", "1.4:0,stairs:4:0.17,1:0", "--out", str(out)]) == 0
    last = (out / "left_truth.csv").read_text().strip().splitlines()[-1].split(",")
    assert float(last[3]) == pytest.approx(4 * 0.17, abs=1e-12)  # t, x, y, z, ...: the truth's z


# -- per-swing variability (swing_scale) ----------------------------------------------------------


def test_swing_scale_of_one_is_the_default_bit_for_bit():
    a = simulate("straight", distance_m=6.0, seed=2)
    b = simulate("straight", distance_m=6.0, seed=2, swing_scale=(1.0,))
    for x, y in ((a.left, b.left), (a.right, b.right)):
        assert np.array_equal(x.acc, y.acc) and np.array_equal(x.gyr, y.gyr)
    assert np.array_equal(a.truth_left.position, b.truth_left.position)


def test_swing_scale_scales_each_swing_in_turn():
    # each foot's swings alternate the default's pitch profile and half of it; footprints,
    # timing and stances stay those of the default walk
    plain = simulate("straight", distance_m=8.4, noise=False)
    rec = simulate("straight", distance_m=8.4, noise=False, swing_scale=(1.0, 0.5))
    for truth, ref in ((rec.truth_left, plain.truth_left), (rec.truth_right, plain.truth_right)):
        assert np.array_equal(truth.stance, ref.stance)
        np.testing.assert_array_equal(truth.position[truth.stance], ref.position[ref.stance])

        def pitch(q):  # toe-down pitch: the foot's x axis is (cos th, 0, -sin th) on a straight walk
            return np.arcsin(np.clip(-quat.as_matrix(q)[:, 2, 0], -1.0, 1.0))

        p, p_ref = pitch(truth.quaternion), pitch(ref.quaternion)
        swings = list(zip(truth.events["heel_off"], truth.events["foot_flat"]))
        assert len(swings) >= 4
        for i, (a, b) in enumerate(swings):
            factor = 1.0 if i % 2 == 0 else 0.5
            np.testing.assert_allclose(p[a : b + 1], factor * p_ref[a : b + 1], atol=1e-9)


@pytest.mark.parametrize("value", [(), (0.0,), (1.0, 4.0), "1", (float("nan"),), 1e308])
def test_bad_swing_scale_is_refused(value):
    with pytest.raises(InvalidParameterError, match="swing_scale"):
        simulate("straight", distance_m=3.0, swing_scale=value)
