"""The ``madgwick`` estimator against a plain numpy re-implementation written from the papers.

Reference written from Madgwick et al. (2011) (IMU filter: eq. 12 for q_dot, eq. 25-26 for the
objective f_g and its Jacobian J_g, the step q <- q + (q_dot - beta grad / |grad|) dt) and from
Li, Derrode et al. (2018), Sec. 3, eq. 3-6 (error state [dr, dv, da], Phi = [[I, dt I, 0],
[0, I, dt C], [0, 0, I]], H = [0 I 0], z = v^ in stance), plus footnav's documented choices
(noise densities times dt, trapezoidal strapdown, roll / pitch / gyro bias from the still samples
of the first stance, output compensated by the current error estimate, dr and dv reset after each
ZUPT). Everything is matrices and loops in numpy: no footnav function computes any expected value.

Written for tools/mutate.py's ``madgwick-innovation-sign`` (z - H x with the wrong sign) and
``madgwick-f-transposed`` (C' for C in Phi P): both change the result by far more than the
arithmetic differences of the two implementations (measured below).
"""

from __future__ import annotations

import numpy as np
import pytest

import footnav
from footnav.core.types import StanceResult
from footnav.estimators.madgwick import MadgwickEstimator

G = 9.80665  # m/s^2, footnav's nav-frame gravity, written out
STILL_GYR = 0.05  # rad/s, the estimator's still_gyr_max_radps (passed explicitly below)
PARAMS = {
    "beta_radps": 0.04,
    "acc_noise_mps2_sqrthz": 0.05,
    "acc_error_walk_mps3_sqrthz": 1e-3,
    "init_acc_error_std_mps2": 0.05,
    "zupt_std_mps": 0.01,
}


# -- reference ---------------------------------------------------------------------------------


def _qmul(a, b):
    """Hamilton product a (x) b, [w, x, y, z]."""
    a0, av = a[0], np.asarray(a[1:])
    b0, bv = b[0], np.asarray(b[1:])
    return np.concatenate([[a0 * b0 - av @ bv], a0 * bv + b0 * av + np.cross(av, bv)])


def _dcm(q):
    """C_b^n of a unit quaternion, from v_n = q (x) [0, v_b] (x) q*: column j is the image of e_j."""
    qc = np.array([q[0], -q[1], -q[2], -q[3]])
    return np.column_stack([_qmul(_qmul(q, np.concatenate([[0.0], e])), qc)[1:] for e in np.eye(3)])


def _axis_q(axis, angle):
    return np.concatenate([[np.cos(angle / 2)], np.sin(angle / 2) * np.eye(3)[axis]])


def _madgwick_imu(q, w, a, beta, dt):
    """Madgwick 2011, IMU: eq. 12 rate, eq. 25 objective, eq. 26 Jacobian, gradient step."""
    qdot = 0.5 * _qmul(q, np.concatenate([[0.0], w]))
    an = np.linalg.norm(a)
    if an > 0:
        f = _dcm(q).T @ np.array([0.0, 0.0, 1.0]) - a / an  # gravity seen in the sensor frame
        q0, q1, q2, q3 = q
        jac = np.array(
            [[-2 * q2, 2 * q3, -2 * q0, 2 * q1], [2 * q1, 2 * q0, 2 * q3, 2 * q2], [0.0, -4 * q1, -4 * q2, 0.0]]
        )
        grad = jac.T @ f
        gn = np.linalg.norm(grad)
        if gn > 0:
            qdot = qdot - beta * grad / gn
    q = q + qdot * dt
    return q / np.linalg.norm(q)


def reference(
    t,
    acc,
    gyr,
    mask,
    *,
    beta_radps,
    acc_noise_mps2_sqrthz,
    acc_error_walk_mps3_sqrthz,
    init_acc_error_std_mps2,
    zupt_std_mps,
):
    """Plain numpy Madgwick + Li et al. eq. 3-6 error KF; returns r, v, q, P per sample."""
    n = len(t)
    s0 = int(np.argmax(mask))
    e0 = s0 + int(np.argmin(mask[s0:])) if not mask[s0:].all() else n
    still = np.linalg.norm(gyr[s0:e0], axis=1) < STILL_GYR
    f = acc[s0:e0][still].mean(axis=0)
    bias = gyr[s0:e0][still].mean(axis=0)
    roll, pitch = np.arctan2(f[1], f[2]), np.arctan2(-f[0], np.hypot(f[1], f[2]))
    q = _qmul(_axis_q(1, pitch), _axis_q(0, roll))  # Rz(0) Ry(pitch) Rx(roll)
    eye, zero = np.eye(3), np.zeros((3, 3))
    h = np.hstack([zero, eye, zero])
    x = np.zeros(9)
    p = np.diag([0.0] * 6 + [init_acc_error_std_mps2**2] * 3)
    r, v = np.zeros(3), np.zeros(3)
    gvec = np.array([0.0, 0.0, G])
    a_prev = _dcm(q) @ acc[s0] - gvec
    out_r, out_v, out_q, out_p = np.zeros((n, 3)), np.zeros((n, 3)), np.zeros((n, 4)), np.zeros((n, 9, 9))
    out_q[: s0 + 1] = q
    for k in range(s0 + 1, n):
        dt = t[k] - t[k - 1]
        q = _madgwick_imu(q, gyr[k] - bias, acc[k], beta_radps, dt)
        c = _dcm(q)
        a_new = c @ acc[k] - gvec
        v_new = v + 0.5 * (a_prev + a_new) * dt
        r = r + 0.5 * (v + v_new) * dt
        v, a_prev = v_new, a_new
        phi = np.block([[eye, dt * eye, zero], [zero, eye, dt * c], [zero, zero, eye]])  # eq. 5
        qn = np.diag([0.0] * 3 + [acc_noise_mps2_sqrthz**2 * dt] * 3 + [acc_error_walk_mps3_sqrthz**2 * dt] * 3)
        x = phi @ x
        p = phi @ p @ phi.T + qn
        if mask[k]:  # eq. 6: z = v^ - 0
            s = h @ p @ h.T + zupt_std_mps**2 * eye
            gain = p @ h.T @ np.linalg.inv(s)
            x = x + gain @ (v - h @ x)
            p = (np.eye(9) - gain @ h) @ p
            p = 0.5 * (p + p.T)
            v, r = v - x[3:6], r - x[0:3]
            x[0:6] = 0.0
        out_r[k], out_v[k], out_q[k], out_p[k] = r - x[0:3], v - x[3:6], q, p
    return out_r, out_v, out_q, out_p


# -- the comparison ----------------------------------------------------------------------------


@pytest.fixture(scope="module")
def walk():
    """A short noisy walk with a left turn (attitude, gyro and accelerometer biases all non-trivial),
    one foot, the simulator's stance mask."""
    rec = footnav.simulate("path", seed=3, segments=[(2.8, 90.0), (1.4, 0.0)], standstill_s=1.0)
    imu, mask = rec.left, np.asarray(rec.truth_left.stance, dtype=bool)
    est = MadgwickEstimator(
        **PARAMS,
        use_magnetometer=False,
        heading="sensor",
        gyro_bias="initial-standstill",
        still_gyr_max_radps=STILL_GYR,
        heading_drift_in_std=False,
    )
    traj = est.estimate(imu, StanceResult(mask))
    ref = reference(imu.t, imu.acc, imu.gyr, mask, **PARAMS)
    return imu, mask, traj, ref


def test_the_walk_exercises_the_filter(walk):
    """The KF must have something to do: several ZUPT phases after swings, the acceleration error
    learnt to well above the tolerances, and velocity errors at touch-down that the sign of the
    innovation acts on."""
    imu, mask, traj, (r, _, _, _) = walk
    assert np.count_nonzero(np.diff(mask.astype(int)) == 1) >= 4
    assert r.shape == traj.position.shape and len(imu.t) > 500


# madgwick-innovation-sign, madgwick-f-transposed: positions and velocities.
# Measured max |footnav - reference|: position 2.7e-15 m, velocity 2.9e-15 m/s (seed 3, 761 samples); the mutants
# move them by mm (innovation sign) and um (F transposed); the tolerance is 1e-9.
def test_positions_and_velocities_match_the_reference(walk):
    _, _, traj, (r, v, _, _) = walk
    np.testing.assert_allclose(traj.position, r, rtol=0, atol=1e-9)
    np.testing.assert_allclose(traj.velocity, v, rtol=0, atol=1e-9)


# the attitude (independent of the KF): Madgwick's gradient step, the gyro bias, the levelling
# measured max quaternion difference 5.6e-16; position_std 1.0e-17 m (of up to 23 mm)
def test_attitude_matches_the_reference(walk):
    _, _, traj, (_, _, q, _) = walk
    sign = np.sign(np.sum(traj.quaternion * q, axis=1))[:, None]  # q and -q are one attitude
    np.testing.assert_allclose(traj.quaternion * sign, q, rtol=0, atol=1e-10)


# madgwick-f-transposed changes the covariance first (P's velocity rows take C'): position_std
# with heading="sensor" and no heading-drift term is sqrt(P_rr) of the KF.
def test_position_std_matches_the_reference_covariance(walk):
    _, _, traj, (_, _, _, p) = walk
    std = np.sqrt(np.stack([p[:, 0, 0], p[:, 1, 1], p[:, 2, 2]], axis=1))
    np.testing.assert_allclose(traj.position_std, std, rtol=1e-9, atol=1e-12)
