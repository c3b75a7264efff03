"""A step-able error-state ZUPT-aided INS for one foot or two feet in one joint filter.

Per foot, the error state is ``dx = [dphi, dv, dp]`` (9 states: attitude, velocity, position in
the nav frame; seed 001 eq. 1-3) or ``[dphi, dv, dp, dba, dbg]`` (15 states, adding the
accelerometer and gyroscope bias errors). With C^ = (I - [dphi x]) C, dv = v^ - v, dp = p^ - p and
db = b^ - b, the continuous error model is::

    d(dphi)/dt = C^ dbg,   d(dv)/dt = [f^n x] dphi - C^ dba,   d(dp)/dt = dv,   d(db)/dt = w_b

discretised per sample as F = I + A dt with Q = diag(sigma_g^2, sigma_a^2, 0, sigma_ba^2,
sigma_bg^2) dt from noise *densities*, so the filter behaves the same at any sampling rate.
Measurements (a ZUPT ``v^ = 0`` in stance, an optional zero angular rate ``w^ = 0``, and any
position measurement a fusion makes) update ``dx``, which is fed back into the nominal state and
reset to zero (closed loop, seed 002 Alg. 1).

Two feet share one covariance: each foot's samples are processed in time order, and a
measurement that links the feet (seed 001 eq. 7) updates both. :class:`InsFilter` runs the
compiled per-sample loop between the points where a caller wants to act (:meth:`run_until`) and
keeps checkpoints (state and covariance) at step ends and where the caller updates, so that
:mod:`footnav.core.smoothing` can smooth the run afterwards in memory that grows with the number
of steps, not of samples.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numba import njit
from numpy.typing import NDArray

from footnav.core import kalman
from footnav.core.errors import InvalidInputError
from footnav.core.mechanization import strapdown_step
from footnav.core.quaternion import as_matrix_nb, from_rotvec_nb, multiply_nb, normalize_nb

__all__ = ["InsFilter", "FilterNoise", "Checkpoint", "ATT", "VEL", "POS", "ACC_BIAS", "GYR_BIAS"]

#: Offsets of the blocks of one foot's error state.
ATT, VEL, POS, ACC_BIAS, GYR_BIAS = 0, 3, 6, 9, 12

#: Largest number of samples between two checkpoints: bounds the smoother's buffers when a foot
#: stands still for minutes.
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
    step_end: bool  # a foot's stance ended here (a step boundary for step-wise smoothing)
    #: measurement updates applied at this instant after the per-sample ones, in order, as
    #: (H, K, S^-1 y): what the smoother needs to undo them backwards
    updates: list = field(default_factory=list)


# -- compiled kernels ---------------------------------------------------------------------------


@njit(cache=True, inline="always", error_model="numpy")
def _f_apply(src, dst, n, x, y, z, c, dt):
    """dst = F src for one foot's block (src, dst: (n,)); S = [f^n x] dt = [[0,-z,y],[z,0,-x],[-y,x,0]]."""
    a0, a1, a2 = src[0], src[1], src[2]
    v0, v1, v2 = src[3], src[4], src[5]
    dst[0], dst[1], dst[2] = a0, a1, a2
    dst[3] = v0 - z * a1 + y * a2
    dst[4] = v1 + z * a0 - x * a2
    dst[5] = v2 - y * a0 + x * a1
    dst[6] = src[6] + dt * v0
    dst[7] = src[7] + dt * v1
    dst[8] = src[8] + dt * v2
    if n == 15:
        for i in range(3):
            # attitude error grows with the gyro bias error, velocity error with the acc bias error
            dst[i] += dt * (c[i, 0] * src[12] + c[i, 1] * src[13] + c[i, 2] * src[14])
            dst[3 + i] -= dt * (c[i, 0] * src[9] + c[i, 1] * src[10] + c[i, 2] * src[11])
        for i in range(9, 15):
            dst[i] = src[i]


@njit(cache=True, inline="always", error_model="numpy")
def _ft_apply(mu, o, n, x, y, z, c, dt):
    """mu <- F' mu on one foot's block starting at ``o`` (the smoother's backward step)."""
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
            mu[o + 9 + j] -= dt * (c[0, j] * v0 + c[1, j] * v1 + c[2, j] * v2)
            mu[o + 12 + j] += dt * (c[0, j] * a0 + c[1, j] * a1 + c[2, j] * a2)


@njit(cache=True, error_model="numpy")
def _predict_cov(cov, o, n, f_n, c, dt, q_diag, src, dst):
    """P <- F P F' + Q dt for one foot's block at offset ``o`` of the joint covariance.

    F differs from I only in the foot's rows, so F P changes those rows and (F P) F' those
    columns: O(N n) instead of the O(N^3) of a dense product.
    """
    big = cov.shape[0]
    x, y, z = f_n[0] * dt, f_n[1] * dt, f_n[2] * dt
    for j in range(big):  # rows: M = F P
        for i in range(n):
            src[i] = cov[o + i, j]
        _f_apply(src, dst, n, x, y, z, c, dt)
        for i in range(n):
            cov[o + i, j] = dst[i]
    for i in range(big):  # columns: P = M F'
        for j in range(n):
            src[j] = cov[i, o + j]
        _f_apply(src, dst, n, x, y, z, c, dt)
        for j in range(n):
            cov[i, o + j] = dst[j]
    for i in range(n):
        cov[o + i, o + i] += q_diag[i] * dt


@njit(cache=True, error_model="numpy")
def _update(cov, dx, idx, m, y, r_diag, gain, sy, s, s_inv, low, hp):
    """Update with a measurement of the states ``idx[:m]`` (H a selection): y = H dx + noise.

    K = P H' S^-1, dx = K y, P <- P - K H P (symmetrised). Writes ``gain`` (N, m) = K and
    ``sy`` = S^-1 y for the smoother. Returns False when S is not positive definite.
    """
    big = cov.shape[0]
    for a in range(m):
        for b in range(m):
            s[a, b] = cov[idx[a], idx[b]]
        s[a, a] += r_diag[a]
    if not kalman.spd_inverse(s[:m, :m], s_inv[:m, :m], low[:m, :m]):
        return False
    for a in range(m):
        acc = 0.0
        for b in range(m):
            acc += s_inv[a, b] * y[b]
        sy[a] = acc
    for i in range(big):
        for b in range(m):
            acc = 0.0
            for a in range(m):
                acc += cov[i, idx[a]] * s_inv[a, b]
            gain[i, b] = acc
        acc = 0.0
        for b in range(m):
            acc += cov[i, idx[b]] * sy[b]
        dx[i] = acc
    for a in range(m):
        for j in range(big):
            hp[a, j] = cov[idx[a], j]
    for i in range(big):
        for j in range(i, big):
            acc = cov[i, j]
            for a in range(m):
                acc -= gain[i, a] * hp[a, j]
            cov[i, j] = acc
            cov[j, i] = acc
    return True


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
def _update_vel(cov, dx, o, v, r, gain, sy, hp):
    """The ZUPT update of :func:`_update` for the velocity block at ``o`` (y = v^, H = [0 I 0]),
    with the 3 x 3 inverse written out: the update runs at every stance sample."""
    big = cov.shape[0]
    i00, i01, i02, i11, i12, i22, det = sym3_inverse(
        cov[o, o] + r, cov[o, o + 1], cov[o, o + 2], cov[o + 1, o + 1] + r, cov[o + 1, o + 2], cov[o + 2, o + 2] + r
    )
    if not det > 0.0:
        return False
    sy[0] = i00 * v[0] + i01 * v[1] + i02 * v[2]
    sy[1] = i01 * v[0] + i11 * v[1] + i12 * v[2]
    sy[2] = i02 * v[0] + i12 * v[1] + i22 * v[2]
    for j in range(big):
        hp[0, j] = cov[o, j]
        hp[1, j] = cov[o + 1, j]
        hp[2, j] = cov[o + 2, j]
    for i in range(big):
        h0, h1, h2 = hp[0, i], hp[1, i], hp[2, i]  # P[i, vel] = P[vel, i] (symmetric)
        g0 = h0 * i00 + h1 * i01 + h2 * i02
        g1 = h0 * i01 + h1 * i11 + h2 * i12
        g2 = h0 * i02 + h1 * i12 + h2 * i22
        gain[i, 0] = g0
        gain[i, 1] = g1
        gain[i, 2] = g2
        dx[i] = h0 * sy[0] + h1 * sy[1] + h2 * sy[2]
        for j in range(i, big):
            val = cov[i, j] - g0 * hp[0, j] - g1 * hp[1, j] - g2 * hp[2, j]
            cov[i, j] = val
            cov[j, i] = val
    return True


@njit(cache=True, inline="always", error_model="numpy")
def _nis3(cov, o, y0, y1, y2, r):
    """Normalised innovation squared y' (P_block + r I)^-1 y of a measurement of the 3 states at o."""
    i00, i01, i02, i11, i12, i22, _ = sym3_inverse(
        cov[o, o] + r, cov[o, o + 1], cov[o, o + 2], cov[o + 1, o + 1] + r, cov[o + 1, o + 2], cov[o + 2, o + 2] + r
    )
    return i00 * y0 * y0 + i11 * y1 * y1 + i22 * y2 * y2 + 2.0 * (i01 * y0 * y1 + i02 * y0 * y2 + i12 * y1 * y2)


@njit(cache=True, error_model="numpy")
def feedback(q, v, p, ba, bg, dx, o, n, dq, q_tmp):
    """Closed-loop reset of one foot: C <- (I + [dphi x]) C^, v -= dv, p -= dp, b -= db."""
    from_rotvec_nb(dx[o], dx[o + 1], dx[o + 2], dq)
    multiply_nb(dq, q, q_tmp)
    for i in range(4):
        q[i] = q_tmp[i]
    normalize_nb(q)
    for i in range(3):
        v[i] -= dx[o + 3 + i]
        p[i] -= dx[o + 6 + i]
        if n == 15:
            ba[i] -= dx[o + 9 + i]
            bg[i] -= dx[o + 12 + i]


@njit(cache=True, error_model="numpy")
def _run(
    t, acc, gyr, stance, stop_at, k, t_stop, max_events, step_stops,
    q, v, p, ba, bg, f_n, cov, n, q_diag, r_zupt, r_zaru,
    out_q, out_v, out_p, out_pcov,
    record, rec_off, ev_foot, ev_k, ev_f, ev_c, ev_dt, ev_prows, ev_m, ev_idx, ev_gain, ev_sy,
):
    """Advance the feet through their samples with t <= t_stop, in time order.

    Foot f owns samples ``k[f] + 1 .. stop_at[f]`` of the concatenated arrays (``k[f]`` is its
    last processed sample). With ``record``, event i of this call is written at ``rec_off + i``
    of the record arrays (offsets, not slices: every caller then shares one compiled signature). Returns (reason, events): reason 0 nothing left before t_stop,
    1 a foot's stance just ended (a step boundary; only with ``step_stops``), 2 ``max_events``
    processed.
    """
    n_feet = len(k)
    big = cov.shape[0]
    src = np.zeros(n)
    dst = np.zeros(n)
    c = np.zeros((3, 3))
    dq = np.zeros(4)
    q_tmp = np.zeros(4)
    a_prev = np.zeros(3)
    w_prev = np.zeros(3)
    a_cur = np.zeros(3)
    w_cur = np.zeros(3)
    dx = np.zeros(big)
    idx = np.zeros(6, dtype=np.int64)
    y = np.zeros(6)
    r_diag = np.zeros(6)
    gain = np.zeros((big, 6))
    sy = np.zeros(6)
    s = np.zeros((6, 6))
    s_inv = np.zeros((6, 6))
    low = np.zeros((6, 6))
    hp = np.zeros((6, big))
    c_next = np.zeros((3, 3))
    f_prev = np.zeros(3)
    events = 0
    while events < max_events:
        f = -1
        best = np.inf
        for g in range(n_feet):
            if k[g] < stop_at[g]:
                tn = t[k[g] + 1]
                if tn <= t_stop and tn < best:
                    best = tn
                    f = g
        if f < 0:
            return _DONE, events
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
        strapdown_step(q[f], v[f], p[f], f_n[f], a_prev, w_prev, a_cur, w_cur, dt, dq, q_tmp, c_next)
        _predict_cov(cov, o, n, f_prev, c, dt, q_diag, src, dst)
        m = 0
        if stance[kn]:
            for i in range(3):
                idx[i] = o + VEL + i
                y[i] = v[f, i]  # z = v^ - 0 = dv + noise
                r_diag[i] = r_zupt
            m = 3
            # a detected stance is not always still: the zero-angular-rate update is skipped when
            # the rate is implausible for a still foot (chi-square gate), or it would turn real
            # rotation into gyro bias
            if r_zaru > 0.0 and n == 15 and _nis3(cov, o + GYR_BIAS, w_cur[0], w_cur[1], w_cur[2], r_zaru) < ZARU_GATE:
                for i in range(3):
                    idx[3 + i] = o + GYR_BIAS + i
                    y[3 + i] = -w_cur[i]  # w^ = w - dbg: -w^ = dbg + noise
                    r_diag[3 + i] = r_zaru
                m = 6
            if m == 3:
                ok = _update_vel(cov, dx, o + VEL, v[f], r_zupt, gain, sy, hp)
            else:
                ok = _update(cov, dx, idx, m, y, r_diag, gain, sy, s, s_inv, low, hp)
            if ok:
                feedback(q[f], v[f], p[f], ba[f], bg[f], dx, o, n, dq, q_tmp)
            else:
                m = 0
        if record:
            e = rec_off + events
            ev_foot[e] = f
            ev_k[e] = kn
            ev_dt[e] = dt
            ev_f[e, 0], ev_f[e, 1], ev_f[e, 2] = fx * dt, fy * dt, fz * dt
            for i in range(3):
                for j in range(3):
                    ev_c[e, i, j] = c[i, j]
            for i in range(9):
                for j in range(big):
                    ev_prows[e, i, j] = cov[o + i, j]
            ev_m[e] = m
            for a in range(m):
                ev_idx[e, a] = idx[a]
                ev_sy[e, a] = sy[a]
                for i in range(big):
                    ev_gain[e, i, a] = gain[i, a]
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
        if step_stops and stance[kn] and kn < stop_at[f] and not stance[kn + 1]:
            return _STEP_END, events
    return _FULL, events


# -- the step-able filter -------------------------------------------------------------------------


class InsFilter:
    """Error-state ZUPT-aided INS over one or two feet, advanced by the caller.

    Build it with :meth:`footnav.estimators.ekf.EkfEstimator.start`. The caller advances it with
    :meth:`run_until` (the compiled loop: strapdown, covariance prediction, ZUPT in stance),
    reads the current state (:meth:`position`, :meth:`velocity`, :meth:`quaternion`,
    :attr:`covariance`), applies its own measurements (:meth:`update`, :meth:`update_position`)
    between runs, and collects the per-sample results with :meth:`outputs`. Step ends (when
    ``step_stops``), full segments and the instants of the caller's updates leave a
    :class:`Checkpoint` for the smoother.

    Attributes
    ----------
    n_states
        States per foot (9 or 15).
    n_feet
        1 or 2; foot ``f``'s error states are ``f * n_states`` to ``(f + 1) * n_states``.
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
        # one writable copy for one foot or two: the compiled loop then has one signature (a
        # read-only input would compile every kernel a second time)
        self._t = np.concatenate(t)
        self._acc = np.ascontiguousarray(np.concatenate(acc))
        self._gyr = np.ascontiguousarray(np.concatenate(gyr))
        self._stance = np.ascontiguousarray(np.concatenate([np.asarray(x, dtype=bool) for x in stance]))
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
        total = len(self._t)
        self._out_q = np.empty((total, 4))
        self._out_v = np.empty((total, 3))
        self._out_p = np.empty((total, 3))
        self._out_pcov = np.empty((total, 4))
        for f in range(nf):  # samples up to the start hold the initial state
            a, k = self._offsets[f], self._k[f]
            self._out_q[a : k + 1] = self._q[f]
            self._out_v[a : k + 1] = 0.0
            self._out_p[a : k + 1] = self._p[f]
            o = f * n_states + POS
            self._out_pcov[a : k + 1] = [self._cov[o, o], self._cov[o, o + 1], self._cov[o + 1, o + 1], self._cov[o + 2, o + 2]]
        self._n_events = 0
        self._since_checkpoint = 0
        self._empty = _empty_record(big)
        #: Optional observer of the run with ``before_run(filt) -> (buffers, max_events)`` and
        #: ``after_run(filt, events)``: :class:`footnav.core.smoothing.StepSmoother`.
        self.recorder = None
        #: Stop (and leave a checkpoint) at every step end: what step-wise smoothing needs.
        self.step_stops = True
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
    def run_until(self, t_stop: float = np.inf) -> None:
        """Process every sample with time <= ``t_stop`` (s) of each foot, in time order."""
        while True:
            # a checkpoint at least every MAX_SEGMENT_EVENTS: the smoother re-runs one at a time
            max_events = MAX_SEGMENT_EVENTS - self._since_checkpoint
            if self.recorder is not None:
                buffers, rec_off, room = self.recorder.before_run(self)
                record, max_events = True, min(max_events, room)
            else:
                record, buffers, rec_off = False, self._empty, 0
            reason, events = _run(
                self._t, self._acc, self._gyr, self._stance, self._stop_at, self._k, float(t_stop),
                max_events, self.step_stops, self._q, self._v, self._p, self._ba, self._bg, self._f_n, self._cov,
                self.n_states, self._q_diag, self.noise.zupt_std_mps**2, self.noise.zaru_std_radps**2,
                self._out_q, self._out_v, self._out_p, self._out_pcov, record, rec_off, *buffers,
            )
            self._n_events += events
            self._since_checkpoint += events
            if self.recorder is not None:
                self.recorder.after_run(self, events)
            # checkpoints where a step ends or a segment is full; a stop for the caller needs one
            # only if the caller then updates (see update): memory grows with steps, not with stops
            if events and reason != _DONE:
                # a full buffer of a step-wise smoother is a forced step boundary
                self._add_checkpoint(step_end=reason == _STEP_END or self.recorder is not None)
            if reason == _DONE:
                return

    def _add_checkpoint(self, step_end: bool) -> None:
        self.checkpoints.append(self._checkpoint(step_end=step_end))
        self._since_checkpoint = 0
        if self.recorder is not None:
            self.recorder.on_checkpoint(self)

    def close(self) -> None:
        """Leave a checkpoint at the current state (the smoother needs one after the last sample)."""
        if self._since_checkpoint:
            self._add_checkpoint(step_end=False)

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
        gain = np.linalg.solve(chol.T, np.linalg.solve(chol, ph.T)).T  # K = P H' S^-1
        dx = gain @ y
        cov = self._cov - gain @ ph.T
        self._cov[:] = 0.5 * (cov + cov.T)
        self._apply(dx)
        self.close()  # the update belongs to a checkpoint at this instant
        cp = self.checkpoints[-1]
        cp.updates.append((hm, gain, sy))
        # the checkpoint holds the state after every update at this instant
        self._fill_checkpoint(cp)
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
            feedback(self._q[f], self._v[f], self._p[f], self._ba[f], self._bg[f], dx, f * self.n_states, self.n_states, dq, q_tmp)

    # -- checkpoints and outputs ------------------------------------------------------------------
    def _checkpoint(self, step_end: bool) -> Checkpoint:
        cp = Checkpoint(self._n_events, self._k.copy(), *(np.empty(0),) * 7, step_end=step_end)
        self._fill_checkpoint(cp)
        return cp

    def _fill_checkpoint(self, cp: Checkpoint) -> None:
        cp.q, cp.v, cp.p = self._q.copy(), self._v.copy(), self._p.copy()
        cp.ba, cp.bg, cp.f_n, cp.cov = self._ba.copy(), self._bg.copy(), self._f_n.copy(), self._cov.copy()

    def replay(self, a: int, b: int) -> tuple:
        """Re-run from checkpoint ``a`` to checkpoint ``b`` recording what the smoother needs.

        Returns the record arrays (foot, sample, f^n dt, C, dt, P rows, m, indices, gains,
        S^-1 y) of the events between the two checkpoints, and the outputs written meanwhile
        are the same as the first run's (the loop is deterministic).
        """
        ca, cb = self.checkpoints[a], self.checkpoints[b]
        n_ev = cb.n_events - ca.n_events
        big = self._cov.shape[0]
        rec = _empty_record(big, n_ev)
        k = ca.k.copy()
        stop = cb.k.copy()
        q, v, p, ba, bg, f_n, cov = (x.copy() for x in (ca.q, ca.v, ca.p, ca.ba, ca.bg, ca.f_n, ca.cov))
        done = 0
        while done < n_ev:
            _, events = _run(
                self._t, self._acc, self._gyr, self._stance, stop, k, np.inf, n_ev - done, self.step_stops,
                q, v, p, ba, bg, f_n, cov, self.n_states, self._q_diag, self.noise.zupt_std_mps**2,
                self.noise.zaru_std_radps**2, self._out_q, self._out_v, self._out_p, self._out_pcov,
                True, done, *rec,
            )
            if events == 0:  # pragma: no cover - the checkpoints come from this very loop
                raise RuntimeError("replay did not reproduce the forward run")
            done += events
        return rec

    def outputs(self, foot: int) -> tuple[NDArray, NDArray, NDArray, NDArray]:
        """Per-sample attitude, velocity, position and position covariance (xx, xy, yy, zz) of ``foot``."""
        sl = slice(self._offsets[foot], self._offsets[foot + 1])
        return self._out_q[sl], self._out_v[sl], self._out_p[sl], self._out_pcov[sl]

    def global_index(self, foot: int, k: int) -> int:
        return int(self._offsets[foot] + k)


def _empty_record(big: int, n: int = 0) -> tuple:
    """Buffers of :func:`_run`'s record mode for ``n`` events of a filter with ``big`` states."""
    return (
        np.zeros(n, dtype=np.int64),  # foot
        np.zeros(n, dtype=np.int64),  # global sample index
        np.zeros((n, 3)),  # f^n dt
        np.zeros((n, 3, 3)),  # C
        np.zeros(n),  # dt
        np.zeros((n, 9, big)),  # rows att, vel, pos of P after the sample's updates
        np.zeros(n, dtype=np.int64),  # measurements at the sample
        np.zeros((n, 6), dtype=np.int64),
        np.zeros((n, big, 6)),
        np.zeros((n, 6)),
    )
