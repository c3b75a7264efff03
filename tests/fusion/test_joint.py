"""footnav.fusion.joint.continue_rigidly: what a coupled fusion puts outside the common span,
against a hand-computed rigid motion (turn about z by the heading difference, then move)."""

from __future__ import annotations

import numpy as np

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
