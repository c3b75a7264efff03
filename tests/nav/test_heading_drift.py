"""footnav.nav.heading_drift against a dense numpy propagation of its 5-state model, hand-computed
walks (a diagonal line, a U-turn and back, a lap) and a hand-computed standstill (the rate's
standard error from samples with noise, ddof 1)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from footnav.nav.heading_drift import heading_drift_cov, standstill_rate_std
from footnav.nav.initial_alignment import MIN_STILL_SAMPLES


def _dense(t, vel, quat, start, var_rate0, q2, var_scale):
    """P over [dp_x, dp_y, dpsi, beta, k], F = I but for F[0,2] = -v_y dt, F[1,2] = v_x dt,
    F[2,3] = dt and F[2,4] = the turn about the vertical (scipy's rotation vector of q1 q0*)."""
    rot = Rotation.from_quat(quat[:, [1, 2, 3, 0]])  # scipy: [x, y, z, w]
    turns = (rot[1:] * rot[:-1].inv()).as_rotvec()[:, 2]
    p = np.zeros((5, 5))
    p[3, 3], p[4, 4] = var_rate0, var_scale
    out = np.zeros((len(t), 3))
    for k in range(start + 1, len(t)):
        dt = t[k] - t[k - 1]
        f = np.eye(5)
        f[0, 2], f[1, 2], f[2, 3], f[2, 4] = -vel[k - 1, 1] * dt, vel[k - 1, 0] * dt, dt, turns[k - 1]
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
    # an attitude that turns about all three axes (a foot pitches through its swing), either sign of q
    euler = np.column_stack([0.3 * np.sin(np.arange(n) / 9), 0.8 * np.sin(np.arange(n) / 13), np.linspace(0, 3, n)])
    quat = Rotation.from_euler("xyz", euler).as_quat()[:, [3, 0, 1, 2]]
    quat[::3] *= -1.0
    got = heading_drift_cov(t, vel, 17, 3e-3, 4e-4, quat, 0.02)
    ref = _dense(t, vel, quat, 17, 3e-3**2, 4e-4**2, 0.02**2)
    np.testing.assert_allclose(got, ref, rtol=1e-10, atol=1e-18)
    assert np.all(got[:18] == 0.0) and abs(got[-1, 1]) > 0.1 * np.sqrt(got[-1, 0] * got[-1, 2])
    # no attitude given: the model without the scale state
    np.testing.assert_allclose(
        heading_drift_cov(t, vel, 17, 3e-3, 4e-4), _dense(t, vel, quat, 17, 3e-3**2, 4e-4**2, 0.0), rtol=1e-10
    )


def _legs(*legs, rate_hz=100.0):
    """A walk at 1 m/s of ``(turn, length)`` legs: a pivot of ``turn`` rad about the vertical over
    2 s at rest, then ``length`` m straight on: t, velocity, quaternion."""
    yaw, moving, heading = [np.zeros(1)], [np.zeros(1)], 0.0
    for turn, length in legs:
        n_turn, n_leg = int(2 * rate_hz), int(round(length * rate_hz))
        yaw += [np.linspace(heading, heading + turn, n_turn), np.full(n_leg, heading + turn)]
        moving += [np.zeros(n_turn), np.ones(n_leg)]
        heading += turn
    yaw, speed = np.concatenate(yaw), np.concatenate(moving)
    vel = np.column_stack([np.cos(yaw), np.sin(yaw), np.zeros(len(yaw))]) * speed[:, None]
    quat = np.column_stack([np.cos(yaw / 2), np.zeros(len(yaw)), np.zeros(len(yaw)), np.sin(yaw / 2)])
    return np.arange(len(yaw)) / rate_hz, vel, quat


def test_a_scale_error_turns_the_way_back_by_k_pi():
    # mutant: drift-scale-turn-missing. A U-turn read k too large turns the way back by k pi: after
    # L back along -x the foot is k pi L off the line (std s pi L with std s of k), and none along it
    # (rel 5e-3: the last sample's velocity is not integrated, 1 cm of the last leg)
    length, s = 20.0, 0.01
    t, vel, quat = _legs((0.0, length), (np.pi, length))
    cov = heading_drift_cov(t, vel, 0, 0.0, 0.0, quat, s)
    assert cov[-1, 2] == pytest.approx((s * np.pi * length) ** 2, rel=5e-3)
    assert cov[-1, 0] == pytest.approx(0.0, abs=1e-12) and cov[-1, 1] == pytest.approx(0.0, abs=1e-12)
    assert np.all(cov[: 201 + int(length * 100)] == 0.0)  # nothing before the U-turn
    # turned back the other way, the heading error is k (pi - pi) = 0: a third leg adds nothing
    t, vel, quat = _legs((0.0, length), (np.pi, length), (-np.pi, 3 * length))
    cov = heading_drift_cov(t, vel, 0, 0.0, 0.0, quat, s)
    assert cov[-1, 2] == pytest.approx((s * np.pi * length) ** 2, rel=5e-3)
    # the same turn twice doubles the heading error: 2 k pi on the third leg, back along +x, takes
    # 2 k pi L off the -k pi L of the second (a second turn not accumulated would end at 0)
    t, vel, quat = _legs((0.0, length), (np.pi, length), (np.pi, length))
    cov = heading_drift_cov(t, vel, 0, 0.0, 0.0, quat, s)
    assert cov[-1, 2] == pytest.approx((s * np.pi * length - 2 * s * np.pi * length) ** 2, rel=5e-3)


def test_laps_the_same_way_accumulate_the_scale_error():
    # one square lap of side a turning +90 deg four times: the heading error after the j-th turn is
    # k j pi/2, so the lap closes off by sum_j k (j pi/2) x (side j's direction) -- a hand sum
    a, s, rate = 10.0, 0.01, 50.0
    n = int(a * rate)
    yaw = np.repeat(np.arange(4) * np.pi / 2, n)
    t = np.arange(len(yaw)) / rate
    vel = np.column_stack([np.cos(yaw), np.sin(yaw), np.zeros(len(yaw))])
    quat = np.column_stack([np.cos(yaw / 2), np.zeros(len(yaw)), np.zeros(len(yaw)), np.sin(yaw / 2)])
    cov = heading_drift_cov(t, vel, 0, 0.0, 0.0, quat, s)
    # dp = k sum_j (j pi/2) J u_j a, J u_j = u_{j+1}: sides 1..3 give (pi/2)(-1,0)... hand-summed
    d = sum(j * np.pi / 2 * a * np.array([-np.sin(j * np.pi / 2), np.cos(j * np.pi / 2)]) for j in range(4))
    d = d * s
    # the turn happens within one sample, so the side's first sample still has the old heading error
    np.testing.assert_allclose(cov[-1], [d[0] ** 2, d[0] * d[1], d[1] ** 2], rtol=2e-2)


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
