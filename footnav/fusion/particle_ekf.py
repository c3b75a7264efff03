"""One foot of Lee, Cho & Park (2022): the EKF of eq. 3 with the horizontal position in particles.

The foot's state is split (eq. 2, 8): the horizontal position ``[p_x, p_y]`` is a particle cloud,
every other error state is in an EKF (eq. 3)::

    dx_EKF = [dp_z, dv^l (3), dphi^l (2, about the horizontal axes), db_a^b (3)]      (9 states)

No heading error and no gyro bias state: ZUPTs do not observe them (Sec. 3.1); the gyro bias is
the mean rate of the first standstill. Per sample (Algorithm 1):

* INS mechanization (eq. 4; :func:`footnav.nav.mechanization.strapdown_step`);
* ``P = Phi P Phi' + Q`` with Phi of eq. 6: ``dp_z' = dp_z + dv_z dt``,
  ``dv' = dv + [f^n x]_{3x2} dphi dt - C_b^n db_a dt``, the rest constant. The bias term's sign
  is footnav's convention (``db = b^ - b``, ``dv = v^ - v``, ``C^ = (I - [dphi x]) C``);
  the paper writes ``+C_b^n dt`` for its opposite bias-error sign;
* every particle moves with the mechanization's horizontal displacement plus a draw of
  ``N(0, P_vel dt^2)`` (eq. 10-11; ``P_vel`` the EKF's horizontal velocity covariance) plus,
  while the foot moves, the lateral drift ``C_b^n [0, f', 0]'`` (eq. 12), ``f'`` an offset
  Rayleigh draw (module :mod:`footnav.fusion.particle`, :func:`drift_scales`);
* in stance, the ZUPT (eq. 7): ``H = [0 I_3 0 0]``, ``y = v^``, ``K = P H' (H P H' + R)^-1``,
  fed back into ``p_z``, ``v``, the attitude and ``b_a``.

The particles never feed back into the EKF: the EKF has no horizontal position (eq. 2-3).
Randomness comes only from the arrays of draws the caller passes (its ``numpy`` Generator).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from footnav._numba import njit  # numba.njit that survives a read-only install
from footnav.nav.kalman import sym3_inverse
from footnav.nav.mechanization import strapdown_step
from footnav.nav.quaternion import as_matrix_nb, from_rotvec_nb, multiply_nb, normalize_nb

__all__ = ["N_STATES", "PZ", "VEL", "ATT", "ACC_BIAS", "PaperFoot", "drift_scales"]

#: Offsets in the error state of eq. 3.
PZ, VEL, ATT, ACC_BIAS = 0, 1, 4, 6
N_STATES = 9
_SQRT_HALF_PI = math.sqrt(0.5 * math.pi)


def drift_scales(
    mask: NDArray[np.bool_], sigma_m: float, offset_m: float
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Per-sample scale and offset of the lateral drift, so that one step's sum has the moments of
    one draw of ``Rayleigh(sigma_m) - offset_m`` (the per-step distribution of Sec. 2.2, Fig. 2).

    Eq. 12 adds the drift at every time update; Fig. 2 fits it per step. Over a swing of ``n``
    moving samples, draws ``sigma_s R - o_s`` (``R`` a unit Rayleigh draw) with
    ``sigma_s = sigma / sqrt(n)`` and ``o_s = sigma_s sqrt(pi/2) - (sigma sqrt(pi/2) - offset) / n``
    sum to the step's mean ``sigma sqrt(pi/2) - offset`` and variance ``(2 - pi/2) sigma^2``
    (the skew shrinks as ``1/sqrt(n)``). Stance samples get 0, 0 (no drift while the foot stands).

    Returns
    -------
    scale, offset
        (N,) each, m.
    """
    moving = ~np.asarray(mask, dtype=bool)
    scale, offset = np.zeros(len(moving)), np.zeros(len(moving))
    if sigma_m == 0.0:
        # no Rayleigh term, no drift: the offset alone would push each foot sideways by
        # offset_m at every step with nothing random around it (issue 36)
        return scale, offset
    edges = np.flatnonzero(np.diff(np.r_[0, moving.astype(np.int8), 0]))
    mean_step = sigma_m * _SQRT_HALF_PI - offset_m
    for a, b in zip(edges[::2], edges[1::2]):
        s = sigma_m / math.sqrt(b - a)
        scale[a:b] = s
        offset[a:b] = s * _SQRT_HALF_PI - mean_step / (b - a)
    return scale, offset


@njit(cache=True, error_model="numpy")
# complexity: a compiled loop over the samples, one pass
def _advance(  # noqa: C901
    k0,
    k1,
    t,
    acc,
    gyr,
    mask,
    bg,
    q,
    v,
    p,
    f_n,
    ba,
    cov,
    noise,
    side,
    cloud,
    normals,
    rayleigh,
    drift_scale,
    drift_offset,
    out_pos,
    out_vel,
    out_q,
    out_std,
    dq,
    q_tmp,
    c,
    tmp,
):
    """Samples ``k0+1 .. k1`` of one foot, in place (module docstring); ``noise`` holds
    ``[sigma_a^2, sigma_g^2, sigma_ba^2, r_zupt]`` (densities squared, m^2/s^2); ``normals``
    (k1-k0, N, 2) and ``rayleigh`` (k1-k0, N) unit draws; ``side`` +1 for the right foot's drift
    along the body's +y, -1 for the left's (mirrored, Sec. 2.2). Writes each sample's cloud mean
    (with ``p_z``), velocity, attitude and std to the ``out_`` rows."""
    n = cloud.shape[0]
    dxs, gain = np.empty(N_STATES), np.empty((N_STATES, 3))
    acc_prev, gyr_prev, acc_k, gyr_k = np.empty(3), np.empty(3), np.empty(3), np.empty(3)
    for k in range(k0 + 1, k1 + 1):
        j = k - k0 - 1
        dt = t[k] - t[k - 1]
        for i in range(3):
            acc_prev[i] = acc[k - 1, i] - ba[i]
            gyr_prev[i] = gyr[k - 1, i] - bg[i]
            acc_k[i] = acc[k, i] - ba[i]
            gyr_k[i] = gyr[k, i] - bg[i]
        px, py = p[0, 0], p[0, 1]
        strapdown_step(q, v, p, f_n, 0, acc_prev, gyr_prev, acc_k, gyr_k, dt, dq, q_tmp, c)  # eq. 4
        as_matrix_nb(q[0], c)
        # P <- Phi P Phi' + Q (eq. 5-6): rows first (tmp = Phi P), then columns
        fx, fy, fz = f_n[0, 0], f_n[0, 1], f_n[0, 2]
        # [f^n x] without its third column: [[0, -fz], [fz, 0], [-fy, fx]]
        fa = ((0.0, -fz), (fz, 0.0), (-fy, fx))
        for r in range(N_STATES):
            for col in range(N_STATES):
                tmp[r, col] = cov[r, col]
        for col in range(N_STATES):
            tmp[PZ, col] += dt * cov[VEL + 2, col]
            for i in range(3):
                acc_term = fa[i][0] * cov[ATT, col] + fa[i][1] * cov[ATT + 1, col]
                bias_term = (
                    c[i, 0] * cov[ACC_BIAS, col] + c[i, 1] * cov[ACC_BIAS + 1, col] + c[i, 2] * cov[ACC_BIAS + 2, col]
                )
                tmp[VEL + i, col] += dt * (acc_term - bias_term)
        for r in range(N_STATES):
            for col in range(N_STATES):
                cov[r, col] = tmp[r, col]
        for r in range(N_STATES):
            cov[r, PZ] += dt * tmp[r, VEL + 2]
            for i in range(3):
                acc_term = fa[i][0] * tmp[r, ATT] + fa[i][1] * tmp[r, ATT + 1]
                bias_term = c[i, 0] * tmp[r, ACC_BIAS] + c[i, 1] * tmp[r, ACC_BIAS + 1] + c[i, 2] * tmp[r, ACC_BIAS + 2]
                cov[r, VEL + i] += dt * (acc_term - bias_term)
        for i in range(3):
            cov[VEL + i, VEL + i] += noise[0] * dt
            cov[ACC_BIAS + i, ACC_BIAS + i] += noise[2] * dt
        cov[ATT, ATT] += noise[1] * dt
        cov[ATT + 1, ATT + 1] += noise[1] * dt
        # particles (eq. 10-12): displacement + N(0, P_vel dt^2) + C_b^n [0, f', 0]'
        vxx, vxy, vyy = cov[VEL, VEL] * dt * dt, cov[VEL, VEL + 1] * dt * dt, cov[VEL + 1, VEL + 1] * dt * dt
        l11 = math.sqrt(max(vxx, 0.0))
        l21 = vxy / l11 if l11 > 0.0 else 0.0
        l22 = math.sqrt(max(vyy - l21 * l21, 0.0))
        dx, dy = p[0, 0] - px, p[0, 1] - py
        lat_x, lat_y = side * c[0, 1], side * c[1, 1]  # the body's y axis in nav, horizontal part
        ds, do = drift_scale[k], drift_offset[k]
        mx = my = 0.0
        for m in range(n):
            g0, g1 = normals[j, m, 0], normals[j, m, 1]
            drift = ds * rayleigh[j, m] - do
            cloud[m, 0] += dx + l11 * g0 + drift * lat_x
            cloud[m, 1] += dy + l21 * g0 + l22 * g1 + drift * lat_y
            mx += cloud[m, 0]
            my += cloud[m, 1]
        if mask[k]:
            # ZUPT (eq. 7): y = v^ - 0, S = P_vv + R, K = P H' S^-1, dx = K y
            i00, i01, i02, i11, i12, i22, det = sym3_inverse(
                cov[VEL, VEL] + noise[3],
                cov[VEL, VEL + 1],
                cov[VEL, VEL + 2],
                cov[VEL + 1, VEL + 1] + noise[3],
                cov[VEL + 1, VEL + 2],
                cov[VEL + 2, VEL + 2] + noise[3],
            )
            if det > 0.0:
                y0, y1, y2 = v[0, 0], v[0, 1], v[0, 2]
                s0 = i00 * y0 + i01 * y1 + i02 * y2
                s1 = i01 * y0 + i11 * y1 + i12 * y2
                s2 = i02 * y0 + i12 * y1 + i22 * y2
                for r in range(N_STATES):
                    dxs[r] = cov[r, VEL] * s0 + cov[r, VEL + 1] * s1 + cov[r, VEL + 2] * s2
                    # K = P H' S^-1
                    gain[r, 0] = cov[r, VEL] * i00 + cov[r, VEL + 1] * i01 + cov[r, VEL + 2] * i02
                    gain[r, 1] = cov[r, VEL] * i01 + cov[r, VEL + 1] * i11 + cov[r, VEL + 2] * i12
                    gain[r, 2] = cov[r, VEL] * i02 + cov[r, VEL + 1] * i12 + cov[r, VEL + 2] * i22
                # P <- P - K H P
                for r in range(N_STATES):
                    for col in range(N_STATES):
                        tmp[r, col] = cov[r, col] - (
                            gain[r, 0] * cov[VEL, col] + gain[r, 1] * cov[VEL + 1, col] + gain[r, 2] * cov[VEL + 2, col]
                        )
                for r in range(N_STATES):
                    for col in range(N_STATES):
                        cov[r, col] = 0.5 * (tmp[r, col] + tmp[col, r])
                # feedback: p_z, v, attitude (C = (I + [dphi x]) C^), b_a
                p[0, 2] -= dxs[PZ]
                for i in range(3):
                    v[0, i] -= dxs[VEL + i]
                    ba[i] -= dxs[ACC_BIAS + i]
                from_rotvec_nb(dxs[ATT], dxs[ATT + 1], 0.0, dq)
                multiply_nb(dq, q[0], q_tmp)
                normalize_nb(q_tmp)
                for i in range(4):
                    q[0, i] = q_tmp[i]
        mx /= n
        my /= n
        sxx = syy = 0.0
        for m in range(n):
            sxx += (cloud[m, 0] - mx) ** 2
            syy += (cloud[m, 1] - my) ** 2
        out_pos[k, 0], out_pos[k, 1], out_pos[k, 2] = mx, my, p[0, 2]
        for i in range(3):
            out_vel[k, i] = v[0, i]
        for i in range(4):
            out_q[k, i] = q[0, i]
        out_std[k, 0], out_std[k, 1] = math.sqrt(sxx / n), math.sqrt(syy / n)
        out_std[k, 2] = math.sqrt(max(cov[PZ, PZ], 0.0))


class PaperFoot:
    """One foot's EKF (eq. 3) and particle cloud, advanced sample by sample (module docstring).

    Parameters
    ----------
    t, acc, gyr, mask
        The foot's samples and stance mask (N,), (N, 3), (N, 3), (N,).
    start
        First sample (the end of the first stance's alignment: the state holds before it).
    q0, p0, gyro_bias
        Initial attitude [w, x, y, z] (body -> nav), position (3,), m, gyro bias (3,), rad/s.
    cov0
        (9,) initial variances of eq. 3's states.
    noise
        ``[sigma_a^2, sigma_g^2, sigma_ba^2, r_zupt]``: densities squared and the ZUPT variance.
    cloud
        (N_p, 2) the initial particles, m.
    side
        +1 (right foot) or -1 (left foot): the sign of the drift along the body's +y.
    drift_scale, drift_offset
        (N,) from :func:`drift_scales`.
    """

    def __init__(
        self, t, acc, gyr, mask, start, q0, p0, gyro_bias, cov0, noise, cloud, side, drift_scale, drift_offset
    ):
        self.t, self.acc, self.gyr = t, np.ascontiguousarray(acc, float), np.ascontiguousarray(gyr, float)
        self.mask = np.asarray(mask, dtype=np.bool_)
        self.k = int(start)
        self.bg = np.asarray(gyro_bias, float)
        self.q = np.asarray(q0, float).reshape(1, 4).copy()
        self.v = np.zeros((1, 3))
        self.p = np.asarray(p0, float).reshape(1, 3).copy()
        c = np.empty((3, 3))
        as_matrix_nb(self.q[0], c)
        self.f_n = (c @ self.acc[self.k]).reshape(1, 3)
        self.ba = np.zeros(3)
        self.cov = np.diag(np.asarray(cov0, float))
        self.noise = np.asarray(noise, float)
        self.cloud = np.ascontiguousarray(cloud, float)
        self.side = float(side)
        self.drift_scale, self.drift_offset = drift_scale, drift_offset
        n = len(t)
        self.position, self.velocity = np.empty((n, 3)), np.zeros((n, 3))
        self.quaternion, self.position_std = np.empty((n, 4)), np.zeros((n, 3))
        self._work = (np.empty(4), np.empty(4), np.empty((3, 3)), np.empty((N_STATES, N_STATES)))
        self._record_until(self.k)

    def _record_until(self, k: int) -> None:
        """Samples up to ``k`` hold the initial state (before the start)."""
        self.position[: k + 1] = [self.cloud[:, 0].mean(), self.cloud[:, 1].mean(), self.p[0, 2]]
        self.quaternion[: k + 1] = self.q[0]
        self.position_std[: k + 1, :2] = self.cloud.std(axis=0)

    def run_until(self, k: int, rng: np.random.Generator) -> None:
        """Advance to sample ``k`` (inclusive), drawing from ``rng``."""
        k = min(int(k), len(self.t) - 1)
        if k <= self.k:
            return
        n, n_p = k - self.k, self.cloud.shape[0]
        normals = rng.standard_normal((n, n_p, 2))
        rayleigh = rng.rayleigh(1.0, (n, n_p))
        _advance(
            self.k,
            k,
            self.t,
            self.acc,
            self.gyr,
            self.mask,
            self.bg,
            self.q,
            self.v,
            self.p,
            self.f_n,
            self.ba,
            self.cov,
            self.noise,
            self.side,
            self.cloud,
            normals,
            rayleigh,
            self.drift_scale,
            self.drift_offset,
            self.position,
            self.velocity,
            self.quaternion,
            self.position_std,
            *self._work,
        )
        self.k = k

    def set_cloud(self, cloud: NDArray[np.float64]) -> None:
        """Replace the particles (after a PF update) and rewrite the current sample's mean and std."""
        self.cloud = np.ascontiguousarray(cloud, float)
        self.position[self.k, :2] = self.cloud.mean(axis=0)
        self.position_std[self.k, :2] = self.cloud.std(axis=0)
