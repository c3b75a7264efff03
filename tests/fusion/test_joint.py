"""footnav.fusion.joint.continue_rigidly: what a coupled fusion puts outside the common span,
against a hand-computed rigid motion (turn about z by the heading difference, then move)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import footnav
from footnav.core.types import StanceResult
from footnav.fusion.joint import continue_rigidly
from footnav.nav import quaternion as quat


def test_outside_the_span_position_velocity_and_attitude_turn_together():
    # mutant: joint-continue-velocity-unturned, joint-continue-velocity-transposed
    # alone: heading 0, walking along +x at 1.2 m/s; fused anchor: heading +90 deg at (5, 1, 0.2)
    n = 5
    t = np.arange(n) * 0.1
    pos = np.column_stack([1.2 * t, np.zeros(n), np.full(n, 0.05)])
    vel = np.tile([1.2, 0.0, 0.3], (n, 1))
    q = np.tile(quat.from_yaw(np.array(0.0)), (n, 1))
    anchor_alone = (pos[-1], q[-1])
    anchor_fused = (np.array([5.0, 1.0, 0.2]), quat.from_yaw(np.array(np.pi / 2)))
    p, v, qq = continue_rigidly((pos, vel, q), anchor_alone, anchor_fused)
    # by hand: turn +90 deg maps (x, y) -> (-y, x); the anchor sample lands on (5, 1, 0.2)
    expected_p = np.column_stack([5.0 - 0.0 * t, 1.0 + 1.2 * (t - t[-1]), np.full(n, 0.2)])
    np.testing.assert_allclose(p, expected_p, atol=1e-12)
    np.testing.assert_allclose(v, np.tile([0.0, 1.2, 0.3], (n, 1)), atol=1e-12)
    np.testing.assert_allclose(quat.yaw(qq), np.pi / 2, atol=1e-12)
    # the velocity is the derivative of the position it comes with
    np.testing.assert_allclose(np.diff(p[:, :2], axis=0) / 0.1, v[1:, :2], atol=1e-9)


def test_a_clockwise_turn_too():
    pos = np.array([[0.0, 0.0, 0.0], [1.0, 1.0, 0.0]])
    vel = np.array([[1.0, 1.0, 0.0], [1.0, 1.0, 0.0]])
    q = np.tile(quat.from_yaw(np.array(0.3)), (2, 1))
    p, v, _ = continue_rigidly((pos, vel, q), (pos[0], q[0]), (np.zeros(3), quat.from_yaw(np.array(0.3 - np.pi / 4))))
    r = np.sqrt(2.0)
    np.testing.assert_allclose(p[1], [r, 0.0, 0.0], atol=1e-12)
    np.testing.assert_allclose(v[0], [r, 0.0, 0.0], atol=1e-12)


# mutant: joint-alone-std
# joint-alone-std: past the span both feet cover, a foot continues alone from the fused estimate:
# its horizontal position std starts at the fused std and grows from there
def test_position_std_continues_from_the_fused_span():
    rec = footnav.simulate("straight", seed=3, distance_m=12.0)
    right = rec.right.slice(0, rec.right.n_samples - 300)  # the right foot's recording stops 3 s early
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = footnav.make_pipeline("glrt", "ekf", "range").run(rec.left, right)
    first, stop = res.left.meta["span"]["fused_samples"]
    assert stop < rec.left.n_samples
    std = res.left.position_std
    assert np.all(std[stop:, :2] >= std[stop - 1, :2] - 1e-9)


# -- the alone part's turn (joint-alone-rotation-transposed) ------------------------------------
#
# A foot's samples outside the common span, continued from the fused estimate (issue 17).
#
# ``footnav.fusion.joint`` fills a foot's samples outside the feet's common span with that foot
# estimated alone, turned about z by the heading difference ``turn`` between the fused and the
# alone estimate at the span's edge. On an ordinary walk both estimates put the first step along
# +x, so ``turn`` is a few mrad and a rotation by -turn instead of +turn moves the alone part by
# millimetres. Here the estimator keeps the sensor's own heading (``heading="sensor"``) and the
# sensors are mounted yawed 60 deg on the shoes, while the fused run turns each foot's first step
# to +x: ``turn`` is about 60 deg, and the wrong rotation turns the alone part 120 deg away from
# the walking direction. The reference is the simulator's truth.


def _fit_2d(a: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Rotation r and translation t minimising sum |r a_i + t - b_i|^2 (2-D Kabsch, no scale)."""
    ma, mb = a.mean(axis=0), b.mean(axis=0)
    u, _, vt = np.linalg.svd((a - ma).T @ (b - mb))
    d = np.sign(np.linalg.det(vt.T @ u.T))
    r = vt.T @ np.diag([1.0, d]) @ u.T
    return r, mb - r @ ma


@pytest.fixture(scope="module")
def yawed_walk():
    return footnav.simulate("straight", seed=3, distance_m=12.0, mounting_rpy_deg=(0.0, 0.0, 60.0))


# mutant: joint-alone-rotation-transposed
# joint-alone-rotation-transposed: the alone part must continue the fused foot in the walking
# direction. The whole trajectory is fitted to the truth on its fused samples only (a rigid 2-D
# motion: the fused nav frame has its own origin and x axis); the alone samples then lie on the
# truth within the fused part's own error. Measured (seed 3): right-end case, fused 3.3 mm,
# alone 3.8 mm; left-start case (the left foot starts mid-walk, so the fused frame is aligned at
# a short stance), fused 0.32 m, alone 0.32 m. The mutant puts the alone part 120 deg off: 1.2 m
# at the end of the right-end case's last 0.7 m step, about 6 m over the left-start case's 3.5 m.
@pytest.mark.parametrize("case", ["right-end", "left-start"])
def test_alone_part_continues_in_the_walking_direction(yawed_walk, case):
    rec = yawed_walk
    n = rec.left.n_samples
    st_left, st_right = rec.truth_left.stance, rec.truth_right.stance
    if case == "right-end":  # the right foot stops 3 s early: the left walks its last step alone
        k = 300
        left, right, sl, sr, foot = rec.left, rec.right.slice(0, n - k), st_left, st_right[: n - k], "left"
    else:  # the left foot starts 5 s late: the right walks its first steps alone
        k = 500
        left, right, sl, sr, foot = rec.left.slice(k, None), rec.right, st_left[k:], st_right, "right"
    pipe = footnav.make_pipeline("threshold", "ekf", "range", estimator_params={"heading": "sensor"})
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the span warning (tested in test_spans.py)
        res = pipe.fusion.fuse(pipe.estimator, left, StanceResult(sl), right, StanceResult(sr))
    traj = getattr(res, foot)
    truth = getattr(rec, f"truth_{foot}").position[:, :2]
    span = traj.meta["span"]
    a, b = span["fused_samples"]
    alone = np.concatenate([np.arange(lo, hi) for lo, hi in span["alone_samples"]])
    assert len(alone) == k
    # the case is what it should be: the sensor's heading is 60 deg off the first step
    r_sensor, _ = _fit_2d(
        pipe.estimator.estimate(getattr(rec, foot), StanceResult(getattr(rec, f"truth_{foot}").stance)).position[:, :2],
        truth,
    )
    assert abs(abs(np.degrees(np.arctan2(r_sensor[1, 0], r_sensor[0, 0]))) - 60.0) < 2.0
    r, t = _fit_2d(traj.position[a:b, :2], truth[a:b])
    err = np.linalg.norm(traj.position[:, :2] @ r.T + t - truth, axis=1)
    fused_err = err[a:b].max()
    assert fused_err < 0.5
    assert err[alone].max() < fused_err + 0.05, (err[alone].max(), fused_err)
