"""Property tests (hypothesis) of the math every component relies on."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from footnav.analysis import metrics
from footnav.nav import quaternion as quat
from footnav.nav.kalman import update3 as _update3

finite = st.floats(-10.0, 10.0, allow_nan=False, allow_infinity=False)
unit_q = (
    arrays(np.float64, 4, elements=finite)
    .filter(lambda q: np.linalg.norm(q) > 1e-3)
    .map(lambda q: q / np.linalg.norm(q))
)


@given(unit_q, unit_q, arrays(np.float64, 3, elements=finite))
def test_composition_and_rotation_round_trip(p, q, v):
    pq = quat.multiply(p, q)
    assert abs(np.linalg.norm(pq) - 1.0) < 1e-12
    np.testing.assert_allclose(quat.rotate(pq, v), quat.rotate(p, quat.rotate(q, v)), atol=1e-9)
    back = quat.rotate(quat.conjugate(q), quat.rotate(q, v))
    np.testing.assert_allclose(back, v, atol=1e-9)
    np.testing.assert_allclose(quat.as_matrix(pq), quat.as_matrix(p) @ quat.as_matrix(q), atol=1e-12)


@given(arrays(np.float64, 4, elements=finite).filter(lambda q: np.linalg.norm(q) > 1e-6))
def test_normalisation_gives_a_unit_quaternion_of_the_same_rotation(q):
    n = quat.normalize(q)
    assert abs(np.linalg.norm(n) - 1.0) < 1e-12
    np.testing.assert_allclose(quat.as_matrix(n) @ quat.as_matrix(n).T, np.eye(3), atol=1e-12)


@given(arrays(np.float64, 3, elements=st.floats(-3.0, 3.0)))
def test_rotation_vector_round_trip(r):
    q = quat.from_rotvec(r)
    back = quat.as_rotvec(q)
    # equal rotations: same matrix (the vector is defined up to 2 pi)
    np.testing.assert_allclose(quat.as_matrix(quat.from_rotvec(back)), quat.as_matrix(q), atol=1e-10)


def _spd(rng, n):
    a = rng.standard_normal((n, n))
    return a @ a.T + 1e-3 * np.eye(n)


def _update3_numpy(cov, o, y, r):
    """The same update written densely: K = P H' (H P H' + R)^-1, dx = K y, P - K H P."""
    h = np.zeros((3, len(cov)))
    h[:, o : o + 3] = np.eye(3)
    s = h @ cov @ h.T + r * np.eye(3)
    gain = cov @ h.T @ np.linalg.inv(s)
    return cov - gain @ h @ cov, gain @ y, gain, np.linalg.solve(s, y)


@settings(max_examples=60, deadline=None)
@given(st.integers(0, 2**31 - 1), st.sampled_from([9, 15, 18, 30]), st.floats(1e-6, 10.0))
def test_kalman_update_keeps_the_covariance_symmetric_positive_definite(seed, n, r):
    rng = np.random.default_rng(seed)
    cov = _spd(rng, n)
    o = int(rng.integers(0, n - 2))
    ok = _update3(
        cov, np.zeros(n), o, *rng.standard_normal(3), r, np.inf, np.zeros((n, 3)), np.zeros(3), np.zeros((3, n))
    )
    assert ok
    assert np.array_equal(cov, cov.T)
    assert np.linalg.eigvalsh(cov).min() > -1e-12 * np.abs(cov).max()


@settings(max_examples=60, deadline=None)
@given(st.integers(0, 2**31 - 1), st.sampled_from([9, 15, 18, 30]), st.floats(1e-6, 1.0))
def test_written_out_update_equals_the_dense_one(seed, n, r):
    rng = np.random.default_rng(seed)
    cov = _spd(rng, n)
    y = rng.standard_normal(3)
    o = int(rng.integers(0, n - 2))
    ref_cov, ref_dx, ref_gain, ref_sy = _update3_numpy(cov, o, y, r)
    dx, gain, sy = np.zeros(n), np.zeros((n, 3)), np.zeros(3)
    _update3(cov, dx, o, *y, r, np.inf, gain, sy, np.zeros((3, n)))
    scale = np.abs(ref_cov).max()
    np.testing.assert_allclose(cov, ref_cov, rtol=1e-9, atol=1e-9 * scale)
    np.testing.assert_allclose(dx, ref_dx, rtol=1e-9, atol=1e-9 * np.abs(ref_dx).max())
    np.testing.assert_allclose(gain, ref_gain, rtol=1e-9, atol=1e-9 * np.abs(ref_gain).max())
    np.testing.assert_allclose(sy, ref_sy, rtol=1e-9, atol=1e-9 * np.abs(ref_sy).max())


def test_update_refuses_a_singular_innovation_covariance():
    cov = np.zeros((9, 9))
    before = cov.copy()
    assert not _update3(
        cov, np.zeros(9), 3, 1.0, 0.0, 0.0, 0.0, np.inf, np.zeros((9, 3)), np.zeros(3), np.zeros((3, 9))
    )
    assert np.array_equal(cov, before)


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 2**31 - 1), st.floats(-np.pi, np.pi), arrays(np.float64, 2, elements=st.floats(-100, 100)))
def test_metrics_are_invariant_to_a_rigid_motion_of_the_estimate(seed, angle, shift):
    rng = np.random.default_rng(seed)
    ref = np.cumsum(rng.standard_normal((60, 3)), axis=0)
    est = ref + 0.1 * rng.standard_normal((60, 3))
    c, s = np.cos(angle), np.sin(angle)
    rot = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])
    moved = est @ rot.T + np.r_[shift, 0.0]
    # ATE aligns rigidly first: a heading and an offset of the whole estimate do not count
    assert abs(metrics.ate_rmse(moved, ref, dims=2) - metrics.ate_rmse(est, ref, dims=2)) < 1e-7
    # distances between the feet and path lengths do not depend on the frame
    other = est[::-1]
    assert (
        abs(metrics.final_separation(moved, other @ rot.T + np.r_[shift, 0.0]) - metrics.final_separation(est, other))
        < 1e-9
    )
    assert abs(metrics.travelled_distance(moved, dims=2) - metrics.travelled_distance(est, dims=2)) < 1e-7
