"""A step-able error-state ZUPT-aided INS for one foot or two feet in one joint filter.

Per foot, the error state is ``dx = [dphi, dv, dp]`` (9 states: attitude, velocity, position in
the nav frame; Zhao et al. (2019), eq. 1-3) or ``[dphi, dv, dp, dba, dbg]`` (15 states, adding the
accelerometer and gyroscope bias errors). With C^ = (I - [dphi x]) C, dv = v^ - v, dp = p^ - p and
db = b^ - b, the continuous error model is::

    d(dphi)/dt = C^ dbg,   d(dv)/dt = [f^n x] dphi - C^ dba,   d(dp)/dt = dv,   d(db)/dt = w_b

discretised per sample as F = I + A dt with Q = diag(sigma_g^2, sigma_a^2, 0, sigma_ba^2,
sigma_bg^2) dt from noise *densities*, so the filter behaves the same at any sampling rate.
A takes f^n and C at the start of the interval. The exact linearisation of the Simpson /
trapezoid step of :mod:`footnav.core.mechanization` (velocity row [dv_f x] with the step's
specific-force increment dv_f, position row dt/2 [dv_f x]) differs by O(dt) per sample, which
telescopes over a step. Tried (Nov 2026): 9-state results changed by < 0.5 %; 15-state ones
either way (simulator: forward ATE -5 %, smoothed ATE -2 to +12 %; real recordings: -54 % to
+25 % per recording, mean ATE within 2 %), so F stays as it is.
Measurements (a ZUPT ``v^ = 0`` in stance, an optional zero angular rate ``w^ = 0``, and any
position measurement a fusion makes) update ``dx``, which is fed back into the nominal state and
reset to zero (closed loop, Chistyakov et al. (2021), Alg. 1).

Two feet share one covariance: each foot's samples are processed in time order, and a
measurement that links the feet (Zhao et al. (2019), eq. 7) updates both. :class:`InsFilter` runs the
compiled per-sample loop between the points where a caller wants to act (:meth:`run_until`) and
keeps checkpoints (state and covariance) every ``MAX_SEGMENT_EVENTS`` samples and where the
caller updates, so that :mod:`footnav.core.smoothing` can smooth the run afterwards in memory that
grows with the number of steps (plus a bounded cache of the latest segments' records), not of
samples.

One compiled function, :func:`_run`, does all the per-sample work: filtering, recording what the
smoother needs (per sample f^n dt, dt and, with bias states, C; per update K, y and S^-1 y, not
the covariance), step-wise smoothing at each step end, and the whole-walk smoother's recording,
replay and backward pass of one segment. One entry point keeps the first call's compilation
short: each compiled caller would re-optimise the loop it calls.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import NamedTuple

import numpy as np
from numpy.typing import NDArray

from footnav.core._numba import njit  # numba.njit that survives a read-only install
from footnav.core.buffers import staggered
from footnav.core.errors import InvalidInputError
from footnav.core.mechanization import strapdown_step
from footnav.core.quaternion import as_matrix_nb, from_rotvec_nb, multiply_nb, normalize_nb

__all__ = ["InsFilter", "FilterNoise", "Checkpoint", "ATT", "VEL", "POS", "ACC_BIAS", "GYR_BIAS", "empty_record", "Work", "work"]

#: Offsets of the blocks of one foot's error state.
ATT, VEL, POS, ACC_BIAS, GYR_BIAS = 0, 3, 6, 9, 12

#: Largest number of samples between two checkpoints (and in a step-wise smoother's buffer):
#: bounds the smoother's buffers when a foot stands still for minutes.
MAX_SEGMENT_EVENTS = 4096



#: Chi-square gate of the zero-angular-rate update: 3 degrees of freedom, 99.9 %.
ZARU_GATE = 16.27

# run loop stop reasons
_DONE, _STEP_END, _FULL = 0, 1, 2


@dataclass(frozen=True)
class FilterNoise:
    """Noise of the filter, SI units; densities are per sqrt(Hz) and scaled with dt."""

    acc_mps2_sqrthz: float
    gyr_radps_sqrthz: float
    zupt_std_mps: float
    acc_bias_walk_mps3_sqrthz: float = 0.0
    gyr_bias_walk_radps2_sqrthz: float = 0.0
    zaru_std_radps: float = 0.0  # 0: no zero-angular-rate update

    def q_diag(self, n: int) -> NDArray[np.float64]:
        """Diagonal of Q / dt for one foot's n states."""
        q = np.zeros(n)
        q[ATT : ATT + 3] = self.gyr_radps_sqrthz**2
        q[VEL : VEL + 3] = self.acc_mps2_sqrthz**2
        if n == 15:
            q[ACC_BIAS : ACC_BIAS + 3] = self.acc_bias_walk_mps3_sqrthz**2
            q[GYR_BIAS : GYR_BIAS + 3] = self.gyr_bias_walk_radps2_sqrthz**2
        return q


@dataclass
class Checkpoint:
    """Filter state after every update at one instant: where the smoother restarts the run."""

    n_events: int  # events processed before this checkpoint (over both feet)
    k: NDArray[np.int64]
    q: NDArray[np.float64]
    v: NDArray[np.float64]
    p: NDArray[np.float64]
    ba: NDArray[np.float64]
    bg: NDArray[np.float64]
    f_n: NDArray[np.float64]
    cov: NDArray[np.float64]
    step_end: bool  # a foot's stance ended here (with ``InsFilter.step_stops``)
    #: measurement updates applied at this instant after the per-sample ones, in order, as
    #: (H, K, S^-1 y, y): what the smoother needs to undo them backwards
    updates: list = field(default_factory=list)


class Work(NamedTuple):
    """Scratch of the compiled loop, allocated once per filter in Python: an allocation in the
    loop would cost per call, and one with a constant shape a numpy helper compiled per shape."""

    c: NDArray[np.float64]  # (3, 3) C for the bias columns of F
    c_next: NDArray[np.float64]  # (3, 3) the strapdown's rotation matrix
    dq: NDArray[np.float64]  # (4,)
    q_tmp: NDArray[np.float64]  # (4,)
    a_prev: NDArray[np.float64]  # (3,) bias-corrected specific force and angular rate, k-1 and k
    w_prev: NDArray[np.float64]
    a_cur: NDArray[np.float64]
    w_cur: NDArray[np.float64]
    f_prev: NDArray[np.float64]  # (3,) f^n at the start of the interval
    y: NDArray[np.float64]  # (6,) ZUPT and ZARU innovations
    sy: NDArray[np.float64]  # (3,) S^-1 y of the ZUPT
    sy_z: NDArray[np.float64]  # (3,) and of the ZARU
    dx: NDArray[np.float64]  # (N,) correction
    gain: NDArray[np.float64]  # (N, 3) K of the ZUPT
    gain_z: NDArray[np.float64]  # (N, 3) and of the ZARU
    hp: NDArray[np.float64]  # (3, N) H P
    kt: NDArray[np.float64]  # (rows,) the backward pass's S^-1 y - K' mu
    offset: NDArray[np.float64]  # (feet, 3) the step-wise smoother's position chaining
    seen: NDArray[np.float64]  # (feet,)


def work(big: int, n_feet: int, rows: int = 6) -> Work:
    """Scratch for a filter with ``big`` error states over ``n_feet`` feet, caller updates of up
    to ``rows`` rows."""
    z = np.zeros
    return Work(
        z((3, 3)), z((3, 3)), z(4), z(4), z(3), z(3), z(3), z(3), z(3), z(6), z(3), z(3),
        z(big), z((big, 3)), z((big, 3)), z((3, big)), z(max(rows, 6)), z((n_feet, 3)), z(n_feet),
    )


# -- compiled kernels ---------------------------------------------------------------------------


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
def _predict_cov(cov, o, n, f_n, c, dt, q_diag):
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


@njit(cache=True, inline="always", error_model="numpy")
def sym3_inverse(a, b, c, d, e, f):
    """Inverse of the symmetric [[a b c] [b d e] [c e f]] by cofactors: (i00, i01, i02, i11, i12,
    i22, det); the entries are undefined when det <= 0 (not positive definite)."""
    i00 = d * f - e * e
    i01 = c * e - b * f
    i02 = b * e - c * d
    det = a * i00 + b * i01 + c * i02
    inv = 1.0 / det if det != 0.0 else 0.0
    return (i00 * inv, i01 * inv, i02 * inv, (a * f - c * c) * inv, (b * c - a * e) * inv, (a * d - b * b) * inv, det)


@njit(cache=True, error_model="numpy")
def _update3(cov, dx, o, y0, y1, y2, r, gate, gain, sy, hp):
    """Kalman update with a measurement of the 3 states at ``o``: ``y = dx[o:o+3] + noise``,
    noise variance ``r`` (each axis); H is a selection, so S is a 3 x 3 block of P plus r I,
    inverted by cofactors.

    K = P H' S^-1 (written to ``gain`` (N, 3)), dx = K y, S^-1 y (to ``sy`` (3,)), P <- P - K H P,
    both triangles from one value (exactly symmetric). ``hp`` (3, N) is scratch.
    Returns False (and changes nothing) when S is not positive definite or the normalised
    innovation squared y' S^-1 y exceeds ``gate`` (a chi-square gate; inf: none).
    """
    big = cov.shape[0]
    i00, i01, i02, i11, i12, i22, det = sym3_inverse(
        cov[o, o] + r, cov[o, o + 1], cov[o, o + 2], cov[o + 1, o + 1] + r, cov[o + 1, o + 2], cov[o + 2, o + 2] + r
    )
    if not det > 0.0:
        return False
    s0 = i00 * y0 + i01 * y1 + i02 * y2
    s1 = i01 * y0 + i11 * y1 + i12 * y2
    s2 = i02 * y0 + i12 * y1 + i22 * y2
    if y0 * s0 + y1 * s1 + y2 * s2 > gate:
        return False
    sy[0], sy[1], sy[2] = s0, s1, s2
    for j in range(big):
        h0, h1, h2 = cov[o, j], cov[o + 1, j], cov[o + 2, j]  # H P = P H' (symmetric)
        hp[0, j], hp[1, j], hp[2, j] = h0, h1, h2
        gain[j, 0] = h0 * i00 + h1 * i01 + h2 * i02
        gain[j, 1] = h0 * i01 + h1 * i11 + h2 * i12
        gain[j, 2] = h0 * i02 + h1 * i12 + h2 * i22
        dx[j] = h0 * s0 + h1 * s1 + h2 * s2
    for i in range(big):
        g0, g1, g2 = gain[i, 0], gain[i, 1], gain[i, 2]
        for j in range(i, big):
            val = cov[i, j] - g0 * hp[0, j] - g1 * hp[1, j] - g2 * hp[2, j]
            cov[i, j] = val
            cov[j, i] = val
    return True


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


# -- the backward (smoothing) pass ----------------------------------------------------------------


@njit(cache=True, inline="always", error_model="numpy")
def _ft_apply(mu, o, n, x, y, z, c, e, dt):
    """mu <- F' mu on one foot's block starting at ``o`` (``c[e]``: C of the transition)."""
    a0, a1, a2 = mu[o], mu[o + 1], mu[o + 2]
    v0, v1, v2 = mu[o + 3], mu[o + 4], mu[o + 5]
    # F' has S' = -S in the attitude row, dt I in the velocity row
    mu[o] = a0 + z * v1 - y * v2
    mu[o + 1] = a1 - z * v0 + x * v2
    mu[o + 2] = a2 + y * v0 - x * v1
    mu[o + 3] = v0 + dt * mu[o + 6]
    mu[o + 4] = v1 + dt * mu[o + 7]
    mu[o + 5] = v2 + dt * mu[o + 8]
    if n == 15:
        for j in range(3):
            mu[o + 9 + j] -= dt * (c[e, 0, j] * v0 + c[e, 1, j] * v1 + c[e, 2, j] * v2)
            mu[o + 12 + j] += dt * (c[e, 0, j] * a0 + c[e, 1, j] * a1 + c[e, 2, j] * a2)


@njit(cache=True, inline="always", error_model="numpy")
def _finv_apply(d, o, n, x, y, z, c, e, dt):
    """d <- F^-1 d on one foot's block starting at ``o``: F is unit block-triangular, so its
    inverse is back-substitution (attitude, then velocity, then position; biases unchanged)."""
    if n == 15:
        for i in range(3):
            d[o + i] -= dt * (c[e, i, 0] * d[o + 12] + c[e, i, 1] * d[o + 13] + c[e, i, 2] * d[o + 14])
            d[o + 3 + i] += dt * (c[e, i, 0] * d[o + 9] + c[e, i, 1] * d[o + 10] + c[e, i, 2] * d[o + 11])
    a0, a1, a2 = d[o], d[o + 1], d[o + 2]
    d[o + 3] -= -z * a1 + y * a2
    d[o + 4] -= z * a0 - x * a2
    d[o + 5] -= -y * a0 + x * a1
    d[o + 6] -= dt * d[o + 3]
    d[o + 7] -= dt * d[o + 4]
    d[o + 8] -= dt * d[o + 5]


@njit(cache=True, error_model="numpy")
def _smooth_back(used, chain, cov, mu, d, n, n_feet, q_diag, rec, out_q, out_v, out_p, sm_q, sm_v, sm_p, ws):
    """Bryson-Frazier backward pass over the recorded events ``used - 1`` down to 0.

    Each event's smoothed sample is its filtered output corrected by ``-d``, where ``d = P mu``
    is the smoothed minus the filtered error state. Going back through an update (K, y,
    S^-1 y): ``d <- d + K y``, ``mu <- mu + H' (S^-1 y - K' mu)``; through a transition:
    ``d <- F^-1 (d - Q mu)``, ``mu <- F' mu`` (from ``d = P mu``, P- = F P+ F' + Q and
    P+ = P- - K H P-). So no covariance is stored per sample.

    ``chain`` False (one segment of the whole-walk smoother): ``mu`` is the adjoint after the
    last event, and ``d = cov mu`` with ``cov`` the covariance there. ``chain`` True (one step
    of the step-wise smoother, OpenShoe's smoothed variant): mu = 0 at the step's end, and each
    foot's positions are chained to where its previous step's smoothing left it (position is
    an integral: the step's smoothed displacement is added to its smoothed start). On return,
    ``mu`` and ``d`` are those before the first event.
    """
    ev_foot, ev_k, ev_fdt, ev_dt, ev_c, ev_nu, ev_base, ev_gain, ev_sy, ev_y = rec
    big = len(mu)
    kt, dq, q_tmp = ws.kt, ws.dq, ws.q_tmp
    for i in range(big):
        if chain:
            mu[i] = 0.0
            d[i] = 0.0
        else:
            acc = 0.0
            for j in range(big):
                acc += cov[i, j] * mu[j]
            d[i] = acc
    for e in range(used - 1, -1, -1):
        nu = ev_nu[e]
        o = ev_foot[e] * n
        if nu >= 0:  # a sample: its smoothed output, then back through its updates and transition
            k = ev_k[e]
            from_rotvec_nb(d[o], d[o + 1], d[o + 2], dq)
            multiply_nb(dq, out_q[k], q_tmp)
            normalize_nb(q_tmp)
            for i in range(4):
                sm_q[k, i] = q_tmp[i]
            for i in range(3):
                sm_v[k, i] = out_v[k, i] - d[o + 3 + i]
                sm_p[k, i] = out_p[k, i] - d[o + 6 + i]
        # the updates, last first: a sample's nu 3-state selections (none when nu = 0; K in
        # columns 3u:3u+3), or a caller's update between samples of m = -nu rows (K in columns
        # 0:m, H' in m:2m). Rows of an event without updates hold stale values: never read.
        m = 3 if nu >= 0 else -nu
        for u in range((nu if nu >= 0 else 1) - 1, -1, -1):
            col = 3 * u
            for a in range(m):
                acc = ev_sy[e, col + a]
                for i in range(big):
                    acc -= ev_gain[e, i, col + a] * mu[i]
                kt[a] = acc
            for i in range(big):
                acc = 0.0
                for a in range(m):
                    acc += ev_gain[e, i, col + a] * ev_y[e, col + a]
                d[i] += acc
            if nu < 0:
                for i in range(big):
                    acc = 0.0
                    for a in range(m):
                        acc += ev_gain[e, i, m + a] * kt[a]
                    mu[i] += acc
            else:
                for a in range(m):
                    mu[ev_base[e, u] + a] += kt[a]
        if nu < 0:
            continue
        dt = ev_dt[e]
        for i in range(n):
            d[o + i] -= q_diag[i] * dt * mu[o + i]
        x, y, z = ev_fdt[e, 0], ev_fdt[e, 1], ev_fdt[e, 2]
        _finv_apply(d, o, n, x, y, z, ev_c, e, dt)
        _ft_apply(mu, o, n, x, y, z, ev_c, e, dt)
    if chain:
        # d is now P mu before the step; a foot's first event in it follows its start sample
        offset, seen = ws.offset, ws.seen
        for f in range(n_feet):
            seen[f] = 0.0
        for e in range(used):
            f = ev_foot[e]
            if ev_nu[e] >= 0 and seen[f] == 0.0:
                seen[f] = 1.0
                k0 = ev_k[e] - 1
                for i in range(3):
                    offset[f, i] = d[f * n + 6 + i] + sm_p[k0, i] - out_p[k0, i]
        for e in range(used):
            if ev_nu[e] >= 0:
                f, k = ev_foot[e], ev_k[e]
                for i in range(3):
                    sm_p[k, i] += offset[f, i]


# -- the forward loop -------------------------------------------------------------------------------


@njit(cache=True, error_model="numpy")
def _next_foot(t, k, stop_at, t_stop):
    """The foot whose next sample comes first at or before ``t_stop``, or -1. A function of its
    own: an ``f = -1`` in the loop made numba compile the kernels ``f`` reaches once more, for the
    literal -1."""
    f = -1
    best = np.inf
    for g in range(len(k)):
        if k[g] < stop_at[g]:
            tn = t[k[g] + 1]
            if tn <= t_stop and tn < best:
                best = tn
                f = g
    return f

#: What a call of :func:`_run` does besides filtering.
MODE_FILTER, MODE_STEP, MODE_WHOLE, MODE_CLOSE, MODE_RECORD, MODE_BACK = 0, 1, 2, 3, 4, 5


@njit(cache=True, error_model="numpy")
def _run(
    t, acc, gyr, stance, stop_at, k, t_stop, max_events, step_stops,
    q, v, p, ba, bg, f_n, cov, n, q_diag, r_zupt, r_zaru,
    out_q, out_v, out_p, out_pcov,
    mode, rec, sm, fill, mu, d, ws,
):
    """Advance the feet through their samples with t <= t_stop, in time order.

    Foot f owns samples ``k[f] + 1 .. stop_at[f]`` of the concatenated arrays (``k[f]`` is its
    last processed sample). ``mode``:

    * ``MODE_FILTER``: filter only.
    * ``MODE_STEP``: also record each event at ``fill[0]`` of ``rec``; where a foot's stance ends
      (or ``rec`` is full) smooth the recorded step into ``sm`` (:func:`_smooth_back`).
    * ``MODE_WHOLE``: record from 0, then ``d = P mu`` and the backward pass over what was
      recorded, leaving ``mu``, ``d`` of the first event's predecessor (one segment of the
      whole-walk smoother).
    * ``MODE_CLOSE``: no filtering; smooth the recorded open step now.
    * ``MODE_RECORD``: record each event at ``fill[0]`` of ``rec``, nothing more (the forward
      run keeps its segments for the whole-walk smoother; ``max_events`` keeps within ``rec``).
    * ``MODE_BACK``: no filtering; ``d = P mu`` with the given covariance and the backward pass
      over the ``fill[0]`` recorded events (a kept segment of the whole-walk smoother).

    Returns (reason, events): reason 0 nothing left before t_stop, 1 a foot's stance just ended
    (only with ``step_stops``), 2 ``max_events`` processed.
    """
    n_feet = len(k)
    big = cov.shape[0]
    ev_foot, ev_k, ev_fdt, ev_dt, ev_c, ev_nu, ev_base, ev_gain, ev_sy, ev_y = rec
    sm_q, sm_v, sm_p = sm
    capacity = len(ev_k)
    c, c_next, dq, q_tmp, f_prev = ws.c, ws.c_next, ws.dq, ws.q_tmp, ws.f_prev
    a_prev, w_prev, a_cur, w_cur = ws.a_prev, ws.w_prev, ws.a_cur, ws.w_cur
    y, sy, sy_z, dx, gain, gain_z, hp = ws.y, ws.sy, ws.sy_z, ws.dx, ws.gain, ws.gain_z, ws.hp
    step = mode == MODE_STEP or mode == MODE_CLOSE  # a variable, not a literal: one compiled pass
    if mode == MODE_CLOSE or mode == MODE_BACK:
        _smooth_back(fill[0], step, cov, mu, d, n, n_feet, q_diag, rec, out_q, out_v, out_p, sm_q, sm_v, sm_p, ws)
        fill[0] = 0
        return _DONE, 0
    record = mode == MODE_STEP or mode == MODE_WHOLE or mode == MODE_RECORD
    if mode == MODE_WHOLE:
        fill[0] = 0
    events = 0
    reason = _FULL
    while events < max_events:
        f = _next_foot(t, k, stop_at, t_stop)
        if f < 0:
            reason = _DONE
            break
        o = f * n
        kp = k[f]
        kn = kp + 1
        k[f] = kn
        for i in range(3):
            a_prev[i] = acc[kp, i] - ba[f, i]
            w_prev[i] = gyr[kp, i] - bg[f, i]
            a_cur[i] = acc[kn, i] - ba[f, i]
            w_cur[i] = gyr[kn, i] - bg[f, i]
        dt = t[kn] - t[kp]
        # F uses the attitude (bias columns only) and specific force at the start of the interval
        if n == 15:
            as_matrix_nb(q[f], c)
        fx, fy, fz = f_n[f, 0], f_n[f, 1], f_n[f, 2]
        f_prev[0], f_prev[1], f_prev[2] = fx, fy, fz  # strapdown_step overwrites f_n[f] with f^n(k)
        strapdown_step(q, v, p, f_n, f, a_prev, w_prev, a_cur, w_cur, dt, dq, q_tmp, c_next)
        _predict_cov(cov, o, n, f_prev, c, dt, q_diag)
        nu = 0
        if stance[kn]:
            # ZUPT: z = v^ - 0 = dv + noise
            y[0], y[1], y[2] = v[f, 0], v[f, 1], v[f, 2]
            if _update3(cov, dx, o + VEL, y[0], y[1], y[2], r_zupt, np.inf, gain, sy, hp):
                feedback(q, v, p, ba, bg, f, dx, o, n, dq, q_tmp)
                nu = 1
            # zero angular rate, after the ZUPT (sequential updates with R block-diagonal equal
            # the joint one): w^ = w - bg^, so -w^ = dbg + noise. Skipped when the rate is
            # implausible for a still foot (chi-square gate): a detected stance is not always
            # still, and real rotation would be taken for gyro bias
            if r_zaru > 0.0 and n == 15 and nu == 1:
                for i in range(3):
                    y[3 + i] = bg[f, i] - gyr[kn, i]
                if _update3(cov, dx, o + GYR_BIAS, y[3], y[4], y[5], r_zaru, ZARU_GATE, gain_z, sy_z, hp):
                    feedback(q, v, p, ba, bg, f, dx, o, n, dq, q_tmp)
                    nu = 2
        if record:
            e = fill[0]
            if e == capacity:  # a full buffer: the step is cut here (MODE_STEP only)
                _smooth_back(e, step, cov, mu, d, n, n_feet, q_diag, rec, out_q, out_v, out_p, sm_q, sm_v, sm_p, ws)
                e = 0
            ev_foot[e] = f
            ev_k[e] = kn
            ev_dt[e] = dt
            ev_fdt[e, 0], ev_fdt[e, 1], ev_fdt[e, 2] = fx * dt, fy * dt, fz * dt
            if n == 15:
                for i in range(3):
                    for j in range(3):
                        ev_c[e, i, j] = c[i, j]
            ev_nu[e] = nu
            for u in range(nu):
                ev_base[e, u] = o + (VEL if u == 0 else GYR_BIAS)
            for a in range(3 * nu):
                ev_y[e, a] = y[a]
            if nu > 0:
                for a in range(3):
                    ev_sy[e, a] = sy[a]
                    for i in range(big):
                        ev_gain[e, i, a] = gain[i, a]
            if nu > 1:
                for a in range(3):
                    ev_sy[e, 3 + a] = sy_z[a]
                    for i in range(big):
                        ev_gain[e, i, 3 + a] = gain_z[i, a]
            fill[0] = e + 1
        for i in range(4):
            out_q[kn, i] = q[f, i]
        for i in range(3):
            out_v[kn, i] = v[f, i]
            out_p[kn, i] = p[f, i]
        out_pcov[kn, 0] = cov[o + POS, o + POS]
        out_pcov[kn, 1] = cov[o + POS, o + POS + 1]
        out_pcov[kn, 2] = cov[o + POS + 1, o + POS + 1]
        out_pcov[kn, 3] = cov[o + POS + 2, o + POS + 2]
        events += 1
        if stance[kn] and kn < stop_at[f] and not stance[kn + 1]:  # the foot's stance ends: a step
            if mode == MODE_STEP:
                _smooth_back(fill[0], step, cov, mu, d, n, n_feet, q_diag, rec, out_q, out_v, out_p, sm_q, sm_v, sm_p, ws)
                fill[0] = 0
            if step_stops:
                reason = _STEP_END
                break
    if mode == MODE_WHOLE:
        _smooth_back(fill[0], step, cov, mu, d, n, n_feet, q_diag, rec, out_q, out_v, out_p, sm_q, sm_v, sm_p, ws)
    return reason, events


# -- the step-able filter -------------------------------------------------------------------------


#: Place of the record's arrays in :func:`footnav.core.buffers.staggered`'s pattern, after the
#: filter's eight per-sample arrays.
RECORD_PLACE = 8
#: Place of the smoothed copies, after the record's ten arrays.
SMOOTHED_PLACE = RECORD_PLACE + 10


def empty_record(big: int, n: int = 0, columns: int = 6, *, zero: bool = True) -> tuple:
    """Buffers of :func:`_run`'s record for ``n`` events of a filter with ``big`` error states
    and ``columns`` gain columns: 3 per update at a sample (3 for a ZUPT, 6 with the ZARU), 2 m
    for a caller's update of m rows (K and H'). Narrow rows keep the backward pass's reads of K
    contiguous. ``zero=False`` leaves them uninitialised (the loop writes an event before the
    backward pass reads it)."""
    i8, f8 = np.int64, np.float64
    cols = max(3, columns)
    return tuple(staggered([
        ((n,), i8),  # foot
        ((n,), i8),  # global sample index
        ((n, 3), f8),  # f^n dt at the start of the interval
        ((n,), f8),  # dt
        ((n, 3, 3), f8),  # C at the start of the interval (bias states only)
        ((n,), i8),  # updates at the sample: 0, 1 (ZUPT), 2 (and ZARU); -m a caller's
        ((n, 2), i8),  # first error state of each update's 3-block
        ((n, big, cols), f8),  # K, three columns per update; a caller's: K then H'
        ((n, cols), f8),  # S^-1 y (two updates of 3 at a sample, or a caller's)
        ((n, cols), f8),  # y
    ], zero=zero, first=RECORD_PLACE))


class InsFilter:
    """Error-state ZUPT-aided INS over one or two feet, advanced by the caller.

    Build it with :meth:`footnav.estimators.ekf.EkfEstimator.start`. The caller advances it with
    :meth:`run_until` (the compiled loop: strapdown, covariance prediction, ZUPT in stance),
    reads the current state (:meth:`position`, :meth:`velocity`, :meth:`quaternion`,
    :attr:`covariance`), applies its own measurements (:meth:`update`, :meth:`update_position`)
    between runs, and collects the per-sample results with :meth:`outputs`. Full segments, the
    instants of the caller's updates and (with :attr:`step_stops`) step ends leave a
    :class:`Checkpoint` for the smoother.

    Attributes
    ----------
    n_states
        States per foot (9 or 15).
    n_feet
        1 or 2; foot ``f``'s error states are ``f * n_states`` to ``(f + 1) * n_states``.
    step_stops
        Return from :meth:`run_until` (leaving a checkpoint) at every step end; off by default,
        as nothing in footnav needs it: for a caller that inspects the filter step by step.
    step_smoother
        A :class:`footnav.core.smoothing.StepSmoother` smoothing each step as the filter runs,
        or None.
    """

    def __init__(
        self,
        t: list[NDArray[np.float64]],
        acc: list[NDArray[np.float64]],
        gyr: list[NDArray[np.float64]],
        stance: list[NDArray[np.bool_]],
        start: list[int],
        q0: list[NDArray[np.float64]],
        p0: list[NDArray[np.float64]],
        bg0: list[NDArray[np.float64]],
        cov0_diag: NDArray[np.float64],
        noise: FilterNoise,
        n_states: int,
    ) -> None:
        self.n_feet = len(t)
        self.n_states = n_states
        self.noise = noise
        lengths = [len(x) for x in t]
        self._offsets = np.concatenate(([0], np.cumsum(lengths))).astype(np.int64)
        # one writable copy of the inputs for one foot or two (a read-only input would compile
        # every kernel a second time), in one buffer with the outputs (footnav.core.buffers: 4K
        # aliasing). Two buffers would let an unsmoothed result free the inputs, but ran the
        # step-wise smoother 0.42 -> 0.50 us/sample (10-min walk)
        total = int(self._offsets[-1])
        f8 = np.float64
        self._t, self._acc, self._gyr, self._stance, self._out_q, self._out_v, self._out_p, self._out_pcov = staggered(
            [((total,), f8), ((total, 3), f8), ((total, 3), f8), ((total,), np.bool_),
             ((total, 4), f8), ((total, 3), f8), ((total, 3), f8), ((total, 4), f8)]
        )
        for dst, src in ((self._t, t), (self._acc, acc), (self._gyr, gyr), (self._stance, stance)):
            np.concatenate(src, out=dst, casting="unsafe" if dst is self._stance else "same_kind")
        self._stop_at = self._offsets[1:] - 1
        self._start = np.array(start, dtype=np.int64)
        self._k = self._offsets[:-1] + self._start
        nf = self.n_feet
        self._q = np.array(q0, dtype=float).reshape(nf, 4).copy()
        self._v = np.zeros((nf, 3))
        self._p = np.array(p0, dtype=float).reshape(nf, 3).copy()
        self._ba = np.zeros((nf, 3))
        self._bg = np.array(bg0, dtype=float).reshape(nf, 3).copy()
        self._f_n = np.zeros((nf, 3))
        for f in range(nf):
            c = np.zeros((3, 3))
            as_matrix_nb(self._q[f], c)
            self._f_n[f] = c @ (self._acc[self._k[f]] - self._ba[f])
        big = nf * n_states
        self._cov = np.diag(np.tile(np.asarray(cov0_diag, float), nf))
        self._q_diag = noise.q_diag(n_states)
        for f in range(nf):  # samples up to the start hold the initial state
            a, k = self._offsets[f], self._k[f]
            self._out_q[a : k + 1] = self._q[f]
            self._out_v[a : k + 1] = 0.0
            self._out_p[a : k + 1] = self._p[f]
            o = f * n_states + POS
            self._out_pcov[a : k + 1] = [self._cov[o, o], self._cov[o, o + 1], self._cov[o + 1, o + 1], self._cov[o + 2, o + 2]]
        self._n_events = 0
        self._since_checkpoint = 0
        # the record and smoother arguments of a plain filtering call (not used by it)
        self._no_record = empty_record(big)
        self._no_sm = (np.zeros((0, 4)), np.zeros((0, 3)), np.zeros((0, 3)))
        self._no_fill = np.zeros(1, dtype=np.int64)
        self._no_vec = np.zeros(big)
        self._work = work(big, nf)
        self.step_smoother = None
        #: :class:`footnav.core.smoothing.SegmentRecords` when the forward run keeps its record
        #: for the whole-walk smoother, or None.
        self.segment_records = None
        self.step_stops = False
        #: Per-foot notes of whoever built the filter (the estimator's alignment).
        self.meta: list[dict] = [{} for _ in range(self.n_feet)]
        self.checkpoints: list[Checkpoint] = [self._checkpoint(step_end=False)]

    # -- reading the state --------------------------------------------------------------------
    @property
    def covariance(self) -> NDArray[np.float64]:
        """The joint error covariance (N, N) now; a copy."""
        return self._cov.copy()

    def block(self, foot: int, name: str) -> slice:
        """Slice of the joint error state holding ``foot``'s block ``name`` (att, vel, pos, acc_bias, gyr_bias)."""
        offsets = {"att": ATT, "vel": VEL, "pos": POS, "acc_bias": ACC_BIAS, "gyr_bias": GYR_BIAS}
        if name not in offsets or (offsets[name] >= 9 and self.n_states == 9):
            raise KeyError(f"no block {name!r} in a {self.n_states}-state filter")
        o = foot * self.n_states + offsets[name]
        return slice(o, o + 3)

    def index(self, foot: int) -> int:
        """Sample index (within the foot's own recording) of the foot's current state."""
        return int(self._k[foot] - self._offsets[foot])

    def start_index(self, foot: int) -> int:
        """Sample index (within the foot's own recording) where the foot's filter started."""
        return int(self._start[foot])

    def time(self, foot: int) -> float:
        return float(self._t[self._k[foot]])

    def position(self, foot: int) -> NDArray[np.float64]:
        return self._p[foot].copy()

    def velocity(self, foot: int) -> NDArray[np.float64]:
        return self._v[foot].copy()

    def quaternion(self, foot: int) -> NDArray[np.float64]:
        return self._q[foot].copy()

    def biases(self, foot: int) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Current accelerometer (m/s^2) and gyroscope (rad/s) bias estimates."""
        return self._ba[foot].copy(), self._bg[foot].copy()

    @property
    def finished(self) -> bool:
        return bool(np.all(self._k >= self._stop_at))

    # -- acting --------------------------------------------------------------------------------
    def _call(self, mode, k, stop_at, t_stop, max_events, step_stops, state, rec, sm, fill, mu, d):
        """One call of the compiled loop from ``state`` = (q, v, p, ba, bg, f_n, cov)."""
        return _run(
            self._t, self._acc, self._gyr, self._stance, stop_at, k, float(t_stop), int(max_events), bool(step_stops),
            *state, self.n_states, self._q_diag, self.noise.zupt_std_mps**2, self.noise.zaru_std_radps**2,
            self._out_q, self._out_v, self._out_p, self._out_pcov, mode, rec, sm, fill, mu, d, self._scratch(rec),
        )

    @property
    def record_columns(self) -> int:
        """Gain columns a sample's updates take in a smoother's record: 3 (the ZUPT), 6 when
        the zero-angular-rate update follows it."""
        return 6 if self.n_states == 15 and self.noise.zaru_std_radps > 0 else 3

    def _scratch(self, rec: tuple) -> Work:
        """The loop's scratch, widened when a record holds caller updates of more rows."""
        if len(self._work.kt) < rec[8].shape[1]:
            self._work = work(self._cov.shape[0], self.n_feet, rec[8].shape[1])
        return self._work

    def _state(self) -> tuple:
        return self._q, self._v, self._p, self._ba, self._bg, self._f_n, self._cov

    def run_until(self, t_stop: float = np.inf) -> None:
        """Process every sample with time <= ``t_stop`` (s) of each foot, in time order."""
        ss, sr = self.step_smoother, self.segment_records
        while True:
            # the buffers anew at each call: a checkpoint may hand the segment records a new one
            if ss is not None:
                mode, bufs = MODE_STEP, (ss.record, ss.smoothed, ss.fill, ss.mu, ss.d)
            elif sr is not None:
                mode, bufs = MODE_RECORD, (sr.record, self._no_sm, sr.fill, self._no_vec, self._no_vec)
            else:
                mode, bufs = MODE_FILTER, (self._no_record, self._no_sm, self._no_fill, self._no_vec, self._no_vec)
            # a checkpoint at least every MAX_SEGMENT_EVENTS: the smoother re-runs one at a time
            reason, events = self._call(
                mode, self._k, self._stop_at, t_stop, MAX_SEGMENT_EVENTS - self._since_checkpoint, self.step_stops,
                self._state(), *bufs,
            )
            self._n_events += events
            self._since_checkpoint += events
            # checkpoints where a step ends or a segment is full; a stop for the caller needs one
            # only if the caller then updates (see update): memory grows with steps, not with stops
            if events and reason != _DONE:
                self._add_checkpoint(step_end=reason == _STEP_END)
            if reason == _DONE:
                return

    def _add_checkpoint(self, step_end: bool) -> None:
        self.checkpoints.append(self._checkpoint(step_end=step_end))
        self._since_checkpoint = 0
        if self.segment_records is not None:  # before any update at this instant changes P
            self.segment_records.keep(len(self.checkpoints) - 1, self._cov)

    def close(self) -> None:
        """Leave a checkpoint at the current state (the smoother needs one after the last sample)."""
        if self._since_checkpoint:
            self._add_checkpoint(step_end=False)

    def close_step(self, smoother) -> None:
        """Smooth ``smoother``'s open step now (:class:`footnav.core.smoothing.StepSmoother`)."""
        self._call(
            MODE_CLOSE, self._k, self._stop_at, -np.inf, 0, False, self._state(),
            smoother.record, smoother.smoothed, smoother.fill, smoother.mu, smoother.d,
        )

    def update(
        self,
        h: NDArray[np.float64],
        innovation: NDArray[np.float64],
        r: NDArray[np.float64],
        *,
        gate: float | None = None,
    ) -> NDArray[np.float64] | None:
        """Linear measurement of the error state: ``innovation = h(x^) - z = H dx + noise``.

        Parameters
        ----------
        h
            H, (m, N) over the joint error state (see :meth:`block` for the columns).
        innovation
            h(x^) - z, (m,), in the measurement's units.
        r
            Measurement noise variance per component, (m,) or scalar, units squared.
        gate
            If given, skip the update (return None) when the normalised innovation squared
            y' S^-1 y exceeds it (a chi-square gate against outliers).

        Returns
        -------
        ndarray or None
            The correction dx that was fed back into the nominal states (and recorded for the
            smoother), or None when the gate rejected the measurement.
        """
        big = self._cov.shape[0]
        hm = np.atleast_2d(np.asarray(h, dtype=float))
        y = np.atleast_1d(np.asarray(innovation, dtype=float))
        m = len(y)
        r = np.broadcast_to(np.asarray(r, dtype=float), (m,))
        if hm.shape != (m, big) or not (np.all(np.isfinite(y)) and np.all(np.isfinite(hm)) and np.all(r > 0)):
            raise InvalidInputError(
                f"measurement update needs H of shape ({m}, {big}), finite innovations and positive variances; "
                f"got H {hm.shape}, innovation {y!r}, r {r!r}",
                field="innovation",
            )
        ph = self._cov @ hm.T
        s = hm @ ph + np.diag(r)
        try:
            chol = np.linalg.cholesky(s)
        except np.linalg.LinAlgError:
            raise InvalidInputError("measurement update: innovation covariance is not positive definite", field="r") from None
        sy = np.linalg.solve(chol.T, np.linalg.solve(chol, y))
        if gate is not None and float(y @ sy) > gate:
            return None
        # the update belongs to a checkpoint at this instant, made before P changes (a kept
        # segment's backward pass starts from the covariance after its last sample)
        self.close()
        gain = np.linalg.solve(chol.T, np.linalg.solve(chol, ph.T)).T  # K = P H' S^-1
        dx = gain @ y
        cov = self._cov - gain @ ph.T
        self._cov[:] = 0.5 * (cov + cov.T)
        self._apply(dx)
        cp = self.checkpoints[-1]
        cp.updates.append((hm, gain, sy, y))
        # the checkpoint holds the state after every update at this instant
        self._fill_checkpoint(cp)
        if self.step_smoother is not None:
            self.step_smoother.add_update(self, hm, gain, sy, y)
        return dx

    def selection(self, indices: NDArray[np.int64]) -> NDArray[np.float64]:
        """H that measures the error states ``indices`` (one row each)."""
        idx = np.asarray(indices, dtype=np.int64)
        h = np.zeros((len(idx), self._cov.shape[0]))
        h[np.arange(len(idx)), idx] = 1.0
        return h

    def update_position(self, foot: int, z: NDArray[np.float64], std_m: float | NDArray[np.float64], axes: int = 3) -> NDArray[np.float64]:
        """Position measurement ``z`` (m, nav) of ``foot``'s first ``axes`` axes (2: horizontal)."""
        sl = self.block(foot, "pos")
        h = self.selection(np.arange(sl.start, sl.start + axes))
        innov = self._p[foot, :axes] - np.asarray(z, float)[:axes]
        return self.update(h, innov, np.broadcast_to(np.asarray(std_m, float) ** 2, (axes,)))

    def _apply(self, dx: NDArray[np.float64]) -> None:
        dq, q_tmp = np.zeros(4), np.zeros(4)
        for f in range(self.n_feet):
            feedback(self._q, self._v, self._p, self._ba, self._bg, f, dx, f * self.n_states, self.n_states, dq, q_tmp)

    # -- checkpoints and outputs ------------------------------------------------------------------
    def _checkpoint(self, step_end: bool) -> Checkpoint:
        cp = Checkpoint(self._n_events, self._k.copy(), *(np.empty(0),) * 7, step_end=step_end)
        self._fill_checkpoint(cp)
        return cp

    def _fill_checkpoint(self, cp: Checkpoint) -> None:
        cp.q, cp.v, cp.p = self._q.copy(), self._v.copy(), self._p.copy()
        cp.ba, cp.bg, cp.f_n, cp.cov = self._ba.copy(), self._bg.copy(), self._f_n.copy(), self._cov.copy()

    def replay(self, a: int, b: int, mode: int, record: tuple, smoothed: tuple, fill, mu, d) -> None:
        """Re-run from checkpoint ``a`` to checkpoint ``b`` in ``mode`` (``MODE_STEP`` or
        ``MODE_WHOLE``, see :func:`_run`) with the smoother's buffers; the filter's own state is
        untouched and the outputs written meanwhile are the first run's (the loop is
        deterministic)."""
        ca, cb = self.checkpoints[a], self.checkpoints[b]
        n_ev = cb.n_events - ca.n_events
        state = tuple(x.copy() for x in (ca.q, ca.v, ca.p, ca.ba, ca.bg, ca.f_n, ca.cov))
        _, events = self._call(mode, ca.k.copy(), cb.k.copy(), np.inf, n_ev, False, state, record, smoothed, fill, mu, d)
        if events != n_ev:  # pragma: no cover - the checkpoints come from this very loop
            raise RuntimeError("replay did not reproduce the forward run")

    def smooth_kept(self, record: tuple, used: int, cov: NDArray[np.float64], smoothed: tuple, mu, d) -> None:
        """The whole-walk smoother's backward pass over a kept segment (``MODE_BACK``): ``used``
        events of ``record``, ``cov`` the covariance after its last sample."""
        fill = np.array([used], dtype=np.int64)
        state = (self._q, self._v, self._p, self._ba, self._bg, self._f_n, cov)  # only cov is read
        self._call(MODE_BACK, self._k, self._stop_at, -np.inf, 0, False, state, record, smoothed, fill, mu, d)

    def outputs(self, foot: int) -> tuple[NDArray, NDArray, NDArray, NDArray]:
        """Per-sample attitude, velocity, position and position covariance (xx, xy, yy, zz) of ``foot``."""
        sl = slice(self._offsets[foot], self._offsets[foot + 1])
        return self._out_q[sl], self._out_v[sl], self._out_p[sl], self._out_pcov[sl]

    def global_index(self, foot: int, k: int) -> int:
        return int(self._offsets[foot] + k)
