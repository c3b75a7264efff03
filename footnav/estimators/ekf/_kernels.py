"""Compiled kernels of the error-state filter: covariance prediction and closed-loop feedback.

Per foot, the error state is ``dx = [dphi, dv, dp]`` (9 states: attitude, velocity, position in
the nav frame; Zhao et al. (2019), eq. 1-3) or ``[dphi, dv, dp, dba, dbg]`` (15 states, adding the
accelerometer and gyroscope bias errors). With C^ = (I - [dphi x]) C, dv = v^ - v, dp = p^ - p and
db = b^ - b, the continuous error model is::

    d(dphi)/dt = C^ dbg,   d(dv)/dt = [f^n x] dphi - C^ dba,   d(dp)/dt = dv,   d(db)/dt = w_b

discretised per sample as F = I + A dt with Q = diag(sigma_g^2, sigma_a^2, 0, sigma_ba^2,
sigma_bg^2) dt from noise *densities*, so the filter behaves the same at any sampling rate.
A takes f^n and C at the start of the interval. The exact linearisation of the Simpson /
trapezoid step of :mod:`footnav.nav.mechanization` (velocity row [dv_f x] with the step's
specific-force increment dv_f, position row dt/2 [dv_f x]) differs by O(dt) per sample, which
telescopes over a step. Tried (Nov 2026): 9-state results changed by < 0.5 %; 15-state ones
either way (simulator: forward ATE -5 %, smoothed ATE -2 to +12 %; real recordings: -54 % to
+25 % per recording, mean ATE within 2 %), so F stays as it is.
Measurements (a ZUPT ``v^ = 0`` in stance, an optional zero angular rate ``w^ = 0``, and any
position measurement a fusion makes) update ``dx``, which is fed back into the nominal state and
reset to zero (closed loop, Chistyakov et al. (2021), Alg. 1).

Every kernel works in place on one foot's block at offset ``o`` of the joint state, so that two
feet share one covariance at the cost of one. The measurement update is footnav's one Kalman
kernel, :func:`footnav.nav.kalman.update3`, shared with ``madgwick``.
"""

from __future__ import annotations

import numpy as np

from footnav._numba import njit  # numba.njit that survives a read-only install
from footnav.nav.quaternion import from_rotvec_nb

__all__ = ["feedback", "feedback_all", "predict_cov"]


@njit(cache=True, inline="always", error_model="numpy")
def _f_rows(cov, o, n, j, x, y, z, c, dt):
    """Column j of the foot's rows of P <- F P, in place (``S = [f^n dt x]``, see the module
    docstring): attitude += dt C dbg (15 states), velocity += S attitude - dt C dba, position +=
    dt velocity, each from the values before the step."""
    a0, a1, a2 = cov[o, j], cov[o + 1, j], cov[o + 2, j]
    v0, v1, v2 = cov[o + 3, j], cov[o + 4, j], cov[o + 5, j]
    cov[o + 3, j] = v0 - z * a1 + y * a2
    cov[o + 4, j] = v1 + z * a0 - x * a2
    cov[o + 5, j] = v2 - y * a0 + x * a1
    cov[o + 6, j] += dt * v0
    cov[o + 7, j] += dt * v1
    cov[o + 8, j] += dt * v2
    if n == 15:
        b0, b1, b2 = cov[o + 9, j], cov[o + 10, j], cov[o + 11, j]
        g0, g1, g2 = cov[o + 12, j], cov[o + 13, j], cov[o + 14, j]
        for i in range(3):
            cov[o + i, j] += dt * (c[i, 0] * g0 + c[i, 1] * g1 + c[i, 2] * g2)
            cov[o + 3 + i, j] -= dt * (c[i, 0] * b0 + c[i, 1] * b1 + c[i, 2] * b2)


@njit(cache=True, inline="always", error_model="numpy")
def _f_cols(cov, o, n, i, x, y, z, c, dt):
    """Row i of the foot's columns of P <- P F', in place (the transpose of :func:`_f_rows`)."""
    a0, a1, a2 = cov[i, o], cov[i, o + 1], cov[i, o + 2]
    v0, v1, v2 = cov[i, o + 3], cov[i, o + 4], cov[i, o + 5]
    cov[i, o + 3] = v0 - z * a1 + y * a2
    cov[i, o + 4] = v1 + z * a0 - x * a2
    cov[i, o + 5] = v2 - y * a0 + x * a1
    cov[i, o + 6] += dt * v0
    cov[i, o + 7] += dt * v1
    cov[i, o + 8] += dt * v2
    if n == 15:
        b0, b1, b2 = cov[i, o + 9], cov[i, o + 10], cov[i, o + 11]
        g0, g1, g2 = cov[i, o + 12], cov[i, o + 13], cov[i, o + 14]
        for r in range(3):
            cov[i, o + r] += dt * (c[r, 0] * g0 + c[r, 1] * g1 + c[r, 2] * g2)
            cov[i, o + 3 + r] -= dt * (c[r, 0] * b0 + c[r, 1] * b1 + c[r, 2] * b2)


@njit(cache=True, error_model="numpy")
def predict_cov(cov, o, n, f_n, c, dt, q_diag):
    """P <- F P F' + Q dt for one foot's block at offset ``o`` of the joint covariance, in place.

    F differs from I only in the foot's rows, so F P changes only those rows, and (F P) F' only
    the foot's columns, which outside the foot's own block are the transposed rows just computed
    (P stays exactly symmetric). O(N n) instead of the O(N^3) of a dense product.
    """
    big = cov.shape[0]
    x, y, z = f_n[0] * dt, f_n[1] * dt, f_n[2] * dt
    for j in range(big):
        _f_rows(cov, o, n, j, x, y, z, c, dt)
    for i in range(o, o + n):
        _f_cols(cov, o, n, i, x, y, z, c, dt)
    for a in range(n):
        for b in range(a):  # the block's lower triangle from its upper one
            cov[o + a, o + b] = cov[o + b, o + a]
        cov[o + a, o + a] += q_diag[a] * dt
    for i in range(big):
        if i < o or i >= o + n:
            for a in range(n):
                cov[i, o + a] = cov[o + a, i]


@njit(cache=True, error_model="numpy")
def feedback(q, v, p, ba, bg, f, dx, o, n, dq, q_tmp):
    """Closed-loop reset of foot ``f`` (rows of the per-foot state arrays) by the error ``dx``
    at ``o``: C <- (I + [dphi x]) C^, v -= dv, p -= dp, b -= db. The arrays are passed whole:
    a row view per call costs reference counting in the per-sample loop."""
    from_rotvec_nb(dx[o], dx[o + 1], dx[o + 2], dq)
    w, x, y, z = q[f, 0], q[f, 1], q[f, 2], q[f, 3]
    q_tmp[0] = dq[0] * w - dq[1] * x - dq[2] * y - dq[3] * z
    q_tmp[1] = dq[0] * x + dq[1] * w + dq[2] * z - dq[3] * y
    q_tmp[2] = dq[0] * y - dq[1] * z + dq[2] * w + dq[3] * x
    q_tmp[3] = dq[0] * z + dq[1] * y - dq[2] * x + dq[3] * w
    norm = np.sqrt(q_tmp[0] * q_tmp[0] + q_tmp[1] * q_tmp[1] + q_tmp[2] * q_tmp[2] + q_tmp[3] * q_tmp[3])
    for i in range(4):
        q[f, i] = q_tmp[i] / norm
    for i in range(3):
        v[f, i] -= dx[o + 3 + i]
        p[f, i] -= dx[o + 6 + i]
        if n == 15:
            ba[f, i] -= dx[o + 9 + i]
            bg[f, i] -= dx[o + 12 + i]


@njit(cache=True, error_model="numpy")
def feedback_all(q, v, p, ba, bg, dx, n, dq, q_tmp):
    """Feed the whole error state ``dx`` of an update back into every foot (Sola (2017),
    sec. 6.2): a fusion's measurement of the joint state, which moves the whole covariance
    (P - K H P)."""
    for g in range(len(p)):
        feedback(q, v, p, ba, bg, g, dx, g * n, n, dq, q_tmp)
