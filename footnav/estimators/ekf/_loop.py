"""The compiled forward loop of the error-state filter, one or two feet in one joint filter.

Two feet share one covariance: each foot's samples are processed in time order, and a
measurement that links the feet (Zhao et al. (2019), eq. 7) updates both. One compiled entry
point, :func:`run`, does the per-sample work: the strapdown and covariance prediction, the ZUPT
and ZARU, the record of each event in the event log the smoother reads
(:class:`~footnav.estimators.ekf._records.Record`, by kind), the outputs; the jobs around it are
one-job helpers: :func:`_next_foot`, the range watch (:func:`_apart`, :func:`_watched`,
:func:`_project`), the loop's own update between samples (:func:`_position_update`,
:func:`_logged_update`, :func:`_replay_log`) and the backward pass where a step or a segment
ends (:func:`_cut`, :func:`footnav.estimators.ekf._backward.smooth_back`). One entry point keeps
the first call's compilation short: each compiled caller would re-optimise the loop it calls.

Its arguments are named tuples (:class:`Span`, :class:`Model`, :class:`Buffers`, :class:`Watch`,
:class:`Replay`; numba passes a tuple as one argument), unpacked once at the top of :func:`run`;
its mode and its stop reason small enums mirrored as ints for the compiled code. The per-sample
steps stay in :func:`run`'s body, with their arrays unpacked once, on measurement: helpers
inlined per sample (``_propagate``, ``_zero_updates``, ``_record_sample``, ``_write_output``,
each with the arrays as arguments) made the loop 10-25 % slower (numba counts references for
each array argument it binds, and for each field read of a tuple), and reading the tuples'
fields per sample 2x slower."""

from __future__ import annotations

from enum import IntEnum
from typing import NamedTuple

import numpy as np
from numpy.typing import NDArray

from footnav._numba import njit  # numba.njit that survives a read-only install
from footnav.estimators.ekf._backward import smooth_back
from footnav.estimators.ekf._kernels import feedback, feedback_all, predict_cov
from footnav.estimators.ekf._records import EV_OWN_UPDATE, EV_SAMPLE, GYR_BIAS, POS, VEL, Record, Smoothed, UpdateLog
from footnav.nav.kalman import update3
from footnav.nav.mechanization import strapdown_step
from footnav.nav.quaternion import as_matrix_nb

__all__ = [
    "APART",
    "DONE",
    "FULL",
    "MODE_BACK",
    "MODE_CLOSE",
    "MODE_FILTER",
    "MODE_RECORD",
    "MODE_STEP",
    "MODE_WHOLE",
    "NOT_PD",
    "STEP_END",
    "ZARU_GATE",
    "Buffers",
    "Mode",
    "Model",
    "Replay",
    "Span",
    "Stop",
    "Watch",
    "clip_rows",
    "run",
]

#: Chi-square gate of the zero-angular-rate update: 3 degrees of freedom, 99.9 %.
ZARU_GATE = 16.27


class Stop(IntEnum):
    """Why :func:`run` returned."""

    DONE = 0  #: nothing left before t_stop
    STEP_END = 1  #: a foot's stance ended (with ``Span.step_stops``)
    FULL = 2  #: ``Span.max_events`` done, or the record full
    APART = 3  #: the feet farther apart than the watched bound at a watched time (not projected)
    NOT_PD = 4  #: a projection's innovation covariance was not positive definite


DONE, STEP_END, FULL, APART, NOT_PD = (int(x) for x in Stop)


class Mode(IntEnum):
    """What a call of :func:`run` does besides filtering."""

    FILTER = 0  #: filter only
    STEP = 1  #: record each event; smooth each step at its end (or where the record is full)
    WHOLE = 2  #: record from 0, then the backward pass over it (one whole-walk segment)
    CLOSE = 3  #: no filtering: smooth the recorded open step now
    RECORD = 4  #: record each event, nothing more (the whole-walk smoother's kept chunks)
    BACK = 5  #: no filtering: the backward pass over the recorded events, ``d = P mu`` first


MODE_FILTER, MODE_STEP, MODE_WHOLE, MODE_CLOSE, MODE_RECORD, MODE_BACK = (int(x) for x in Mode)


class Span(NamedTuple):
    """What a call of :func:`run` processes: foot f owns samples ``k[f] + 1 .. stop_at[f]`` of
    the concatenated :class:`Samples` (``k[f]``: its last processed one, advanced in place),
    those with t <= ``t_stop``, at most ``max_events`` of them; ``step_stops``: return at a step
    end."""

    stop_at: NDArray[np.int64]
    k: NDArray[np.int64]
    t_stop: float
    max_events: int
    step_stops: bool


class Model(NamedTuple):
    """The filter's model: ``n`` states per foot, ``q_diag`` Q / dt of one foot, the update
    variances ``r_zupt`` and ``r_zaru`` (0: no ZARU); and the samples whose accelerometer is at
    its range, where the specific force beyond it is unknown: ``clip_row`` per sample of the
    concatenated samples (-1: none) a row of ``clip_var``, the extra velocity variance of its
    transition along each body axis (m^2/s^2), and of ``clip_q``, that variance in nav
    (C diag(clip_var) C', upper triangle 00 01 02 11 12 22), which the forward loop writes and
    the backward pass reads."""

    n: int
    q_diag: NDArray[np.float64]
    r_zupt: float
    r_zaru: float
    clip_row: NDArray[np.int64]
    clip_var: NDArray[np.float64]
    clip_q: NDArray[np.float64]


def clip_rows(total: int, offsets: NDArray[np.int64], clip_var) -> tuple[NDArray[np.int64], NDArray[np.float64]]:
    """:attr:`Model.clip_row` over ``total`` concatenated samples and :attr:`Model.clip_var`, from
    each foot's None or (N, 3) extra velocity variance per body axis (foot f's samples from
    ``offsets[f]``); a sample with none gets row -1."""
    row = np.full(total, -1, dtype=np.int64)
    rows: list[NDArray[np.float64]] = []
    for f, x in enumerate(clip_var or ()):
        if x is not None:
            hit = np.flatnonzero(np.any(np.asarray(x) > 0.0, axis=1))
            row[offsets[f] + hit] = len(rows) + np.arange(len(hit))
            rows.extend(np.asarray(x, dtype=np.float64)[hit])
    return row, np.array(rows, dtype=np.float64).reshape(-1, 3)


class Buffers(NamedTuple):
    """The smoother's: its event log ``rec``, the smoothed outputs ``sm``, ``fill`` (events and
    update rows recorded), the adjoint ``mu`` and ``d = P mu``."""

    rec: Record
    sm: Smoothed
    fill: NDArray[np.int64]
    mu: NDArray[np.float64]
    d: NDArray[np.float64]


class Watch(NamedTuple):
    """The feet's distance watched at ``times`` (s, increasing) from ``index[0]`` on: the
    bound ``bound_m``; ``var_m2`` the projection's variance per axis (0: none, the loop stops
    instead); ``symmetric`` both feet about their centroid (else the moving foot onto the
    sphere around the standing one); ``applied[0]`` projections made."""

    times: NDArray[np.float64]
    bound_m: float
    var_m2: float
    symmetric: bool
    index: NDArray[np.int64]  # type: ignore[assignment]  # shadows tuple.index; the numba kernels read this name
    applied: NDArray[np.int64]


class Replay(NamedTuple):
    """The loop's own updates (:class:`UpdateLog`): logged from ``next[0]`` on; a replay
    (``next[0] < end``) applies the logged ones again at their instants, an entry's instant
    counted in samples from ``before`` (the samples of the run before this call)."""

    log: UpdateLog
    before: int
    next: NDArray[np.int64]
    end: int


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
def _apart(times, index, bound_m, p, t_next, t_stop):
    """Check the watched ``times`` before ``t_next`` (and not after ``t_stop``) from
    ``index[0]`` on: True at the first where feet 0 and 1 are more than ``bound_m`` apart, the
    index left there; else False, the index past the checked times."""
    i = index[0]
    while i < len(times) and times[i] < t_next and times[i] <= t_stop:
        dx, dy, dz = p[0, 0] - p[1, 0], p[0, 1] - p[1, 1], p[0, 2] - p[1, 2]
        if not np.sqrt(dx * dx + dy * dy + dz * dz) <= bound_m:  # a NaN distance stops too
            index[0] = i
            return True
        i += 1
    index[0] = i
    return False


@njit(cache=True, error_model="numpy")
def _position_update(foot, y0, y1, y2, r, state, n, ws, record, rec, fill):
    """The loop's own measurement of ``foot``'s position (innovation y = p^ - z, m; variance
    ``r`` per axis, m^2), fed back into every foot (the joint covariance links them) and
    recorded as an ``EV_OWN_UPDATE`` event. False (nothing changed) when S is not positive
    definite. One signature for every caller: each would compile its own otherwise."""
    q, v, p, ba, bg, cov = state.q, state.v, state.p, state.ba, state.bg, state.cov
    dx, gain, sy = ws.dx, ws.gain, ws.sy
    o = foot * n
    if not update3(cov, dx, o + POS, y0, y1, y2, r, np.inf, gain, sy, ws.hp):
        return False
    feedback_all(q, v, p, ba, bg, dx, n, ws.dq, ws.q_tmp)
    if record:
        e, row = fill[0], fill[1]
        rec.foot[e] = foot
        rec.k[e] = -1  # no sample
        rec.kind[e] = EV_OWN_UPDATE
        rec.width[e] = 3
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
def _logged_update(foot, y0, y1, y2, r, state, n, ws, record, rec, fill, replay, event):
    """:func:`_position_update`, logged at ``replay.next[0]`` as made after ``event`` samples
    of the run (for a replay, :func:`_replay_log`)."""
    if not _position_update(foot, y0, y1, y2, r, state, n, ws, record, rec, fill):
        return False
    log = replay.log
    j = replay.next[0]
    log.event[j] = event
    log.foot[j] = foot
    log.y[j, 0], log.y[j, 1], log.y[j, 2] = y0, y1, y2
    log.r[j] = r
    replay.next[0] = j + 1
    return True


@njit(cache=True, error_model="numpy")
def _project(watch, stance, k, state, n, ws, record, rec, fill, replay, event):
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
    bound, r = watch.bound_m, watch.var_m2
    ux, uy, uz = dx / dist, dy / dist, dz / dist
    left_stands, right_stands = stance[k[0]], stance[k[1]]
    if not watch.symmetric and left_stands != right_stands:
        mover = 1 if left_stands else 0
        anchor = 1 - mover
        s = (1.0 if mover == 0 else -1.0) * bound  # d points from the right foot to the left
        y0 = p[mover, 0] - (p[anchor, 0] + s * ux)
        y1 = p[mover, 1] - (p[anchor, 1] + s * uy)
        y2 = p[mover, 2] - (p[anchor, 2] + s * uz)
        if not _logged_update(mover, y0, y1, y2, r, state, n, ws, record, rec, fill, replay, event):
            return NOT_PD
    else:
        cx, cy, cz = 0.5 * (p[0, 0] + p[1, 0]), 0.5 * (p[0, 1] + p[1, 1]), 0.5 * (p[0, 2] + p[1, 2])
        h = 0.5 * bound
        for foot in range(2):  # the second innovation from the state the first left
            s = h if foot == 0 else -h
            y0 = p[foot, 0] - (cx + s * ux)
            y1 = p[foot, 1] - (cy + s * uy)
            y2 = p[foot, 2] - (cz + s * uz)
            if not _logged_update(foot, y0, y1, y2, r, state, n, ws, record, rec, fill, replay, event):
                return NOT_PD
    watch.applied[0] += 1
    return DONE


@njit(cache=True, error_model="numpy")
def _replay_log(replay, event, state, n, ws, record, rec, fill):
    """Apply again the logged updates made after ``event`` samples of the run (a replay)."""
    log = replay.log
    while replay.next[0] < replay.end and log.event[replay.next[0]] == event:
        j = replay.next[0]
        _position_update(log.foot[j], log.y[j, 0], log.y[j, 1], log.y[j, 2], log.r[j], state, n, ws, record, rec, fill)
        replay.next[0] = j + 1


@njit(cache=True, inline="always", error_model="numpy")
def _cut(bufs, step, cov, model, n_feet, out, ws):
    """The backward pass over what is recorded (a step, a full buffer or a segment); the
    record starts again."""
    smooth_back(
        bufs.fill,
        step,
        cov,
        bufs.mu,
        bufs.d,
        model.n,
        n_feet,
        model.q_diag,
        model.clip_row,
        model.clip_q,
        bufs.rec,
        out.q,
        out.v,
        out.p,
        bufs.sm,
        ws.kt,
        ws.dq,
        ws.q_tmp,
        ws.offset,
        ws.seen,
    )
    bufs.fill[0] = 0
    bufs.fill[1] = 0


@njit(cache=True, error_model="numpy")
def _watched(watch, replay, stance, k, state, model, ws, record, step, bufs, t_next, t_stop, event, n_feet, out):
    """The feet are apart at the watched time ``watch.index[0]`` (:func:`_apart`): project them
    (or stop), then go on through the watched times before the next sample's ``t_next``; -1
    to go on, else the reason to return."""
    fill = bufs.fill
    capacity = len(bufs.rec.k)
    while True:
        if not watch.var_m2 > 0.0:
            return APART
        if record and fill[0] + 3 > capacity:  # room for two projections and the next sample
            if not step:
                return FULL
            _cut(bufs, step, state.cov, model, n_feet, out, ws)
        status = _project(watch, stance, k, state, model.n, ws, record, bufs.rec, fill, replay, event)
        if status != DONE:
            return status
        watch.index[0] += 1
        if not _apart(watch.times, watch.index, watch.bound_m, state.p, t_next, t_stop):
            return -1


@njit(cache=True, error_model="numpy")
# complexity: a compiled loop; split into helpers it ran 10-25 % slower (docs/changes.md, issue 38)
def run(samples, span, state, model, out, mode, bufs, ws, watch, replay):  # noqa: C901
    """Advance the feet through the samples of ``span`` (:class:`Span`), in time order.

    ``state`` (a :class:`FilterState`) is advanced in place and each sample's result written
    to ``out`` (:class:`Outputs`); ``model`` a :class:`Model`; ``bufs`` the smoother's
    :class:`Buffers`, ``ws`` the :class:`Work` scratch. ``mode`` a :class:`Mode`:

    * ``FILTER``: filter only.
    * ``STEP``: also record each event at ``fill[0]`` of ``rec``; where a foot's stance ends
      (or ``rec`` is full) smooth the recorded step into ``sm`` (:func:`smooth_back`).
    * ``WHOLE``: record from 0, then ``d = P mu`` and the backward pass over what was
      recorded, leaving ``mu``, ``d`` of the first event's predecessor (one segment of the
      whole-walk smoother).
    * ``CLOSE``: no filtering; smooth the recorded open step now.
    * ``RECORD``: record each event at ``fill[0]`` of ``rec``, nothing more (the forward
      run keeps its segments for the whole-walk smoother; ``max_events`` keeps within ``rec``).
    * ``BACK``: no filtering; ``d = P mu`` with the given covariance and the backward pass
      over the ``fill[0]`` recorded events (a chunk of segments of the whole-walk smoother).

    ``watch`` (:class:`Watch`): at each watched time (once every sample at or before it is
    processed) the distance between the two feet is checked; where it exceeds the bound, the
    loop projects the feet back (:func:`_project`) or stops, the watch's index left at that
    time. ``replay`` (:class:`Replay`): the loop's own updates are logged, and a replay applies
    the logged ones again. No watch: an empty ``watch.times``, or None together with
    ``replay`` (then numba prunes the watch and the log's code from this compilation: a
    pipeline without a range fusion compiles none of it). (A fusion's check at every few
    samples, and its update at every step, cost a Python round trip each otherwise;
    :meth:`footnav.estimators.ekf.filter.InsFilter.run_range_constrained`.)

    Returns (reason, events): a :class:`Stop` and the samples processed.
    """
    # every array unpacked once, out of the loop: a tuple's field read per sample costs numba a
    # reference count each time (measured: the loop 2x slower)
    t, acc, gyr, stance, zupt = samples
    q, v, p, ba, bg, f_n, cov = state
    out_q, out_v, out_p, out_pcov = out
    k, stop_at, t_stop = span.k, span.stop_at, span.t_stop
    n, q_diag, r_zupt, r_zaru, clip_row, clip_var, clip_q = model
    ev_foot, ev_k, ev_fdt, ev_dt, ev_c, ev_kind, ev_width, ev_base, ev_gain, ev_sy, ev_y = bufs.rec
    fill = bufs.fill
    c, c_next, dq, q_tmp, f_prev = ws.c, ws.c_next, ws.dq, ws.q_tmp, ws.f_prev
    a_prev, w_prev, a_cur, w_cur = ws.a_prev, ws.w_prev, ws.a_cur, ws.w_cur
    y, sy, sy_z, dx, gain, gain_z, hp = ws.y, ws.sy, ws.sy_z, ws.dx, ws.gain, ws.gain_z, ws.hp
    n_feet = len(k)
    big = cov.shape[0]
    capacity = len(ev_k)
    step = mode == MODE_STEP or mode == MODE_CLOSE  # a variable, not a literal: one compiled pass
    if mode == MODE_CLOSE or mode == MODE_BACK:
        _cut(bufs, step, cov, model, n_feet, out, ws)
        return DONE, 0
    record = mode == MODE_STEP or mode == MODE_WHOLE or mode == MODE_RECORD
    if mode == MODE_WHOLE:
        fill[0] = 0
        fill[1] = 0
    events = 0
    reason = FULL
    n_watch = 0
    if watch is not None:  # pruned at compile time when None (numba's dead-branch pruning)
        n_watch = len(watch.times)
        w_times, w_index, w_bound = watch.times, watch.index, watch.bound_m
    if replay is not None:  # pruned with the watch (the filter passes both or neither)
        r_next, r_end, r_before = replay.next, replay.end, replay.before
    while events < span.max_events:
        if replay is not None:  # noqa: SIM102 - one test per statement: numba prunes this one when None
            if r_next[0] < r_end:  # a replay's logged updates at this instant
                _replay_log(replay, r_before + events, state, n, ws, record, bufs.rec, fill)
        if mode == MODE_RECORD and fill[0] >= capacity:  # the loop's own updates filled it
            return FULL, events
        f = _next_foot(t, k, stop_at, t_stop)
        if watch is not None:  # noqa: SIM102 - one test per statement: numba prunes this one when None
            if n_watch:
                # the watched times before the next sample (all of them at the end): every sample
                # at or before each is processed now
                t_next = t[k[f] + 1] if f >= 0 else np.inf
                if _apart(w_times, w_index, w_bound, p, t_next, t_stop):
                    status = _watched(
                        watch,
                        replay,
                        stance,
                        k,
                        state,
                        model,
                        ws,
                        record,
                        step,
                        bufs,
                        t_next,
                        t_stop,
                        r_before + events,
                        n_feet,
                        out,
                    )
                    if status >= 0:
                        return status, events
        if f < 0:
            reason = DONE
            break
        o = f * n
        kp = k[f]
        kn = kp + 1
        k[f] = kn
        # the strapdown; F uses the attitude (bias columns only) and the specific force at the
        # start of the interval (strapdown_step overwrites f_n[f] with f^n(k))
        for i in range(3):
            a_prev[i] = acc[kp, i] - ba[f, i]
            w_prev[i] = gyr[kp, i] - bg[f, i]
            a_cur[i] = acc[kn, i] - ba[f, i]
            w_cur[i] = gyr[kn, i] - bg[f, i]
        dt = t[kn] - t[kp]
        if n == 15:
            as_matrix_nb(q[f], c)
        f_prev[0], f_prev[1], f_prev[2] = f_n[f, 0], f_n[f, 1], f_n[f, 2]
        strapdown_step(q, v, p, f_n, f, a_prev, w_prev, a_cur, w_cur, dt, dq, q_tmp, c_next)
        predict_cov(cov, o, n, f_prev, c, dt, q_diag)
        j = clip_row[kn]
        if j >= 0:  # a clipped sample's unknown specific force along its axes (Model)
            u = 0
            for i in range(3):
                for m in range(i, 3):
                    qv = (
                        c_next[i, 0] * c_next[m, 0] * clip_var[j, 0]
                        + c_next[i, 1] * c_next[m, 1] * clip_var[j, 1]
                        + c_next[i, 2] * c_next[m, 2] * clip_var[j, 2]
                    )
                    clip_q[j, u] = qv
                    u += 1
                    cov[o + VEL + i, o + VEL + m] += qv
                    if m != i:
                        cov[o + VEL + m, o + VEL + i] += qv
        nu = 0
        if zupt[kn]:
            # ZUPT: z = v^ - 0 = dv + noise
            y[0], y[1], y[2] = v[f, 0], v[f, 1], v[f, 2]
            if update3(cov, dx, o + VEL, y[0], y[1], y[2], r_zupt, np.inf, gain, sy, hp):
                # the foot's own block of dx only, though P took all of it (P - K H P): once a
                # fusion links the feet, the other foot's share is dropped, by choice
                # (docs/concepts.md, "The joint filter's ZUPT feedback": all of it measured worse)
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
                _cut(bufs, step, cov, model, n_feet, out, ws)
            # the sample as the EV_SAMPLE event at fill[0]: its transition and its width
            e = fill[0]
            ev_foot[e] = f
            ev_k[e] = kn
            ev_kind[e] = EV_SAMPLE
            ev_width[e] = 3 * nu
            ev_dt[e] = dt
            ev_fdt[e, 0], ev_fdt[e, 1], ev_fdt[e, 2] = f_prev[0] * dt, f_prev[1] * dt, f_prev[2] * dt
            if n == 15:
                for i in range(3):
                    for j in range(3):
                        ev_c[e, i, j] = c[i, j]
            fill[0] = e + 1
            if nu > 0:  # its updates' row at fill[1] (a sample in swing has none)
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
                _cut(bufs, step, cov, model, n_feet, out, ws)
            if span.step_stops:
                reason = STEP_END
                break
    if replay is not None:  # noqa: SIM102 - one test per statement: numba prunes this one when None
        if r_next[0] < r_end:  # a replay's updates at its last instant, before its checkpoint
            _replay_log(replay, r_before + events, state, n, ws, record, bufs.rec, fill)
    if mode == MODE_WHOLE:
        _cut(bufs, step, cov, model, n_feet, out, ws)
    return reason, events
