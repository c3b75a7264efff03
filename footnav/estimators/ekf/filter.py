"""The step-able error-state ZUPT-aided INS for one foot or two feet in one joint filter.

:class:`InsFilter` runs the compiled per-sample loop (:mod:`footnav.estimators.ekf._loop`)
between the points where a caller wants to act (:meth:`~InsFilter.run_until`) and keeps
checkpoints (:class:`~footnav.estimators.ekf._records.Checkpoint`: state and covariance) every
``MAX_SEGMENT_EVENTS`` samples and where the caller updates, so that
:mod:`footnav.estimators.ekf.smoother` can smooth the run afterwards in memory that grows with
the number of steps (plus a bounded cache of the latest segments' records), not of samples.
The error model and its kernels are in :mod:`footnav.estimators.ekf._kernels`.

A stream (:mod:`footnav.pipeline.online`) builds a filter with room for samples still to come
(``capacity``), hands them over as they arrive (:meth:`~InsFilter.extend`) and starts a new filter
from an old one's checkpoint (:meth:`~InsFilter.resume`).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

from footnav._numba import EntryPoints
from footnav.core.errors import InvalidInputError
from footnav.estimators.ekf._buffers import staggered
from footnav.estimators.ekf._loop import (
    APART,
    DONE,
    FULL,
    MODE_BACK,
    MODE_CLOSE,
    MODE_FILTER,
    MODE_RECORD,
    MODE_STEP,
    NOT_PD,
    STEP_END,
    Buffers,
    Model,
    Replay,
    Span,
    Watch,
    clip_rows,
    run,
)
from footnav.estimators.ekf._measurements import Measurements, loop_watch
from footnav.estimators.ekf._records import (
    ACC_BIAS,
    ATT,
    GYR_BIAS,
    POS,
    VEL,
    Checkpoint,
    FilterNoise,
    FilterState,
    Outputs,
    Record,
    Samples,
    Smoothed,
    UpdateLog,
    Work,
    empty_log,
    empty_record,
    work,
)
from footnav.nav.quaternion import as_matrix

__all__ = ["MAX_SEGMENT_EVENTS", "InsFilter"]


#: Largest number of samples between two checkpoints (and in a step-wise smoother's buffer):
#: bounds the smoother's buffers when a foot stands still for minutes.
MAX_SEGMENT_EVENTS = 4096


class InsFilter(Measurements):
    """Error-state ZUPT-aided INS over one or two feet, advanced by the caller.

    Build it with :meth:`footnav.estimators.ekf.EkfEstimator.start`. The caller advances it with
    :meth:`run_until` (the compiled loop: strapdown, covariance prediction, ZUPT in stance),
    reads the current state (:meth:`position`, :meth:`velocity`, :meth:`quaternion`,
    :attr:`covariance`), applies its own measurements (:meth:`update`, :meth:`update_position`)
    between runs, and collects the per-sample results with :meth:`outputs`. Full segments, the
    instants of the caller's updates and (with :attr:`step_stops`) step ends leave a
    :class:`~footnav.estimators.ekf._records.Checkpoint` for the smoother.

    Parameters
    ----------
    t, acc, gyr, stance
        Per foot: time (s), specific force (m/s^2), angular rate (rad/s), stance mask (a
        stance's end is a step).
    start
        Per foot: the sample holding the initial state (the end of its alignment).
    q0, p0, bg0
        Per foot: initial attitude [w, x, y, z] (body to nav), position (m), gyro bias (rad/s).
    cov0_diag
        Initial error variances of one foot's states (n_states,), or of each foot's (n_feet, n_states).
    noise
        The :class:`~footnav.estimators.ekf._records.FilterNoise`.
    n_states
        States per foot (9 or 15).
    capacity
        Per foot: samples the filter has room for, at least those given; the rest come with
        :meth:`extend`. Default: the given samples.
    clip_var
        Per foot, None or (N, 3): extra velocity variance of each sample's transition along each
        body axis, m^2/s^2 (the samples whose accelerometer is at its range; ``EkfEstimator``'s
        ``clip_excess_mps2``), turned into nav with the predicted attitude. Samples given by
        :meth:`extend` get none.
    zupt
        Per foot: the samples that get a zero-velocity update (default: the stance), e.g. each
        stance's settled part (:meth:`footnav.estimators.ekf.EkfEstimator.zupt_rows`).

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
        A :class:`footnav.estimators.ekf.smoother.StepSmoother` smoothing each step as the
        filter runs, or None.
    segment_records
        A :class:`footnav.estimators.ekf.smoother.SegmentRecords` when the forward run keeps its
        record for the whole-walk smoother, or None.
    checkpoints
        The :class:`~footnav.estimators.ekf._records.Checkpoint` s so far, the start first.
    meta
        Per-foot notes of whoever built the filter (the estimator's alignment).
    """

    def __init__(
        self,
        t: Sequence[NDArray[np.float64]],
        acc: Sequence[NDArray[np.float64]],
        gyr: Sequence[NDArray[np.float64]],
        stance: Sequence[NDArray[np.bool_]],
        start: Sequence[int],
        q0: Sequence[NDArray[np.float64]],
        p0: Sequence[NDArray[np.float64]],
        bg0: Sequence[NDArray[np.float64]],
        cov0_diag: NDArray[np.float64],
        noise: FilterNoise,
        n_states: int,
        *,
        capacity: Sequence[int] | None = None,
        clip_var: Sequence[NDArray[np.float64] | None] | None = None,
        zupt: Sequence[NDArray[np.bool_]] | None = None,
    ) -> None:
        self.n_feet = len(t)
        self.n_states = n_states
        self.noise = noise
        lengths = [len(x) for x in t]
        room = lengths if capacity is None else [max(n, int(c)) for n, c in zip(lengths, capacity)]
        self._offsets = np.concatenate(([0], np.cumsum(room))).astype(np.int64)
        # one writable copy of the inputs for one foot or two (a read-only input would compile
        # every kernel a second time), in one buffer with the outputs (.buffers: 4K aliasing).
        # Two buffers would let an unsmoothed result free the inputs, but ran the step-wise
        # smoother 0.42 -> 0.50 us/sample (10-min walk)
        total = int(self._offsets[-1])
        f8 = np.float64
        (
            self._t,
            self._acc,
            self._gyr,
            self._stance,
            self._zupt,
            self._out_q,
            self._out_v,
            self._out_p,
            self._out_pcov,
        ) = staggered(
            [
                ((total,), f8),
                ((total, 3), f8),
                ((total, 3), f8),
                ((total,), np.bool_),
                ((total,), np.bool_),
                ((total, 4), f8),
                ((total, 3), f8),
                ((total, 3), f8),
                ((total, 4), f8),
            ]
        )
        zupt = stance if zupt is None else zupt
        for dst, src in ((self._t, t), (self._acc, acc), (self._gyr, gyr), (self._stance, stance), (self._zupt, zupt)):
            for f in range(self.n_feet):
                a, b = self._offsets[f], self._offsets[f + 1]
                dst[a : a + lengths[f]] = src[f]
                dst[a + lengths[f] : b] = 0  # room for extend: never read before it is written
        self._in = Samples(self._t, self._acc, self._gyr, self._stance, self._zupt)
        # the samples whose accelerometer is at its range (Model.clip_row): their extra
        # velocity variance per body axis, m^2/s^2
        self._clip_row, rows_var = clip_rows(total, self._offsets, clip_var)
        self._out = Outputs(self._out_q, self._out_v, self._out_p, self._out_pcov)
        #: each foot's last sample given so far (an index of the concatenated samples)
        self._stop_at = self._offsets[:-1] + np.asarray(lengths, dtype=np.int64) - 1
        self._start = np.array(start, dtype=np.int64)
        self._k = self._offsets[:-1] + self._start
        nf = self.n_feet
        self._q = np.array(q0, dtype=float).reshape(nf, 4).copy()
        self._v = np.zeros((nf, 3))
        self._p = np.array(p0, dtype=float).reshape(nf, 3).copy()
        self._ba = np.zeros((nf, 3))
        self._bg = np.array(bg0, dtype=float).reshape(nf, 3).copy()
        self._f_n = np.zeros((nf, 3))
        for f in range(nf):  # numpy's as_matrix, not the kernel: no compilation for one matrix per foot
            self._f_n[f] = as_matrix(self._q[f]) @ (self._acc[self._k[f]] - self._ba[f])
        big = nf * n_states
        self._cov = np.diag(np.broadcast_to(np.asarray(cov0_diag, float), (nf, n_states)).ravel())
        # the state's arrays, named; never rebound, only written in place
        self._state = FilterState(self._q, self._v, self._p, self._ba, self._bg, self._f_n, self._cov)
        self._q_diag = noise.q_diag(n_states)
        for f in range(nf):  # samples up to the start hold the initial state
            a, k = self._offsets[f], self._k[f]
            self._out_q[a : k + 1] = self._q[f]
            self._out_v[a : k + 1] = 0.0
            self._out_p[a : k + 1] = self._p[f]
            o = f * n_states + POS
            self._out_pcov[a : k + 1] = [
                self._cov[o, o],
                self._cov[o, o + 1],
                self._cov[o + 1, o + 1],
                self._cov[o + 2, o + 2],
            ]
        self._n_events = 0
        self._since_checkpoint = 0
        # the loop's own updates (run_range_constrained), for replays; entries so far
        self._log: UpdateLog = empty_log()
        self._n_log = 0
        # the record and smoother arguments of a plain filtering call (not used by it; of the
        # same types as a smoother's, so that numba compiles the loop once)
        self._no_sm = Smoothed(np.zeros((0, 4)), np.zeros((0, 3)), np.zeros((0, 3)))
        self._no_vec = np.zeros(big)
        self._no_bufs = Buffers(empty_record(big), self._no_sm, np.zeros(2, dtype=np.int64), self._no_vec, self._no_vec)
        self._model = Model(
            n_states,
            self._q_diag,
            float(noise.zupt_std_mps**2),
            float(noise.zaru_std_radps**2),
            self._clip_row,
            rows_var,
            np.zeros((len(rows_var), 6)),
        )
        self._work = work(big, nf)
        self._fast = EntryPoints(run)
        self._dense: dict[int, tuple] = {}  # update's scratch by rows
        # smoother.py's StepSmoother and SegmentRecords, or None (Any: smoother.py imports this module)
        self.step_smoother: Any = None
        self.segment_records: Any = None
        self.step_stops = False
        self.meta: list[dict] = [{} for _ in range(self.n_feet)]
        self.checkpoints: list[Checkpoint] = [self._checkpoint(step_end=False)]

    # -- reading the state --------------------------------------------------------------------
    @property
    def covariance(self) -> NDArray[np.float64]:
        """The joint error covariance (N, N) now; a copy."""
        return self._cov.copy()

    def state(self) -> FilterState:
        """The nominal state of every foot and the covariance now; a copy."""
        return self._state.copy()

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
        """Time (s) of the foot's current state."""
        return float(self._t[self._k[foot]])

    def position(self, foot: int) -> NDArray[np.float64]:
        """The foot's position now (m, nav); a copy."""
        return self._p[foot].copy()

    def velocity(self, foot: int) -> NDArray[np.float64]:
        """The foot's velocity now (m/s, nav); a copy."""
        return self._v[foot].copy()

    def quaternion(self, foot: int) -> NDArray[np.float64]:
        """The foot's attitude now ([w, x, y, z], body to nav); a copy."""
        return self._q[foot].copy()

    def biases(self, foot: int) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Current accelerometer (m/s^2) and gyroscope (rad/s) bias estimates."""
        return self._ba[foot].copy(), self._bg[foot].copy()

    @property
    def finished(self) -> bool:
        """Every sample given so far is processed."""
        return bool(np.all(self._k >= self._stop_at))

    def samples(self, foot: int) -> Samples:
        """The foot's samples given so far (views: not to be written)."""
        sl = slice(self._offsets[foot], self._stop_at[foot] + 1)
        return Samples(self._t[sl], self._acc[sl], self._gyr[sl], self._stance[sl], self._zupt[sl])

    def capacity(self, foot: int) -> int:
        """Samples the foot's arrays have room for (those given and those :meth:`extend` may add)."""
        return int(self._offsets[foot + 1] - self._offsets[foot])

    # -- growing and restarting ----------------------------------------------------------------
    def extend(
        self,
        t: NDArray[np.float64],
        acc: NDArray[np.float64],
        gyr: NDArray[np.float64],
        stance: NDArray[np.bool_],
        *,
        foot: int = 0,
        zupt: NDArray[np.bool_] | None = None,
    ) -> None:
        """Give the filter the foot's next samples, after those it has (a stream's new samples);
        ``zupt``: those that get a zero-velocity update (default: the stance).

        They go into the room reserved with ``capacity``; :meth:`run_until` processes them. A
        sample ends a step when the next one is out of stance, so the last sample given is
        processed as a step end only once its successor is given.

        Raises
        ------
        InvalidInputError
            When the samples do not fit (see :meth:`capacity`).
        """
        m = len(t)
        a = int(self._stop_at[foot]) + 1
        if a + m > self._offsets[foot + 1]:
            raise InvalidInputError(
                f"foot {foot}'s filter has room for {self.capacity(foot)} samples; it holds "
                f"{a - self._offsets[foot]} and was given {m} more: build it with a larger capacity",
                field="t",
            )
        self._t[a : a + m] = t
        self._acc[a : a + m] = acc
        self._gyr[a : a + m] = gyr
        self._stance[a : a + m] = stance
        self._zupt[a : a + m] = stance if zupt is None else zupt
        self._clip_row[a : a + m] = -1  # (online: no clipped samples' variance yet)
        self._stop_at[foot] += m

    def resume(self, state: FilterState, index: Sequence[int]) -> None:
        """Continue from ``state`` (a :class:`~footnav.estimators.ekf._records.Checkpoint`'s, of
        this filter or of another over the same samples), foot f's last processed sample being
        its sample ``index[f]``.

        The samples up to ``index[f]`` keep the outputs they have (the caller's to fill), and the
        checkpoints start afresh at the resumed state: a smoother of this filter sees the run
        from there. Resuming from a state reached by the same samples continues the run exactly
        (the loop is deterministic).
        """
        for dst, src in zip(self._state, state):
            dst[...] = src
        self._k[:] = self._offsets[:-1] + np.asarray(index, dtype=np.int64)
        self._n_events = 0
        self._since_checkpoint = 0
        self._n_log = 0
        self.checkpoints = [self._checkpoint(step_end=False)]
        if self.segment_records is not None:  # its chunks end at the checkpoints thrown away
            self.segment_records = type(self.segment_records)(self, self.segment_records.budget_bytes / 1e6)

    # -- acting --------------------------------------------------------------------------------
    def _call(
        self,
        mode: int,
        span: Span,
        state: FilterState,
        bufs: Buffers,
        watch: Watch | None = None,
        replay: Replay | None = None,
    ):
        """One call of the compiled loop from ``state`` (a :class:`FilterState`); ``replay``
        default the forward run's (nothing to replay; new entries after the filter's), ``watch``
        default none."""
        forward = replay is None
        if forward:
            replay = Replay(self._log, self._n_events, np.array([self._n_log], dtype=np.int64), self._n_log)
        if watch is None:
            if self._n_log == 0:
                # nothing to watch and nothing logged to replay: the loop compiled without that code
                # (None prunes it; a pipeline without the range fusion never compiles it)
                replay = None
            else:
                watch = loop_watch(np.zeros(0))
        ws = self._scratch(bufs.rec)
        args = (self._in, span, state, self._model, self._out, mode, bufs, ws, watch, replay)
        if state is self._state:  # the filter's own arrays: the loop's entry point, typed once
            out = self._fast(
                args, held=(self._in, state, self._model, self._out, *bufs, ws), fresh=(span, mode, watch, replay)
            )
        else:
            out = run(*args)
        if forward and replay is not None:
            self._n_log = int(replay.next[0])
        return out

    @property
    def record_columns(self) -> int:
        """Gain columns a sample's updates take in a smoother's record: 3 (the ZUPT), 6 when
        the zero-angular-rate update follows it."""
        return 6 if self.n_states == 15 and self.noise.zaru_std_radps > 0 else 3

    def _scratch(self, rec: Record) -> Work:
        """The loop's scratch, widened when a record holds caller updates of more rows."""
        if len(self._work.kt) < rec.sy.shape[1]:
            self._work = work(self._cov.shape[0], self.n_feet, rec.sy.shape[1])
        return self._work

    def run_until(self, t_stop: float = np.inf) -> None:
        """Process every sample with time <= ``t_stop`` (s) of each foot, in time order."""
        self._run(t_stop, None)

    def _run(self, t_stop: float, watch: Watch | None) -> int:
        """:meth:`run_until` with the loop's watch (:func:`footnav.estimators.ekf._loop.run`);
        returns why it stopped: ``DONE``, ``APART`` or ``NOT_PD``."""
        ss, sr = self.step_smoother, self.segment_records
        while True:
            # the buffers anew at each call: a caller's update may widen the step smoother's record
            if ss is not None:
                mode, bufs = MODE_STEP, Buffers(ss.record, ss.smoothed, ss.fill, ss.mu, ss.d)
            elif sr is not None:
                mode, bufs = MODE_RECORD, Buffers(sr.record, self._no_sm, sr.fill, self._no_vec, self._no_vec)
            else:
                mode, bufs = MODE_FILTER, self._no_bufs
            # a checkpoint at least every MAX_SEGMENT_EVENTS: the smoother re-runs one at a time
            span = Span(
                self._stop_at,
                self._k,
                float(t_stop),
                MAX_SEGMENT_EVENTS - self._since_checkpoint,
                bool(self.step_stops),
            )
            reason, events = self._call(mode, span, self._state, bufs, watch)
            self._n_events += events
            self._since_checkpoint += events
            # checkpoints where a step ends or a segment is full; a stop for the caller needs one
            # only if the caller then updates (see update): memory grows with steps, not with stops
            if reason == DONE or reason == APART or reason == NOT_PD:
                return reason
            if events or reason == FULL:  # (FULL without events: the loop's own updates filled the record)
                self._add_checkpoint(step_end=reason == STEP_END, full=reason == FULL)

    def _add_checkpoint(self, step_end: bool, state: bool = True, full: bool = False) -> None:
        """A checkpoint here; ``state=False`` leaves its state to the caller (an update sets it
        after changing the state: a copy now would be thrown away); ``full``: the loop stopped
        for room (the record's chunk closes here)."""
        cp = (
            self._checkpoint(step_end=step_end)
            if state
            else Checkpoint.pending(self._n_events, self._k.copy(), step_end=step_end, n_log=self._n_log)
        )
        self.checkpoints.append(cp)
        self._since_checkpoint = 0
        if self.segment_records is not None:  # before any update at this instant changes P
            self.segment_records.keep(len(self.checkpoints) - 1, self._cov, full=full)

    def close(self) -> None:
        """Leave a checkpoint at the current state (the smoother needs one after the last sample)."""
        if self._since_checkpoint or self._n_log > self.checkpoints[-1].n_log:
            self._add_checkpoint(step_end=False)

    def close_step(self, smoother) -> None:
        """Smooth ``smoother``'s open step now (:class:`footnav.estimators.ekf.smoother.StepSmoother`)."""
        bufs = Buffers(smoother.record, smoother.smoothed, smoother.fill, smoother.mu, smoother.d)
        self._call(MODE_CLOSE, Span(self._stop_at, self._k, -np.inf, 0, False), self._state, bufs)

    # -- checkpoints and outputs ------------------------------------------------------------------
    def _checkpoint(self, step_end: bool) -> Checkpoint:
        return Checkpoint(self._n_events, self._k.copy(), self._state.copy(), step_end=step_end, n_log=self._n_log)

    def replay(self, a: int, b: int, mode: int, record: Record, smoothed: Smoothed, fill, mu, d) -> None:
        """Re-run from checkpoint ``a`` to checkpoint ``b`` in ``mode`` (``MODE_STEP`` or
        ``MODE_WHOLE``, see :func:`footnav.estimators.ekf._loop.run`) with the smoother's buffers;
        the filter's own state is untouched and the outputs written meanwhile are the first
        run's (the loop is deterministic)."""
        ca, cb = self.checkpoints[a], self.checkpoints[b]
        n_ev = cb.n_events - ca.n_events
        replay = Replay(
            self._log, ca.n_events, np.array([ca.n_log], dtype=np.int64), cb.n_log
        )  # the loop's own updates again
        span = Span(cb.k.copy(), ca.k.copy(), np.inf, n_ev, False)
        _, events = self._call(mode, span, ca.state.copy(), Buffers(record, smoothed, fill, mu, d), replay=replay)
        if events != n_ev:  # pragma: no cover - the checkpoints come from this very loop
            raise RuntimeError("replay did not reproduce the forward run")

    def smooth_kept(
        self, record: Record, fill: NDArray[np.int64], cov: NDArray[np.float64], smoothed: Smoothed, mu, d
    ) -> None:
        """The whole-walk smoother's backward pass over a chunk of segments (``MODE_BACK``;
        :class:`~footnav.estimators.ekf.smoother.SegmentRecords`): the ``fill`` (events, update
        rows) of ``record``, ``cov`` the covariance after its last event."""
        fill = np.array(fill, dtype=np.int64)
        state = self._state._replace(cov=cov)  # only cov is read
        self._call(
            MODE_BACK, Span(self._stop_at, self._k, -np.inf, 0, False), state, Buffers(record, smoothed, fill, mu, d)
        )

    def outputs(self, foot: int | None = None) -> Outputs:
        """Per-sample attitude, velocity, position and position covariance (xx, xy, yy, zz) of
        ``foot``, or of all feet concatenated (None); views of the filter's own arrays.

        A sample holds the forward estimate as the loop left it: a caller's :meth:`update` at a
        sample's instant shows from the next sample on (and in the smoothed outputs), not at
        that sample."""
        if foot is None:
            return self._out
        sl = slice(self._offsets[foot], self._offsets[foot + 1])
        return Outputs(self._out_q[sl], self._out_v[sl], self._out_p[sl], self._out_pcov[sl])

    def global_index(self, foot: int, k: int) -> int:
        """Index in the concatenated samples of all feet of the foot's sample ``k``."""
        return int(self._offsets[foot] + k)
