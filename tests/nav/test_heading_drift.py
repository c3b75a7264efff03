"""footnav.nav.heading_drift against a dense numpy propagation of its 4-state model and a
hand-computed standstill (the rate's standard error from samples with noise, ddof 1)."""

from __future__ import annotations

import numpy as np
import pytest

from footnav.nav.heading_drift import heading_drift_cov, standstill_rate_std
from footnav.nav.initial_alignment import MIN_STILL_SAMPLES


def _dense(t, vel, start, var_rate0, q2):
    """P over [dp_x, dp_y, dpsi, beta] with F = [[1 0 ax 0] [0 1 ay 0] [0 0 1 dt] [0 0 0 1]]."""
    p = np.zeros((4, 4))
    p[3, 3] = var_rate0
    out = np.zeros((len(t), 3))
    for k in range(start + 1, len(t)):
        dt = t[k] - t[k - 1]
        f = np.eye(4)
        f[0, 2], f[1, 2], f[2, 3] = -vel[k - 1, 1] * dt, vel[k - 1, 0] * dt, dt
        p = f @ p @ f.T
        p[3, 3] += q2 * dt
        out[k] = p[0, 0], p[0, 1], p[1, 1]
    return out


def test_the_propagation_is_the_dense_models():
    # mutant: drift-xy-cross-swapped, drift-psi-bias-term, drift-start-offset
    rng = np.random.default_rng(7)
    n = 400
    t = np.cumsum(rng.uniform(0.008, 0.012, n))
    vel = np.column_stack([np.cos(np.linspace(0, 3, n)), np.sin(np.linspace(0, 3, n)), np.zeros(n)]) * 1.3
    vel += rng.normal(0.0, 0.2, (n, 3))
    got = heading_drift_cov(t, vel, 17, 3e-3, 4e-4)
    ref = _dense(t, vel, 17, 3e-3**2, 4e-4**2)
    np.testing.assert_allclose(got, ref, rtol=1e-10, atol=1e-18)
    assert np.all(got[:18] == 0.0) and abs(got[-1, 1]) > 0.1 * np.sqrt(got[-1, 0] * got[-1, 2])


def test_standstill_rate_std_hand_computed_with_moving_samples_left_out():
    # mutant: drift-ddof0, drift-still-unfiltered. n still rows alternating two values per axis
    # (each axis's sample variance with ddof 1: n/(n-1) x (0.01)^2), then 30 moving rows
    n = max(MIN_STILL_SAMPLES, 100)
    n += n % 2
    a, b = np.array([0.01, 0.02, -0.01]), np.array([-0.01, 0.0, 0.01])
    still = np.where((np.arange(n) % 2 == 0)[:, None], a, b)
    gyr = np.vstack([still, np.tile([1.0, 0.5, 0.0], (30, 1))])
    got = standstill_rate_std(gyr, 0, len(gyr), 0.1)
    assert got == pytest.approx(0.01 / np.sqrt(n - 1), rel=1e-12)
    # too few still samples: the whole range is used (as align_at_rest does)
    few = np.vstack([still[:4], np.tile([1.0, 0.5, 0.0], (4, 1))])
    assert standstill_rate_std(few, 0, 8, 0.1) == pytest.approx(np.sqrt(np.mean(np.var(few, axis=0, ddof=1)) / 8))


# mutant: drift-lever-sign
# drift-lever-sign: a yaw-rate error b rad/s turns the walked path: dp = dpsi J v dt with
# J v = [-v_y, v_x]. Walking at 1 m/s along the diagonal (1, 1)/sqrt(2), dpsi = b t, so at T the
# position error is b T^2 / 2 along (-1, 1)/sqrt(2): var_xx = var_yy = -cov_xy = (s T^2 / 2)^2 / 2
def test_heading_drift_covariance_of_a_diagonal_walk():
    from footnav.nav.heading_drift import heading_drift_cov

    t = np.arange(1001) / 100.0
    vel = np.tile([np.sqrt(0.5), np.sqrt(0.5), 0.0], (len(t), 1))
    std = 0.01
    cov = heading_drift_cov(t, vel, 0, std, 0.0)
    expected = (std * 10.0**2 / 2) ** 2 / 2  # 0.125 m^2
    np.testing.assert_allclose(cov[-1], [expected, -expected, expected], rtol=0.01)
