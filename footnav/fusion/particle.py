"""Particle-filter dual-foot fusion with lateral systematic drift (seed 004, Lee, Cho, Park 2022).

Seed 004 keeps each foot's horizontal position in a particle filter (PF) and the other error
states in the foot's EKF (a marginalised structure). Per foot and step:

* **Propagation** (eq. 10-12): particles move with the EKF; their spread is the EKF's velocity
  uncertainty integrated over the step (``P_pos = P_vel dt^2``, eq. 11) plus a *lateral*
  systematic drift in the foot's frame, ``C_b^n [0, f'(sigma_sys)]``, with ``f'`` an offset
  Rayleigh distribution, skewed one way for the right shoe and mirrored for the left (Sec. 2.2).
* **Fusion** (eq. 13-14): at the end of each zero-velocity phase, each foot's cloud is summarised
  by its mean and covariance, and the two are summed as Gaussians into one pedestrian position.
* **Update** (eq. 15-16): that position weighs the particles of the foot whose stance ended
  (likelihood ``N(p_fused | x_n, Sigma_i)``, ``Sigma_i`` the foot's cloud), and the cloud is
  resampled systematically (Kitagawa 1996).

footnav's reading. The feet run in the joint filter of :mod:`footnav.fusion.joint` (no coupling
but through the PF). The EKF's horizontal position is kept equal to the PF's: after each PF
update, the cloud's mean and covariance are applied to the EKF as a horizontal position
measurement, so the EKF's next displacement starts from the PF's estimate. The propagation noise
over a step is the growth of the EKF's horizontal position covariance over that step (what
``P_vel dt^2`` sums to, with the EKF's correlations). The Rayleigh distribution is offset by its
mean, so the drift is skewed but unbiased. The likelihood uses the component across the foot's
heading only: when a stance ends the other foot has just landed half a stride ahead, so the
pedestrian position (between the feet) would otherwise pull every foot forward at every step
(measured: the straight walk's E_p doubled). All randomness comes from ``seed``.
"""

from __future__ import annotations

from numbers import Integral
from typing import ClassVar

import numpy as np
from numba import njit
from numpy.typing import NDArray

from footnav.core import quaternion as quat
from footnav.core.component import Fusion, require, require_non_negative
from footnav.core.types import FusionResult
from footnav.fusion.joint import LEFT, RIGHT, finish_joint, check_two_feet, start_joint

__all__ = ["ParticleFusion", "systematic_resample", "offset_rayleigh", "gaussian_sum"]


@njit(cache=True)
def _propagate(cloud, shift, noise_t, normals, drift, lateral, mean, cov):
    """cloud += shift + normals @ noise_t + drift * lateral (eq. 10-12), in place; writes the
    cloud's mean (2,) and covariance (2, 2) (eq. 14)."""
    n = cloud.shape[0]
    for i in range(n):
        x = cloud[i, 0] + shift[0] + normals[i, 0] * noise_t[0, 0] + normals[i, 1] * noise_t[1, 0] + drift[i] * lateral[0]
        y = cloud[i, 1] + shift[1] + normals[i, 0] * noise_t[0, 1] + normals[i, 1] * noise_t[1, 1] + drift[i] * lateral[1]
        cloud[i, 0] = x
        cloud[i, 1] = y
    _moments(cloud, mean, cov)


@njit(cache=True)
def _moments(cloud, mean, cov):
    n = cloud.shape[0]
    mx = my = 0.0
    for i in range(n):
        mx += cloud[i, 0]
        my += cloud[i, 1]
    mx /= n
    my /= n
    cxx = cxy = cyy = 0.0
    for i in range(n):
        dx = cloud[i, 0] - mx
        dy = cloud[i, 1] - my
        cxx += dx * dx
        cxy += dx * dy
        cyy += dy * dy
    mean[0], mean[1] = mx, my
    cov[0, 0], cov[0, 1], cov[1, 0], cov[1, 1] = cxx / n, cxy / n, cxy / n, cyy / n


@njit(cache=True)
def _weigh_and_resample(cloud, z, lateral, var, u, out, mean, cov):
    """Eq. 15-16 across ``lateral``: weights exp(-d^2 / 2 var), systematic resampling with the
    uniform draw ``u`` into ``out``; writes out's mean and covariance."""
    n = cloud.shape[0]
    logw = np.empty(n)
    best = -np.inf
    for i in range(n):
        d = (cloud[i, 0] - z[0]) * lateral[0] + (cloud[i, 1] - z[1]) * lateral[1]
        logw[i] = -0.5 * d * d / var
        if logw[i] > best:
            best = logw[i]
    total = 0.0
    for i in range(n):
        logw[i] = np.exp(logw[i] - best)
        total += logw[i]
    j = 0
    cum = logw[0] / total
    for k in range(n):
        point = (u + k) / n
        while cum <= point and j < n - 1:
            j += 1
            cum += logw[j] / total
        out[k, 0] = cloud[j, 0]
        out[k, 1] = cloud[j, 1]
    _moments(out, mean, cov)


def systematic_resample(weights: NDArray[np.float64], rng: np.random.Generator) -> NDArray[np.int64]:
    """Indices of N particles drawn by systematic resampling (Kitagawa 1996).

    One uniform draw ``u ~ U[0, 1/N)``; particle i is copied once for every point ``u + k/N``
    that falls in its slice of the cumulative weights, so its count is ``floor`` or ``ceil`` of
    ``N w_i``.
    """
    w = np.asarray(weights, dtype=float)
    n = len(w)
    cum = np.cumsum(w / w.sum())
    cum[-1] = 1.0  # rounding must not lose the last particle
    points = (rng.random() + np.arange(n)) / n
    return np.searchsorted(cum, points, side="right").astype(np.int64)


def offset_rayleigh(sigma: float, size: int, rng: np.random.Generator) -> NDArray[np.float64]:
    """Rayleigh(sigma) samples minus the distribution's mean ``sigma sqrt(pi/2)``: zero mean,
    variance ``(2 - pi/2) sigma^2``, mode ``sigma (1 - sqrt(pi/2))`` < 0 (seed 004 eq. 1, Sec. 2.2)."""
    return rng.rayleigh(sigma, size) - sigma * np.sqrt(np.pi / 2)


def gaussian_sum(means: NDArray[np.float64], covs: NDArray[np.float64], weights: NDArray[np.float64]) -> tuple[NDArray, NDArray]:
    """Mean and covariance of a Gaussian mixture (seed 004 eq. 13): ``sum a_i N(mu_i, S_i)``.

    ``mu = sum a_i mu_i``, ``S = sum a_i (S_i + (mu_i - mu)(mu_i - mu)')`` with the weights
    normalised to 1.
    """
    a = np.asarray(weights, float) / np.sum(weights)
    mu = np.einsum("i,ij->j", a, means)
    d = means - mu
    cov = np.einsum("i,ijk->jk", a, covs) + np.einsum("i,ij,ik->jk", a, d, d)
    return mu, cov


class ParticleFusion(Fusion):
    """Each foot's horizontal position in a particle filter, fused by a Gaussian sum (seed 004).

    Parameters
    ----------
    n_particles : int
        Particles per foot (seed 004: 100).
    sigma_sys_m : float
        Scale of the offset-Rayleigh lateral drift added per step, m (seed 004 eq. 12; 0.05 m
        measured best of 0.01 / 0.05 on the simulator's straight walk, the rectangles are within
        5 % either way).
    seed : int
        Seed of the particles' random generator.
    step_width_m : float
        Lateral distance between the feet at the start, m.

    Examples
    --------
    >>> pipe = footnav.make_pipeline("threshold", "ekf", "particle", fusion_params={"n_particles": 1000})  # doctest: +SKIP
    """

    name = "particle"
    needs_two_feet: ClassVar[bool] = True
    needs_stepable_estimator: ClassVar[bool] = True

    def __init__(self, *, n_particles: int = 100, sigma_sys_m: float = 0.05, seed: int = 0, step_width_m: float = 0.2) -> None:
        self.n_particles = n_particles
        self.sigma_sys_m = sigma_sys_m
        self.seed = seed
        self.step_width_m = step_width_m

    def validate_params(self) -> None:
        require(isinstance(self.n_particles, Integral) and not isinstance(self.n_particles, bool) and self.n_particles >= 2,
                self, "n_particles", "an integer >= 2")
        require(isinstance(self.seed, Integral) and not isinstance(self.seed, bool), self, "seed", "an integer")
        require_non_negative(self, "sigma_sys_m", "step_width_m")

    def fuse(self, estimator, left, stance_left, right=None, stance_right=None) -> FusionResult:
        """Both feet's EKFs with their horizontal positions carried by particle clouds."""
        check_two_feet(self, estimator, right, stance_right)
        rng = np.random.default_rng(self.seed)
        imus, stances = (left, right), (stance_left, stance_right)
        filt = start_joint(estimator, left, stance_left, right, stance_right, self.step_width_m)
        n = int(self.n_particles)
        clouds = [np.tile(filt.position(f)[:2], (n, 1)) + 1e-6 * rng.standard_normal((n, 2)) for f in (LEFT, RIGHT)]
        last_p = [filt.position(f)[:2].copy() for f in (LEFT, RIGHT)]
        events = sorted(
            (float(imu.t[stop - 1]), foot)
            for foot, (imu, st) in enumerate(zip(imus, stances))
            for _, stop in st.intervals[:-1]  # the end of each zero-velocity phase but the last
        )
        def pos_cov(f: int) -> NDArray[np.float64]:
            sl = filt.block(f, "pos")
            return filt._cov[sl.start : sl.start + 2, sl.start : sl.start + 2].copy()

        def moments(c: NDArray[np.float64]) -> tuple[NDArray, NDArray]:
            m = c.mean(axis=0)
            d = c - m
            return m, d.T @ d / len(c)

        def psd(a: NDArray[np.float64]) -> tuple[NDArray, NDArray]:
            vals, vecs = np.linalg.eigh(0.5 * (a + a.T))
            return np.maximum(vals, 0.0), vecs

        last_cov = [pos_cov(f) for f in (LEFT, RIGHT)]
        summary = [moments(c) for c in clouds]
        updates = 0
        for t, foot in events:
            filt.run_until(t)
            # eq. 10-12: the cloud of the foot that stood is drawn forward; the other foot's is
            # needed only through its mean and covariance, which move without drawing
            other = 1 - foot
            p_o = filt.position(other)[:2]
            vals_o, vecs_o = psd(pos_cov(other) - last_cov[other])
            mean_o = summary[other][0] + (p_o - last_p[other])
            cov_o = summary[other][1] + (vecs_o * vals_o) @ vecs_o.T
            p = filt.position(foot)[:2]
            vals, vecs = psd(pos_cov(foot) - last_cov[foot])
            yaw = float(quat.yaw(filt.quaternion(foot)))
            lateral = np.array([-np.sin(yaw), np.cos(yaw)])
            side = 1.0 if foot == LEFT else -1.0  # the drift is mirrored between the feet (eq. 12)
            drift = side * offset_rayleigh(self.sigma_sys_m, n, rng) if self.sigma_sys_m > 0 else np.zeros(n)
            mean_f, cov_f = np.empty(2), np.empty((2, 2))
            _propagate(clouds[foot], p - last_p[foot], (vecs * np.sqrt(vals)).T, rng.standard_normal((n, 2)), drift, lateral, mean_f, cov_f)
            # eq. 13-14: each cloud as a Gaussian, their sum is the pedestrian
            z, _ = gaussian_sum(np.array([mean_f, mean_o]), np.array([cov_f, cov_o]), np.ones(2))
            # eq. 15-16: L = N(p_fused | x_n, Sigma_i) with the foot's own spread, across the
            # foot's heading only: the drift it corrects is lateral (Sec. 2), and along the walk
            # the feet are half a stride apart when a stance ends, which is not an error
            resampled, mean, cov = np.empty((n, 2)), np.empty(2), np.empty((2, 2))
            var = float(lateral @ cov_f @ lateral) + 1e-8
            _weigh_and_resample(clouds[foot], z, lateral, var, rng.random(), resampled, mean, cov)
            clouds[foot] = resampled
            # the EKF follows the PF: the cloud's mean and covariance as a position measurement
            vals, vecs = np.linalg.eigh(cov + 1e-8 * np.eye(2))
            sl = filt.block(foot, "pos")
            h = filt.selection(np.arange(sl.start, sl.start + 2))
            filt.update(vecs.T @ h, vecs.T @ (filt.position(foot)[:2] - mean), vals)
            last_p[foot] = filt.position(foot)[:2].copy()
            last_cov[foot] = pos_cov(foot)
            summary[foot] = (mean, cov)
            updates += 1
        meta = {"fusion": self.describe(), "pf_updates": updates, "n_particles": n}
        return finish_joint(estimator, filt, stance_left, stance_right, meta)
