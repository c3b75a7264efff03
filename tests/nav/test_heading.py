"""The nav frame's heading: the in-place turn about z against the matrix form, and the first step."""

import numpy as np
import pytest

from footnav.nav import quaternion as quat
from footnav.nav.heading import heading_of_first_step, rotate_about_z, turn_to_first_step


def _solution(rng, n=50):
    pos, vel = rng.normal(size=(n, 3)), rng.normal(size=(n, 3))
    q = quat.normalize(rng.normal(size=(n, 4)))
    a = rng.normal(size=(n, 3, 3))
    cov3 = a @ a.transpose(0, 2, 1)  # SPD position covariances
    pos_cov = np.column_stack([cov3[:, 0, 0], cov3[:, 0, 1], cov3[:, 1, 1], cov3[:, 2, 2]])
    return pos, vel, q, pos_cov, cov3


@pytest.mark.parametrize("angle", [0.0, 0.3, -2.5, np.pi])
def test_turn_in_place_equals_the_matrix_form(angle):
    rng = np.random.default_rng(1)
    pos, vel, q, pos_cov, cov3 = _solution(rng)
    r = quat.as_matrix(quat.from_yaw(angle))
    ref_pos, ref_vel = pos @ r.T, vel @ r.T
    ref_q = quat.multiply(quat.from_yaw(angle), q)
    ref_cov = r @ cov3 @ r.T
    std = rotate_about_z(angle, pos, vel, q, pos_cov)
    np.testing.assert_allclose(pos, ref_pos, atol=1e-12)
    np.testing.assert_allclose(vel, ref_vel, atol=1e-12)
    np.testing.assert_allclose(q, ref_q, atol=1e-12)
    np.testing.assert_allclose(pos_cov[:, :3], ref_cov[:, [0, 0, 1], [0, 1, 1]], atol=1e-12)
    np.testing.assert_allclose(std, np.sqrt(ref_cov[:, [0, 1, 2], [0, 1, 2]]), atol=1e-12)


def test_turn_refuses_arrays_it_cannot_change_in_place():
    pos, vel, q, pos_cov, _ = _solution(np.random.default_rng(2))
    pos.setflags(write=False)
    with pytest.raises(ValueError, match="in place"):
        rotate_about_z(0.1, pos, vel, q, pos_cov)


def test_first_step_heading_and_turn():
    # a foot standing at the origin, then at (1, 1): the first step points 45 deg left of x
    pos = np.zeros((40, 3))
    pos[20:] = [1.0, 1.0, 0.0]
    steps = np.array([[0, 10], [25, 35]])
    assert heading_of_first_step(pos, steps) == pytest.approx(np.pi / 4)
    meta = {}
    vel, q, pos_cov = np.zeros((40, 3)), np.tile([1.0, 0, 0, 0], (40, 1)), np.tile([1.0, 0, 1.0, 1.0], (40, 1))
    pos_t, _, q_t, std = turn_to_first_step(pos, vel, q, pos_cov, steps, meta)
    assert pos_t is pos  # in place
    np.testing.assert_allclose(pos[-1], [np.sqrt(2), 0.0, 0.0], atol=1e-12)
    assert meta["heading_rotation_rad"] == pytest.approx(-np.pi / 4)
    assert quat.yaw(q_t[-1]) == pytest.approx(-np.pi / 4)
    np.testing.assert_allclose(std, 1.0)  # an isotropic horizontal covariance stays so


def test_no_step_leaves_the_solution_as_it_is():
    pos = np.zeros((20, 3))
    meta = {}
    pos_cov = np.tile([4.0, 0, 1.0, 9.0], (20, 1))
    _, _, _, std = turn_to_first_step(
        pos, np.zeros((20, 3)), np.tile([1.0, 0, 0, 0], (20, 1)), pos_cov, np.array([[0, 5], [10, 15]]), meta
    )
    assert "heading_rotation_rad" not in meta
    np.testing.assert_allclose(std, np.tile([2.0, 1.0, 3.0], (20, 1)))
