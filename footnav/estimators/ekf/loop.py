"""The compiled forward loop of the error-state filter, one or two feet in one joint filter.

Two feet share one covariance: each foot's samples are processed in time order, and a
measurement that links the feet (Zhao et al. (2019), eq. 7) updates both. One compiled function,
:func:`run`, does all the per-sample work: filtering, recording what the smoother needs (per
sample f^n dt, dt and, with bias states, C; per update K, y and S^-1 y, not the covariance),
step-wise smoothing at each step end, and the whole-walk smoother's recording, replay and
backward pass of one segment (:func:`footnav.estimators.ekf.backward.smooth_back`). One entry
point keeps the first call's compilation short: each compiled caller would re-optimise the loop
it calls.
"""

from __future__ import annotations

import numpy as np

from footnav._numba import njit  # numba.njit that survives a read-only install
from footnav.nav.kalman import update3
from footnav.nav.mechanization import strapdown_step
from footnav.nav.quaternion import as_matrix_nb
from footnav.estimators.ekf.backward import smooth_back
from footnav.estimators.ekf.kernels import feedback, feedback_all, predict_cov
from footnav.estimators.ekf.records import GYR_BIAS, POS, VEL

__all__ = [
    "APART", "DONE", "FULL", "MODE_BACK", "MODE_CLOSE", "MODE_FILTER", "MODE_RECORD", "MODE_STEP", "MODE_WHOLE", "NOT_PD", "STEP_END",
    "W_APPLIED", "W_BOUND", "W_NEXT", "W_SYMMETRIC", "W_VAR", "ZARU_GATE", "run",
]

#: Chi-square gate of the zero-angular-rate update: 3 degrees of freedom, 99.9 %.
ZARU_GATE = 16.27

#: Why :func:`run` returned: nothing left before t_stop, a foot's stance ended, max_events done
#: (or the record full), the feet were found farther apart than the watched bound (and not
#: projected), a projection's innovation covariance was not positive definite.
DONE, STEP_END, FULL, APART, NOT_PD = 0, 1, 2, 3, 4

#: The entries of :func:`run`'s ``watch``: the bound (m), the next watched time's index, the
#: projection's variance per axis (m^2; 0: none, the loop stops instead), 1.0 for symmetric
#: projections (0.0: the moving foot onto the sphere around the standing one), projections made.
W_BOUND, W_NEXT, W_VAR, W_SYMMETRIC, W_APPLIED = 0, 1, 2, 3, 4


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


@njit(cache=True, error_model="numpy")
def _apart(watch_times, watch, p, t_next, t_stop):
    """Check the watched times before ``t_next`` (and not after ``t_stop``) from index
    ``watch[W_NEXT]`` on: True at the first where feet 0 and 1 are more than ``watch[W_BOUND]`` m
    apart, ``watch[W_NEXT]`` left there; else False, ``watch[W_NEXT]`` past the checked times."""
    i = int(watch[W_NEXT])
    while i < len(watch_times) and watch_times[i] < t_next and watch_times[i] <= t_stop:
        dx, dy, dz = p[0, 0] - p[1, 0], p[0, 1] - p[1, 1], p[0, 2] - p[1, 2]
        if not np.sqrt(dx * dx + dy * dy + dz * dz) <= watch[W_BOUND]:  # a NaN distance stops too
            watch[W_NEXT] = i
            return True
        i += 1
    watch[W_NEXT] = i
    return False


@njit(cache=True, error_model="numpy")
def _position_update(foot, y0, y1, y2, r, state, n, ws, record, rec, fill):
    """The loop's own measurement of ``foot``'s position (innovation y = p^ - z, m; variance
    ``r`` per axis, m^2), fed back into every foot (the joint covariance links them) and
    recorded as an event without a sample (``rec.k`` -1). False (nothing changed) when S is not
    positive definite. One signature for every caller: each would compile its own otherwise."""
    q, v, p, ba, bg, f_n, cov = state
    dx, gain, sy = ws.dx, ws.gain, ws.sy
    o = foot * n
    if not update3(cov, dx, o + POS, y0, y1, y2, r, np.inf, gain, sy, ws.hp):
        return False
    feedback_all(q, v, p, ba, bg, dx, n, ws.dq, ws.q_tmp)
    if record:
        e, row = fill[0], fill[1]
        rec.foot[e] = foot
        rec.k[e] = -1
        rec.nu[e] = 1
        rec.base[row, 0] = o + POS
        rec.y[row, 0], rec.y[row, 1], rec.y[row, 2] = y0, y1, y2
        for a in range(3):
            rec.sy[row, a] = sy[a]
            for i in range(cov.shape[0]):
                rec.gain[row, i, a] = gain[i, a]
        fill[0] = e + 1
        fill[1] = row + 1
    return True


@njit(cache=True, error_model="numpy")
def _logged_update(foot, y0, y1, y2, r, state, n, ws, record, rec, fill, log, cursor, event):
    """:func:`_position_update`, logged at ``cursor[1]`` as made after ``event`` samples of the
    run (for a replay, :func:`_replay_log`)."""
    if not _position_update(foot, y0, y1, y2, r, state, n, ws, record, rec, fill):
        return False
    j = cursor[1]
    log.event[j] = event
    log.foot[j] = foot
    log.y[j, 0], log.y[j, 1], log.y[j, 2] = y0, y1, y2
    log.r[j] = r
    cursor[1] = j + 1
    return True


@njit(cache=True, error_model="numpy")
def _project(watch, stance, k, state, n, ws, record, rec, fill, log, cursor, event):
    """The range constraint's projection where the feet are farther apart than ``watch``'s
    bound (the ``range`` fusion, :mod:`footnav.fusion.range_constraint`; the same arithmetic):
    the moving foot measured on the sphere around the standing one, or both feet about their
    centroid. Returns DONE, APART (a distance that is not a number: the caller's to report) or
    NOT_PD."""
    p = state.p
    dx, dy, dz = p[0, 0] - p[1, 0], p[0, 1] - p[1, 1], p[0, 2] - p[1, 2]
    dist = np.sqrt(dx * dx + dy * dy + dz * dz)
    if not np.isfinite(dist):
        return APART
    bound, r = watch[W_BOUND], watch[W_VAR]
    ux, uy, uz = dx / dist, dy / dist, dz / dist
    left_stands, right_stands = stance[k[0]], stance[k[1]]
    if watch[W_SYMMETRIC] == 0.0 and left_stands != right_stands:
        mover = 1 if left_stands else 0
        anchor = 1 - mover
        s = (1.0 if mover == 0 else -1.0) * bound  # d points from the right foot to the left
        y0 = p[mover, 0] - (p[anchor, 0] + s * ux)
        y1 = p[mover, 1] - (p[anchor, 1] + s * uy)
        y2 = p[mover, 2] - (p[anchor, 2] + s * uz)
        if not _logged_update(mover, y0, y1, y2, r, state, n, ws, record, rec, fill, log, cursor, event):
            return NOT_PD
    else:
        cx, cy, cz = 0.5 * (p[0, 0] + p[1, 0]), 0.5 * (p[0, 1] + p[1, 1]), 0.5 * (p[0, 2] + p[1, 2])
        h = 0.5 * bound
        for foot in range(2):  # the second innovation from the state the first left
            s = h if foot == 0 else -h
            y0 = p[foot, 0] - (cx + s * ux)
            y1 = p[foot, 1] - (cy + s * uy)
            y2 = p[foot, 2] - (cz + s * uz)
            if not _logged_update(foot, y0, y1, y2, r, state, n, ws, record, rec, fill, log, cursor, event):
                return NOT_PD
    watch[W_APPLIED] += 1.0
    return DONE


@njit(cache=True, error_model="numpy")
def _replay_log(cursor, event, state, n, ws, record, rec, fill, log):
    """Apply again the logged updates made after ``event`` samples of the run (a replay)."""
    while cursor[1] < cursor[2] and log.event[cursor[1]] == event:
        j = cursor[1]
        _position_update(log.foot[j], log.y[j, 0], log.y[j, 1], log.y[j, 2], log.r[j], state, n, ws, record, rec, fill)
        cursor[1] = j + 1


#: What a call of :func:`run` does besides filtering.
MODE_FILTER, MODE_STEP, MODE_WHOLE, MODE_CLOSE, MODE_RECORD, MODE_BACK = 0, 1, 2, 3, 4, 5


@njit(cache=True, error_model="numpy")
def run(
    samples, stop_at, k, t_stop, max_events, step_stops, state, n, q_diag, r_zupt, r_zaru, out,
    mode, rec, sm, fill, mu, d, ws, watch_times, watch, log, cursor,
):
    """Advance the feet through their samples with t <= t_stop, in time order.

    Foot f owns samples ``k[f] + 1 .. stop_at[f]`` of the concatenated :class:`Samples`
    (``k[f]`` is its last processed sample); ``state`` (a :class:`FilterState`) is advanced in
    place and each sample's result written to ``out`` (:class:`Outputs`). ``n`` states per foot,
    ``q_diag`` Q / dt of one foot, ``r_zupt`` and ``r_zaru`` the update variances (0: no ZARU).
    ``rec`` (:class:`Record`), ``sm`` (:class:`Smoothed`), ``fill`` (events and update rows recorded),
    ``mu`` and ``d`` are the smoother's, ``ws`` the :class:`Work` scratch. ``mode``:

    * ``MODE_FILTER``: filter only.
    * ``MODE_STEP``: also record each event at ``fill[0]`` of ``rec``; where a foot's stance ends
      (or ``rec`` is full) smooth the recorded step into ``sm`` (:func:`smooth_back`).
    * ``MODE_WHOLE``: record from 0, then ``d = P mu`` and the backward pass over what was
      recorded, leaving ``mu``, ``d`` of the first event's predecessor (one segment of the
      whole-walk smoother).
    * ``MODE_CLOSE``: no filtering; smooth the recorded open step now.
    * ``MODE_RECORD``: record each event at ``fill[0]`` of ``rec``, nothing more (the forward
      run keeps its segments for the whole-walk smoother; ``max_events`` keeps within ``rec``).
    * ``MODE_BACK``: no filtering; ``d = P mu`` with the given covariance and the backward pass
      over the ``fill[0]`` recorded events (a chunk of segments of the whole-walk smoother).

    ``watch_times`` (s, increasing) and ``watch`` (entries ``W_*``): at each of those times
    from ``watch[W_NEXT]`` on (once every sample at or before it is processed) the distance
    between the two feet is checked. Where it exceeds the bound, the loop projects the feet
    back (:func:`_project`, with ``watch[W_VAR]`` > 0) or stops, ``watch[W_NEXT]`` left at that
    time's index. No watch: an empty ``watch_times``, or None together with ``watch`` and ``log``
    (then numba prunes the watch and the log's code from this compilation: a pipeline without a
    range fusion compiles none of it). (A fusion's check at every few samples,
    and its update at every step, cost a Python round trip each otherwise;
    :meth:`footnav.estimators.ekf.filter.InsFilter.run_range_constrained`.)

    ``log`` (:class:`UpdateLog`) and ``cursor`` ([samples of the run before this call, next
    entry, end of the entries to replay]): the loop's own updates are logged from ``cursor[1]``
    on; a replay (``cursor[1] < cursor[2]``) applies the logged ones again at their instants.

    Returns (reason, events): reason 0 nothing left before t_stop, 1 a foot's stance just ended
    (only with ``step_stops``), 2 ``max_events`` processed or ``rec`` full, 3 the feet apart at
    a watched time, 4 a projection found S not positive definite.
    """
    t, acc, gyr, stance = samples
    q, v, p, ba, bg, f_n, cov = state
    out_q, out_v, out_p, out_pcov = out
    n_feet = len(k)
    big = cov.shape[0]
    ev_foot, ev_k, ev_fdt, ev_dt, ev_c, ev_nu, ev_base, ev_gain, ev_sy, ev_y = rec
    capacity = len(ev_k)
    c, c_next, dq, q_tmp, f_prev = ws.c, ws.c_next, ws.dq, ws.q_tmp, ws.f_prev
    a_prev, w_prev, a_cur, w_cur = ws.a_prev, ws.w_prev, ws.a_cur, ws.w_cur
    y, sy, sy_z, dx, gain, gain_z, hp = ws.y, ws.sy, ws.sy_z, ws.dx, ws.gain, ws.gain_z, ws.hp
    step = mode == MODE_STEP or mode == MODE_CLOSE  # a variable, not a literal: one compiled pass
    if mode == MODE_CLOSE or mode == MODE_BACK:
        smooth_back(fill, step, cov, mu, d, n, n_feet, q_diag, rec, out, sm, ws)
        fill[0] = 0
        fill[1] = 0
        return DONE, 0
    record = mode == MODE_STEP or mode == MODE_WHOLE or mode == MODE_RECORD
    if mode == MODE_WHOLE:
        fill[0] = 0
        fill[1] = 0
    events = 0
    reason = FULL
    n_watch = 0
    if watch_times is not None:  # pruned at compile time when None (numba's dead-branch pruning)
        n_watch = len(watch_times)
    while events < max_events:
        if log is not None:
            if cursor[1] < cursor[2]:
                _replay_log(cursor, cursor[0] + events, state, n, ws, record, rec, fill, log)
        if mode == MODE_RECORD and fill[0] >= capacity:  # the loop's own updates filled it
            return FULL, events
        f = _next_foot(t, k, stop_at, t_stop)
        if watch_times is not None:
            if n_watch:
                # the watched times before the next sample (all of them at the end): every sample
                # at or before each is processed now
                t_next = t[k[f] + 1] if f >= 0 else np.inf
                while _apart(watch_times, watch, p, t_next, t_stop):
                    if not watch[W_VAR] > 0.0:
                        return APART, events
                    if record and fill[0] + 3 > capacity:  # room for two projections and the next sample
                        if not step:
                            return FULL, events
                        smooth_back(fill, step, cov, mu, d, n, n_feet, q_diag, rec, out, sm, ws)
                        fill[0] = 0
                        fill[1] = 0
                    status = _project(watch, stance, k, state, n, ws, record, rec, fill, log, cursor, cursor[0] + events)
                    if status != DONE:
                        return status, events
                    watch[W_NEXT] += 1.0
        if f < 0:
            reason = DONE
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
        predict_cov(cov, o, n, f_prev, c, dt, q_diag)
        nu = 0
        if stance[kn]:
            # ZUPT: z = v^ - 0 = dv + noise
            y[0], y[1], y[2] = v[f, 0], v[f, 1], v[f, 2]
            if update3(cov, dx, o + VEL, y[0], y[1], y[2], r_zupt, np.inf, gain, sy, hp):
                # the foot's own block of dx only, though P took all of it (P - K H P): once a
                # fusion links the feet, the other foot's share is dropped. Feeding all of dx
                # back (feedback_all, as the caller's and the range updates do) was measured on
                # 2026-11-27 (docs/changes.md): 2-D ATE 0.002-0.015 m worse for dtw and
                # step-vector on azure_fgo and gaitmap, so the fusions' noises need choosing
                # again with it first; tests/core/test_ins_filter.py holds it as an xfail
                feedback(q, v, p, ba, bg, f, dx, o, n, dq, q_tmp)
                nu = 1
            # zero angular rate, after the ZUPT (sequential updates with R block-diagonal equal
            # the joint one): w^ = w - bg^, so -w^ = dbg + noise. Skipped when the rate is
            # implausible for a still foot (chi-square gate): a detected stance is not always
            # still, and real rotation would be taken for gyro bias
            if r_zaru > 0.0 and n == 15 and nu == 1:
                for i in range(3):
                    y[3 + i] = bg[f, i] - gyr[kn, i]
                if update3(cov, dx, o + GYR_BIAS, y[3], y[4], y[5], r_zaru, ZARU_GATE, gain_z, sy_z, hp):
                    feedback(q, v, p, ba, bg, f, dx, o, n, dq, q_tmp)
                    nu = 2
        if record:
            if fill[0] == capacity:  # a full buffer: the step is cut here (MODE_STEP only)
                smooth_back(fill, step, cov, mu, d, n, n_feet, q_diag, rec, out, sm, ws)
                fill[0] = 0
                fill[1] = 0
            e = fill[0]
            ev_foot[e] = f
            ev_k[e] = kn
            ev_dt[e] = dt
            ev_fdt[e, 0], ev_fdt[e, 1], ev_fdt[e, 2] = fx * dt, fy * dt, fz * dt
            if n == 15:
                for i in range(3):
                    for j in range(3):
                        ev_c[e, i, j] = c[i, j]
            ev_nu[e] = nu
            fill[0] = e + 1
            if nu > 0:  # an update row (a sample in swing has none)
                row = fill[1]
                for u in range(nu):
                    ev_base[row, u] = o + (VEL if u == 0 else GYR_BIAS)
                for a in range(3 * nu):
                    ev_y[row, a] = y[a]
                for a in range(3):
                    ev_sy[row, a] = sy[a]
                    for i in range(big):
                        ev_gain[row, i, a] = gain[i, a]
                if nu > 1:
                    for a in range(3):
                        ev_sy[row, 3 + a] = sy_z[a]
                        for i in range(big):
                            ev_gain[row, i, 3 + a] = gain_z[i, a]
                fill[1] = row + 1
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
                smooth_back(fill, step, cov, mu, d, n, n_feet, q_diag, rec, out, sm, ws)
                fill[0] = 0
                fill[1] = 0
            if step_stops:
                reason = STEP_END
                break
    if log is not None:
        if cursor[1] < cursor[2]:  # a replay's updates at its last instant, before its checkpoint
            _replay_log(cursor, cursor[0] + events, state, n, ws, record, rec, fill, log)
    if mode == MODE_WHOLE:
        smooth_back(fill, step, cov, mu, d, n, n_feet, q_diag, rec, out, sm, ws)
    return reason, events

