"""Quaternion utilities against scipy's Rotation (scalar-last there, scalar-first here)."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from footnav.nav import quaternion as quat


def _wxyz(r: Rotation) -> np.ndarray:
    return quat.normalize(np.roll(r.as_quat(), 1, axis=-1))


@pytest.fixture
def rotations():
    return Rotation.random(50, random_state=np.random.default_rng(3))


def test_matrix_matches_scipy(rotations):
    np.testing.assert_allclose(quat.as_matrix(_wxyz(rotations)), rotations.as_matrix(), atol=1e-12)


def test_from_matrix_round_trip(rotations):
    np.testing.assert_allclose(quat.from_matrix(rotations.as_matrix()), _wxyz(rotations), atol=1e-12)


def test_multiply_composes_like_scipy(rotations):
    a, b = rotations[:25], rotations[25:]
    np.testing.assert_allclose(
        quat.multiply(_wxyz(a), _wxyz(b)) * np.sign(quat.multiply(_wxyz(a), _wxyz(b))[:, :1]), _wxyz(a * b), atol=1e-12
    )


def test_rotate_and_rotvec(rotations):
    v = np.random.default_rng(0).normal(size=(50, 3))
    np.testing.assert_allclose(quat.rotate(_wxyz(rotations), v), rotations.apply(v), atol=1e-12)
    np.testing.assert_allclose(quat.from_rotvec(rotations.as_rotvec()), _wxyz(rotations), atol=1e-12)
    np.testing.assert_allclose(quat.as_rotvec(_wxyz(rotations)), rotations.as_rotvec(), atol=1e-9)


def test_euler_zyx_matches_scipy(rotations):
    ypr = rotations.as_euler("ZYX")  # intrinsic yaw, pitch, roll
    q = quat.from_euler(ypr[:, 2], ypr[:, 1], ypr[:, 0])
    np.testing.assert_allclose(quat.normalize(q), _wxyz(rotations), atol=1e-12)
    np.testing.assert_allclose(quat.as_euler(q), ypr[:, ::-1], atol=1e-9)
    np.testing.assert_allclose(quat.yaw(q), ypr[:, 0], atol=1e-9)


@settings(max_examples=50, deadline=None)
@given(st.lists(st.floats(-1e-6, 1e-6), min_size=3, max_size=3))
def test_tiny_rotvec_is_exact(r):
    np.testing.assert_allclose(quat.from_rotvec(r), Rotation.from_rotvec(r).as_quat()[[3, 0, 1, 2]], atol=1e-15)


def test_numba_kernels_match_numpy(rotations):
    p, q = _wxyz(rotations[:2])
    out = np.empty(4)
    quat.multiply_nb(p, q, out)
    np.testing.assert_allclose(out, quat.multiply(p, q), atol=1e-15)
    c = np.empty((3, 3))
    quat.as_matrix_nb(p, c)
    np.testing.assert_allclose(c, quat.as_matrix(p), atol=1e-15)
    quat.from_rotvec_nb(0.1, -0.2, 0.3, out)
    np.testing.assert_allclose(out, quat.from_rotvec([0.1, -0.2, 0.3]), atol=1e-15)


def test_scalar_yaw_and_wrap_against_hand_values():
    """quaternion.yaw_of (the per-step scalar yaw) and wrap_angle, against values worked by hand."""
    import math

    from footnav.nav.quaternion import wrap_angle, yaw, yaw_of

    half = math.radians(30.0)
    q = np.array([math.cos(half), 0.0, 0.0, math.sin(half)])  # 60 deg about z
    assert yaw_of(q) == pytest.approx(math.radians(60.0), abs=1e-15)
    assert yaw_of(q) == pytest.approx(float(yaw(q)), abs=1e-15)
    assert wrap_angle(3.5 * math.pi) == pytest.approx(-0.5 * math.pi)
    assert wrap_angle(math.pi) == pytest.approx(-math.pi)  # [-pi, pi)
    assert wrap_angle(-0.25) == -0.25


# mutant: quat-as-rotvec-limit
# quat-as-rotvec-limit: below |q_vec| = 1e-12 the rotation vector is 2 q_vec (angle -> 2 sin(angle / 2))
def test_as_rotvec_of_a_tiny_rotation_is_twice_the_vector_part():
    q = np.array([1.0, 1e-14, -2e-14, 3e-14])
    np.testing.assert_allclose(quat.as_rotvec(q), [2e-14, -4e-14, 6e-14], rtol=1e-12)


# mutant: quat-from-yaw-sign
# quat-from-yaw-sign: a turn of +90 deg about z is [cos 45, 0, 0, sin 45] and takes x to y
def test_from_yaw_is_a_positive_turn_about_z():
    h = np.sqrt(0.5)
    np.testing.assert_allclose(quat.from_yaw(np.pi / 2), [h, 0.0, 0.0, h], atol=1e-15)
    np.testing.assert_allclose(quat.rotate(quat.from_yaw(np.pi / 2), [1.0, 0.0, 0.0]), [0.0, 1.0, 0.0], atol=1e-15)


# mutant: quat-conjugate-index
# quat-conjugate-index: the conjugate negates all three vector components
def test_conjugate_negates_the_whole_vector_part():
    np.testing.assert_array_equal(quat.conjugate([0.5, 0.1, -0.2, 0.3]), [0.5, -0.1, 0.2, -0.3])
