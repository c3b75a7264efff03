"""The dense Kalman and RTS reference (tests/reference_kalman.py) against filterpy, an independent,
well-kept implementation, and footnav's Kalman kernel against the reference."""

import numpy as np
import pytest
import reference_kalman as kalman  # tests/reference_kalman.py

from footnav.nav.kalman import DENSE_BAD_INPUT, DENSE_NOT_PD, DENSE_OK, update3, update_dense

filterpy_kalman = pytest.importorskip("filterpy.kalman")


def _random_spd(rng, n):
    a = rng.normal(size=(n, n))
    return a @ a.T + n * np.eye(n)


@pytest.mark.parametrize("n, m", [(9, 3), (4, 2), (6, 1)])
def test_predict_update_match_filterpy(n, m):
    rng = np.random.default_rng(n * 10 + m)
    f, q, r = rng.normal(size=(n, n)) * 0.3 + np.eye(n), _random_spd(rng, n) * 0.01, _random_spd(rng, m) * 0.1
    h = rng.normal(size=(m, n))
    x0, p0, z = rng.normal(size=n), _random_spd(rng, n), rng.normal(size=m)

    ref = filterpy_kalman.KalmanFilter(dim_x=n, dim_z=m)
    ref.x, ref.P, ref.F, ref.Q, ref.H, ref.R = x0.copy(), p0.copy(), f, q, h, r
    ref.predict()
    ref.update(z)  # filterpy uses the Joseph form too

    p = p0.copy()
    x = f @ x0
    ws = kalman.workspace(n, m)
    kalman.predict(p, f, q, ws[0])
    np.testing.assert_allclose(p, ref.P_prior, rtol=1e-10, atol=1e-12)
    assert kalman.update(x, p, h, r, z - h @ x, *ws)
    np.testing.assert_allclose(x, ref.x, rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(p, ref.P, rtol=1e-10, atol=1e-12)
    np.testing.assert_array_equal(p, p.T)


def test_update_refuses_non_positive_definite_innovation():
    n, m = 3, 1
    x, p = np.zeros(n), np.zeros((n, n))
    h, r = np.array([[1.0, 0.0, 0.0]]), np.zeros((1, 1))
    assert not kalman.update(x, p, h, r, np.array([1.0]), *kalman.workspace(n, m))
    np.testing.assert_array_equal(x, 0.0)


def test_spd_inverse():
    rng = np.random.default_rng(1)
    s = _random_spd(rng, 5)
    out, low = np.empty((5, 5)), np.empty((5, 5))
    assert kalman.spd_inverse(s, out, low)
    np.testing.assert_allclose(out, np.linalg.inv(s), rtol=1e-10)


def test_rts_step_matches_filterpy_smoother():
    rng = np.random.default_rng(7)
    n, steps = 4, 40
    dt = 0.1
    f = np.array([[1, dt, 0, 0], [0, 1, 0, 0], [0, 0, 1, dt], [0, 0, 0, 1]], dtype=float)
    q = np.diag([1e-4, 1e-2, 1e-4, 1e-2])
    h = np.array([[1.0, 0, 0, 0], [0, 0, 1.0, 0]])
    r = np.eye(2) * 0.25
    zs = np.cumsum(rng.normal(size=(steps, 2)), axis=0)

    kf = filterpy_kalman.KalmanFilter(dim_x=n, dim_z=2)
    kf.F, kf.Q, kf.H, kf.R, kf.P = f, q, h, r, np.eye(n)
    xs, ps, xp, pp = [], [], [], []
    for z in zs:
        kf.predict()
        xp.append(kf.x.copy())
        pp.append(kf.P.copy())
        kf.update(z)
        xs.append(kf.x.copy())
        ps.append(kf.P.copy())
    xs, ps = np.array(xs), np.array(ps)
    x_ref, p_ref, _, _ = kf.rts_smoother(xs, ps, Fs=[f] * steps, Qs=[q] * steps)

    x_s, p_s = xs.copy(), ps.copy()
    for k in range(steps - 2, -1, -1):
        kalman.rts_step(xs[k], ps[k], xp[k + 1], pp[k + 1], f, x_s[k + 1], p_s[k + 1], x_s[k], p_s[k])
    np.testing.assert_allclose(x_s, x_ref, rtol=1e-9, atol=1e-10)
    np.testing.assert_allclose(p_s, p_ref, rtol=1e-9, atol=1e-10)


@pytest.mark.parametrize("start", [0, 3, 6])
def test_footnav_selection_update_equals_the_dense_update(start):
    """footnav's one Kalman kernel (a 3-state selection, R = r I) against the dense reference."""
    rng = np.random.default_rng(start)
    n, r = 9, 0.1
    p0 = _random_spd(rng, n)
    p0 = 0.5 * (p0 + p0.T)  # exactly symmetric, as every footnav covariance
    h = np.zeros((3, n))
    h[:, start : start + 3] = np.eye(3)
    y = rng.normal(size=3)
    x1, p1 = np.zeros(n), p0.copy()
    assert kalman.update(x1, p1, h, r * np.eye(3), y, *kalman.workspace(n, 3))
    p2, dx, gain, sy, hp = p0.copy(), np.zeros(n), np.zeros((n, 3)), np.zeros(3), np.zeros((3, n))
    assert update3(p2, dx, start, *y, r, np.inf, gain, sy, hp)
    np.testing.assert_allclose(dx, x1, rtol=1e-12, atol=1e-14)
    np.testing.assert_allclose(p2, p1, rtol=1e-10, atol=1e-12)
    np.testing.assert_array_equal(p2, p2.T)
    # a gate below y' S^-1 y refuses the measurement and leaves P as it was
    p3 = p0.copy()
    assert not update3(p3, dx, start, *y, r, 0.5 * float(y @ sy), gain, sy, hp)
    np.testing.assert_array_equal(p3, p0)


def _dense(p, h, y, r):
    m, n = h.shape
    scratch = (np.zeros((m, m)), np.zeros((n, m)), np.zeros((n, m)), np.zeros(m), np.zeros(n), np.zeros((n, n)))
    status, nis = update_dense(p, h, y, r, *scratch)
    return status, nis, *scratch[2:]


@pytest.mark.parametrize("n, m", [(18, 2), (18, 3), (30, 6), (9, 1)])
def test_dense_update_equals_the_reference(n, m):
    """The caller's update (any H, e.g. the step-vector's rotated [I -I]) against the dense
    reference (Joseph form, checked against filterpy above)."""
    rng = np.random.default_rng(n + m)
    p0 = _random_spd(rng, n)
    p0 = 0.5 * (p0 + p0.T)
    h, y, r = rng.normal(size=(m, n)), rng.normal(size=m), rng.uniform(0.05, 0.5, size=m)
    x1, p1 = np.zeros(n), p0.copy()
    assert kalman.update(x1, p1, h, np.diag(r), y, *kalman.workspace(n, m))
    p_in = p0.copy()
    status, nis, gain, sy, dx, p2 = _dense(p_in, h, y, r)
    assert status == DENSE_OK
    np.testing.assert_array_equal(p_in, p0)  # the input is left as it was
    np.testing.assert_allclose(dx, x1, rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(p2, p1, rtol=1e-9, atol=1e-11)
    np.testing.assert_array_equal(p2, p2.T)
    s = h @ p0 @ h.T + np.diag(r)
    np.testing.assert_allclose(sy, np.linalg.solve(s, y), rtol=1e-10)
    np.testing.assert_allclose(gain, p0 @ h.T @ np.linalg.inv(s), rtol=1e-9, atol=1e-12)
    assert nis == pytest.approx(float(y @ np.linalg.solve(s, y)), rel=1e-12)


def test_dense_update_names_bad_input_and_a_singular_innovation():
    p, h, y, r = np.eye(4), np.zeros((2, 4)), np.ones(2), np.ones(2)
    h[0, 0] = h[1, 1] = 1.0
    assert _dense(p, h, y, r)[0] == DENSE_OK
    for bad in ((h, np.array([1.0, np.nan]), r), (h, y, np.array([1.0, 0.0])), (np.where(h > 0, np.inf, 0.0), y, r)):
        assert _dense(p, *bad)[0] == DENSE_BAD_INPUT
    # a covariance that is no longer positive semi-definite there (P00 = -2): S = -2 + 1 < 0
    assert _dense(np.diag([-2.0, 1.0, 1.0, 1.0]), h, y, r)[0] == DENSE_NOT_PD
