"""footnav.fusion.particle_ekf.PaperFoot (Lee, Cho & Park 2022, eq. 3-7) against a dense numpy
EKF written from the equations, and the height of paper-mode results against the simulator.

The reference below builds Phi (eq. 6), Q, H = [0 I_3 0 0] and K = P H' (H P H' + R)^-1 (eq. 7)
as matrices, in the module docstring's conventions (dx = x^ - x, C^ = (I - [dphi x]) C, db = b^ - b),
and feeds back p_z, v, the attitude and b_a. It shares only the strapdown step (eq. 4, tested on
its own in tests/estimators) with the code under test: the unrolled covariance loops, the
ZUPT's gain and every feedback sign are checked by it.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

import footnav
from footnav.core.types import StanceResult
from footnav.estimators.ekf import EkfEstimator
from footnav.fusion.particle import ParticleFusion
from footnav.fusion.particle_ekf import N_STATES, PaperFoot
from footnav.nav import quaternion as quat
from footnav.nav.mechanization import strapdown_step


def _skew(f):
    return np.array([[0.0, -f[2], f[1]], [f[2], 0.0, -f[0]], [-f[1], f[0], 0.0]])


def reference_ekf(t, acc, gyr, mask, start, q0, p0, bg, cov0, noise, stop):
    """Dense EKF of eq. 3-7 from ``start`` to ``stop``: (p_z, v, q, std_z, b_a) per sample."""
    q, v, p = np.asarray(q0, float).reshape(1, 4).copy(), np.zeros((1, 3)), np.asarray(p0, float).reshape(1, 3).copy()
    f_n = (quat.as_matrix(q[0]) @ acc[start]).reshape(1, 3)
    ba, cov = np.zeros(3), np.diag(np.asarray(cov0, float))
    dq, q_tmp, c = np.empty(4), np.empty(4), np.empty((3, 3))
    h = np.zeros((3, N_STATES))
    h[:, 1:4] = np.eye(3)
    out = {"pz": {}, "v": {}, "q": {}, "std_z": {}, "ba": {}}
    for k in range(start + 1, stop + 1):
        dt = t[k] - t[k - 1]
        strapdown_step(q, v, p, f_n, 0, acc[k - 1] - ba, gyr[k - 1] - bg, acc[k] - ba, gyr[k] - bg, dt, dq, q_tmp, c)
        cm = quat.as_matrix(q[0])
        phi = np.eye(N_STATES)
        phi[0, 3] = dt  # dp_z' = dp_z + dv_z dt
        phi[1:4, 4:6] = dt * _skew(f_n[0])[:, :2]  # + [f^n x]_{3x2} dphi dt
        phi[1:4, 6:9] = -dt * cm  # - C_b^n db_a dt
        qd = np.diag([0.0, *[noise[0] * dt] * 3, *[noise[1] * dt] * 2, *[noise[2] * dt] * 3])
        cov = phi @ cov @ phi.T + qd
        if mask[k]:
            s = h @ cov @ h.T + noise[3] * np.eye(3)
            gain = cov @ h.T @ np.linalg.inv(s)
            dx = gain @ v[0]  # y = v^ - 0
            cov = (np.eye(N_STATES) - gain @ h) @ cov
            cov = 0.5 * (cov + cov.T)
            p[0, 2] -= dx[0]
            v[0] -= dx[1:4]
            ba -= dx[6:9]
            q[0] = quat.normalize(quat.multiply(quat.from_rotvec(np.array([dx[4], dx[5], 0.0])), q[0]))
        out["pz"][k], out["v"][k], out["q"][k] = p[0, 2], v[0].copy(), q[0].copy()
        out["std_z"][k], out["ba"][k] = np.sqrt(cov[0, 0]), ba.copy()
    return out


@pytest.fixture(scope="module")
def stairs_walk():
    return footnav.simulate("path", seed=2, segments=[(3.0, 0.0), ("stairs", 6, 0.17), (3.0, 0.0)])


def test_paper_foot_ekf_matches_a_dense_reference(stairs_walk):
    # mutant: particle-ekf-pz-feedback-sign, particle-ekf-att-feedback-sign, particle-ekf-ba-feedback-sign,
    # particle-ekf-bias-phi-sign, particle-ekf-pz-phi-dropped, particle-ekf-att-q-dropped
    rec = stairs_walk
    imu, truth = rec.left, rec.truth_left
    mask = truth.stance
    start = int(np.argmax(~mask)) - 1  # the last sample of the first stance
    n = len(imu.t)
    cov0 = [1e-4, 1e-4, 1e-4, 1e-4, 1e-3, 1e-3, 1e-4, 1e-4, 1e-4]
    noise = [0.08**2, 0.01**2, 1e-5, 0.01**2]
    # the truth's attitude a little off (tilt errors for the ZUPTs to observe), a small gyro bias
    q0 = quat.multiply(quat.from_rotvec(np.array([0.02, -0.015, 0.0])), truth.quaternion[start])
    bg = np.array([1e-3, -2e-3, 5e-4])
    zeros = np.zeros(n)
    foot = PaperFoot(
        imu.t,
        imu.acc,
        imu.gyr,
        mask,
        start,
        q0,
        np.array([0.0, 0.0, 0.1]),
        bg,
        cov0,
        noise,
        np.zeros((4, 2)),
        1.0,
        zeros,
        zeros,
    )
    foot.run_until(n - 1, np.random.default_rng(0))
    ref = reference_ekf(imu.t, imu.acc, imu.gyr, mask, start, q0, [0.0, 0.0, 0.1], bg, cov0, noise, n - 1)
    ks = np.arange(start + 1, n)
    np.testing.assert_allclose(foot.position[ks, 2], [ref["pz"][k] for k in ks], atol=1e-9)
    np.testing.assert_allclose(foot.velocity[ks], [ref["v"][k] for k in ks], atol=1e-9)
    np.testing.assert_allclose(foot.quaternion[ks], [ref["q"][k] for k in ks], atol=1e-9)
    np.testing.assert_allclose(foot.position_std[ks, 2], [ref["std_z"][k] for k in ks], rtol=1e-7, atol=1e-12)
    np.testing.assert_allclose(foot.ba, ref["ba"][n - 1], atol=1e-12)
    # and the EKF is right, not only alike: it ends at the true height (6 x 0.17 m climbed)
    assert foot.position[-1, 2] - 0.1 == pytest.approx(truth.position[-1, 2] - truth.position[start, 2], abs=0.05)


def test_paper_mode_results_carry_the_height(stairs_walk):
    # the paper-mode fusion's 3-D output: z of each foot and of the path follow the stairs
    rec = stairs_walk
    stances = StanceResult(rec.truth_left.stance), StanceResult(rec.truth_right.stance)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = ParticleFusion(mode="paper", seed=1).fuse(EkfEstimator(), rec.left, stances[0], rec.right, stances[1])
    climbed = rec.meta["height_change_m"]
    assert climbed == pytest.approx(6 * 0.17)
    for traj, truth in ((res.left, rec.truth_left), (res.right, rec.truth_right)):
        rise = traj.position[-1, 2] - traj.position[0, 2]
        assert rise == pytest.approx(truth.position[-1, 2] - truth.position[0, 2], abs=0.08)
        assert np.all(traj.position_std[-1] > 0)
    assert res.path.position.shape[1] == 3
    assert res.path.position[-1, 2] - res.path.position[0, 2] == pytest.approx(climbed, abs=0.08)


# -- the lateral drift of eq. 12 (mutant-derived, tools/mutate.py) ------------------------------
#
# The mutant changes the spread of the cloud, not its mean; the spread is checked against the
# Rayleigh moments of the paper's drift.


G = 9.80665  # m/s^2, written out


def _drift_only_foot(yaw, side, sigma, offset, n_particles, seed):
    """A PaperFoot that stands still (exact gravity, no rotation) with its sensor turned ``yaw``
    about the vertical, while its mask says it moves for 50 samples: no EKF noise, so the cloud
    moves by the drift of eq. 12 alone. The per-sample scale and offset are written from the
    docstring of drift_scales: s = sigma / sqrt(M), o = s sqrt(pi/2) - (sigma sqrt(pi/2) - offset) / M."""
    rate, m = 100.0, 50
    mask = np.r_[np.ones(20, bool), np.zeros(m, bool), np.ones(20, bool)]
    n = len(mask)
    t = np.arange(n) / rate
    acc = np.tile([0.0, 0.0, G], (n, 1))
    gyr = np.zeros((n, 3))
    scale, off = np.zeros(n), np.zeros(n)
    s = sigma / math.sqrt(m)
    scale[~mask] = s
    off[~mask] = s * math.sqrt(math.pi / 2) - (sigma * math.sqrt(math.pi / 2) - offset) / m
    q0 = np.array([math.cos(yaw / 2), 0.0, 0.0, math.sin(yaw / 2)])
    p0 = np.zeros(3)
    foot = PaperFoot(
        t,
        acc,
        gyr,
        mask,
        19,
        q0,
        p0,
        np.zeros(3),
        np.zeros(N_STATES),
        np.array([0.0, 0.0, 0.0, 1e-4]),
        np.zeros((n_particles, 2)),
        side,
        scale,
        off,
    )
    foot.run_until(n - 1, np.random.default_rng(seed))
    return foot.cloud


# mutant: particle-ekf-lateral-transposed
# particle-ekf-lateral-transposed: the drift moves each particle along the body's +y axis in nav,
# C_b^n [0, f', 0]': for a level sensor turned by yaw psi that is (-sin psi, cos psi). One step's
# drift is Rayleigh(sigma) - offset (Sec. 2.2): mean sigma sqrt(pi/2) - offset, variance
# (2 - pi/2) sigma^2, so the cloud's mean is that mean times side (-sin psi, cos psi) and its
# covariance (2 - pi/2) sigma^2 l l'. With the transposed C the x-component flips sign (0.11 m
# off in the mean at psi = 60 deg; the covariance's xy term changes sign).
@pytest.mark.parametrize("side", [1.0, -1.0])
def test_paper_drift_is_along_the_body_y_axis(side):
    yaw, sigma, offset, n = math.radians(60.0), 0.05, 0.0, 20_000
    cloud = _drift_only_foot(yaw, side, sigma, offset, n, seed=11)
    lat = side * np.array([-math.sin(yaw), math.cos(yaw)])
    mean_step = sigma * math.sqrt(math.pi / 2) - offset
    var_step = (2.0 - math.pi / 2) * sigma**2
    # the mean's standard error is sqrt(var_step / n) = 2.3e-4 m: 5 of them
    np.testing.assert_allclose(cloud.mean(axis=0), mean_step * lat, atol=5 * math.sqrt(var_step / n))
    # the spread: all along lat (rank one), variance var_step within 5 % (sample error about 1 %)
    cov = np.cov(cloud.T)
    np.testing.assert_allclose(cov, var_step * np.outer(lat, lat), atol=0.05 * var_step)
    across = cloud @ np.array([lat[1], -lat[0]])
    assert np.abs(across).max() < 1e-12  # nothing across the body's y axis
