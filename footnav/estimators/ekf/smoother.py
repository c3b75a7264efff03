"""Rauch-Tung-Striebel smoothing of an :class:`~footnav.estimators.ekf.filter.InsFilter` run,
step-wise or over the whole walk.

Chistyakov et al. (2021), Alg. 1, smooths the closed-loop error-state filter backwards over the
whole recording; OpenShoe's smoothed variant does it step by step. Both are computed
here in the Bryson-Frazier form of the RTS smoother (Bierman 1977; Simon 2006 sec. 9.4), which
needs no n x n inversion. With the adjoint ``mu`` (mu = 0 after the last sample) and
``d = P mu``, the smoothed minus the filtered error state at each sample::

    through an update (K, y, S^-1 y):   d <- d + K y,          mu <- mu + H' (S^-1 y - K' mu)
    through a transition (F, Q):        d <- F^-1 (d - Q mu),  mu <- F' mu

(from ``P- = F P+ F' + Q`` and ``P+ = P- - K H P-``), and the smoothed state is the filtered
nominal state corrected by ``-d`` like a filter update (attitude C <- (I + [d_phi x]) C). So the
backward pass needs per sample only f^n dt and dt (and C with bias states), and per update K, y
and S^-1 y; never the covariance, which is only read (``d = P mu``) where a pass starts. The
filter's closed-loop resets only move the linearisation point: the recursion runs on the error
relative to each sample's predicted nominal state.

Memory: the filter keeps a checkpoint (state, covariance) every ``MAX_SEGMENT_EVENTS`` samples
and at its caller's updates. The whole-walk smoother needs the record backwards, last event
first: the forward run records into chunks of up to ``MAX_SEGMENT_EVENTS`` events, the caller's
updates between the samples, and keeps its latest chunks up to ``KEEP_RECORD_MB``
(:class:`SegmentRecords`); the smoother runs the backward pass over a kept chunk in one go and
re-runs the segments of a chunk that was not kept from their checkpoints into the same events.
So memory is O(steps) plus at most that budget, a recording whose record fits in it is filtered
once, and a fusion's update at every step costs no pass of its own. A sample of one foot with 9 error states
takes 56 bytes, and 280 more when it has an update (the gain K is most of it; the
:class:`~footnav.estimators.ekf._records.Record` keeps one only for samples with updates): on the
simulator's walks (42 % of the samples in stance) about 175 bytes, so 64 MB per foot hold about
an hour of one foot at 100 Hz (31 minutes when every sample held a gain).
The step-wise smoother records each step as the filter runs and smooths it at its end, inside
the same compiled loop: two buffers' worth of memory whatever the length of the recording, and
no sample is run twice.
The backward pass itself is compiled in :mod:`footnav.estimators.ekf._backward` and run by the
forward loop's smoothing modes; this module decides what is recorded, kept and replayed.
"""

from __future__ import annotations

from typing import Literal

import numpy as np
from numpy.typing import NDArray

from footnav.estimators.ekf import filter as ekf_filter  # MAX_SEGMENT_EVENTS read at run time
from footnav.estimators.ekf._buffers import staggered
from footnav.estimators.ekf._loop import MODE_RECORD, MODE_STEP, MODE_WHOLE
from footnav.estimators.ekf._records import (
    CALLER_UPDATE_ROWS,
    EV_CALLER_UPDATE,
    SMOOTHED_PLACE,
    Record,
    Smoothed,
    empty_record,
)
from footnav.estimators.ekf.filter import InsFilter
from footnav.nav import quaternion as quat

__all__ = ["KEEP_RECORD_MB", "SMOOTHERS", "SegmentRecords", "StepSmoother", "smooth"]

#: Smoothing modes: over the whole run, within each step, or none.
SMOOTHERS = ("whole", "step", "none")

#: Memory (MB) the forward run may keep of its record for the whole-walk smoother; segments
#: beyond it are re-run from their checkpoints instead.
KEEP_RECORD_MB = 64.0


class SegmentRecords:
    """The forward run's record in chunks of consecutive segments, for the whole-walk smoother.

    Attach it as ``filt.segment_records`` before the filter runs: the compiled loop then records
    every sample (``MODE_RECORD``) into the open chunk, and the caller's updates
    (:meth:`InsFilter.update`) are recorded there too, between the samples, as the step-wise
    smoother records them. A segment (from one checkpoint to the next) thus needs no record of
    its own: the filter tells :meth:`keep` where each ends, and the backward pass runs over a
    whole chunk at once (:func:`smooth`), through every segment and update in it. A chunk closes
    when it is full, or at a caller's update it has no room for (that update, and any later one
    at the same instant, is then undone in Python, after the chunk's end). A closed chunk is kept
    as a copy of what it used (its update rows only for the samples with updates) and the buffer
    serves the next one. When the kept chunks exceed ``budget_mb`` the oldest are dropped, and
    :func:`smooth` re-runs their segments from their checkpoints into a chunk of the same events,
    so the smoothed result does not depend on the budget. The backward pass starts at the end,
    so the latest chunks are the ones worth keeping.

    Parameters
    ----------
    filt
        The filter, before it runs.
    budget_mb
        Largest memory of the kept chunks, MB (0: keep none; every segment is re-run).
    """

    def __init__(self, filt: InsFilter, budget_mb: float = KEEP_RECORD_MB) -> None:
        self.big = filt.n_states * filt.n_feet
        self.columns = filt.record_columns
        self.budget_bytes = int(budget_mb * 1e6)
        self.capacity = ekf_filter.MAX_SEGMENT_EVENTS  # a segment never outgrows a chunk
        self.bias_states = filt.n_states == 15
        self.record = self.empty(zero=False)
        #: events and update rows recorded in the open chunk
        self.fill = np.zeros(2, dtype=np.int64)
        #: the open chunk's first and last checkpoint (None before its first) and the
        #: covariance after its last event
        self._first: int | None = None
        self._last: int | None = None
        self._cov = np.zeros((self.big, self.big))
        #: every closed chunk by its last checkpoint: (first checkpoint, covariance after its
        #: last event)
        self.chunks: dict[int, tuple[int, NDArray[np.float64]]] = {}
        #: the kept ones: (record, (events, update rows), bytes)
        self.kept: dict[int, tuple[Record, NDArray[np.int64], int]] = {}
        #: caller's updates at a checkpoint's instant that its chunk holds (the first ones);
        #: -1 - n once the chunk closed there
        self._recorded: dict[int, int] = {}
        self.nbytes = 0

    def empty(self, zero: bool = True) -> Record:
        """A buffer for one chunk (:func:`buffer_record`)."""
        return buffer_record(self.big, self.capacity, self.columns, zero=zero, bias_states=self.bias_states)

    def keep(self, checkpoint: int, cov: NDArray[np.float64], *, full: bool = False) -> None:
        """The open chunk's segments now end at ``checkpoint``, ``cov`` the covariance after its
        last sample (before any caller's update at that instant); the chunk closes here when
        ``full`` (the loop stopped for room: its own updates need more than one row per event)
        or when it is."""
        if self._first is None:
            self._first = checkpoint
        self._last = checkpoint
        self._cov[...] = cov
        if full or self.fill[0] >= self.capacity:
            self._close()

    def add_update(
        self, checkpoint: int, h: NDArray, gain: NDArray, sy: NDArray, y: NDArray, cov: NDArray[np.float64]
    ) -> None:
        """Record a caller's update at ``checkpoint``'s instant (``cov``: the covariance after
        it) in the open chunk when that chunk ends at ``checkpoint`` and has room; else the chunk
        closes there."""
        if self._last != checkpoint or self._recorded.get(checkpoint, 0) < 0:
            return  # its chunk closed at this instant: undone in Python, as the updates after it
        if len(y) > self.record.gain.shape[2] or not has_room(self.record, self.fill):
            self._recorded[checkpoint] = -1 - self._recorded.get(checkpoint, 0)
            self._close()
            return
        write_caller_update(self.record, self.fill, h, gain, sy, y)
        self._recorded[checkpoint] = self._recorded.get(checkpoint, 0) + 1
        self._cov[...] = cov

    def recorded(self, checkpoint: int) -> int:
        """How many of the caller's updates at ``checkpoint`` (the first ones) its chunk holds."""
        n = self._recorded.get(checkpoint, 0)
        return n if n >= 0 else -1 - n

    def _close(self, copy: bool = True) -> None:
        """Close the open chunk: keep a copy of what it used (within the budget) and start the
        next in the same buffer; ``copy=False`` keeps the buffer itself (the run is over)."""
        if self._last is None:
            self.fill[:] = 0
            return
        assert self._first is not None  # set with _last (keep)
        self.chunks[self._last] = (self._first, self._cov.copy())
        used, rows = (int(x) for x in self.fill)
        if used and self.budget_bytes > 0:
            rec = self.record.copy_head(used, rows, stagger=True) if copy else self.record
            nbytes = _nbytes(rec.head(used, rows))
            self.kept[self._last] = (rec, self.fill.copy(), nbytes)
            self.nbytes += nbytes
            while self.nbytes > self.budget_bytes:
                self._drop(next(iter(self.kept)))  # the oldest: chunks are kept in time order
        self.fill[:] = 0
        self._first = self._last = None

    def finish(self) -> None:
        """Close the open chunk in place: the run is over (:func:`smooth`)."""
        self._close(copy=False)

    def take(self, checkpoint: int) -> tuple[int, NDArray[np.float64], tuple[Record, NDArray[np.int64]] | None] | None:
        """The chunk ending at ``checkpoint``: (its first checkpoint, the covariance after its last
        event, (record, (events, update rows)) if kept, else None), the record released; None
        when no chunk ends there."""
        if checkpoint not in self.chunks:
            return None
        first, cov = self.chunks[checkpoint]
        kept = self.kept.get(checkpoint)
        if kept is not None:
            self._drop(checkpoint)
        return first, cov, None if kept is None else kept[:2]

    def _drop(self, checkpoint: int) -> None:
        self.nbytes -= self.kept.pop(checkpoint)[2]


def buffer_record(big: int, capacity: int, columns: int, *, zero: bool = True, bias_states: bool = True) -> Record:
    """A record buffer the loop fills (a step, or a chunk of segments): ``capacity`` events, a
    row for each and rows for the caller's updates between them (two rows each)."""
    return empty_record(big, capacity, columns, rows=capacity + capacity // 4 + 2, zero=zero, bias_states=bias_states)


def has_room(record: Record, fill: NDArray[np.int64]) -> bool:
    """Whether ``record``, filled up to ``fill`` (events, rows), holds one more caller's update
    and still a row for each event left (the loop's events take at most one row each)."""
    events_left = len(record.k) - int(fill[0])
    return events_left >= 1 and len(record.gain) - int(fill[1]) - 2 >= events_left - 1


def write_caller_update(
    record: Record, fill: NDArray[np.int64], h: NDArray, gain: NDArray, sy: NDArray, y: NDArray
) -> None:
    """Record a caller's update of m rows as the ``EV_CALLER_UPDATE`` event at ``fill[0]`` (its
    ``width`` m): K, S^-1 y and y in update row ``fill[1]``, H' in the next
    (:func:`footnav.estimators.ekf._backward.smooth_back` reads them); ``fill`` is advanced."""
    m = len(y)
    e, row = int(fill[0]), int(fill[1])
    record.kind[e] = EV_CALLER_UPDATE
    record.width[e] = m
    record.k[e] = -1  # no sample
    record.gain[row, :, :m] = gain
    record.gain[row + 1, :, :m] = h.T
    record.sy[row, :m] = sy
    record.y[row, :m] = y
    fill[0], fill[1] = e + 1, row + CALLER_UPDATE_ROWS


def _nbytes(record: Record) -> int:
    return sum(a.nbytes for a in record)


class StepSmoother:
    """Step-wise RTS smoothing during the forward run (OpenShoe's smoothed variant).

    Attach it as ``filt.step_smoother``: the filter's compiled loop records every sample into
    :attr:`record` and, when a foot's stance ends, smooths the finished step backwards from its
    end (mu = 0 there) into :attr:`smoothed` and starts the buffer again. The caller's updates
    within a step (:meth:`InsFilter.update`) are recorded between its samples and smoothed with
    it. A step longer than ``capacity`` events (a foot standing still for minutes) is cut into
    pieces there.

    Parameters
    ----------
    filt
        The filter, before it runs (the smoothed arrays start as copies of its outputs).
    capacity
        Samples the buffer holds (default ``MAX_SEGMENT_EVENTS``).
    """

    def __init__(self, filt: InsFilter, capacity: int | None = None) -> None:
        big = filt.n_states * filt.n_feet
        self.capacity = int(ekf_filter.MAX_SEGMENT_EVENTS if capacity is None else capacity)
        self.bias_states = filt.n_states == 15
        self.record = buffer_record(big, self.capacity, filt.record_columns, bias_states=self.bias_states)
        #: events and update rows recorded of the open step (an array the compiled loop updates)
        self.fill = np.zeros(2, dtype=np.int64)
        self.mu = np.zeros(big)
        self.d = np.zeros(big)
        self.smoothed = _copy_outputs(filt)

    def add_update(self, filt: InsFilter, h: NDArray, gain: NDArray, sy: NDArray, y: NDArray) -> None:
        """Record a caller's update (H, K, S^-1 y, y) after the open step's last sample."""
        m = len(y)
        if not has_room(self.record, self.fill):
            filt.close_step(self)
        if m > self.record.gain.shape[2]:  # more rows than any update so far: widen the record
            wide = empty_record(
                len(self.mu), self.capacity, m, rows=len(self.record.gain), bias_states=self.bias_states
            )
            for old, new in zip(self.record, wide):
                # mypy joins the record's differently typed ndarray fields to object
                new[tuple(slice(0, s) for s in old.shape)] = old  # type: ignore[index, attr-defined]
            self.record = wide
        write_caller_update(self.record, self.fill, h, gain, sy, y)

    def result(self, filt: InsFilter) -> Smoothed:
        """Smoothed attitude, velocity, position of all samples (the open step is smoothed now)."""
        filt.close_step(self)
        return self.smoothed


def smooth(filt: InsFilter, mode: Literal["whole", "step"] = "whole") -> Smoothed:
    """Smoothed attitude, velocity and position of every sample of a finished filter run.

    Parameters
    ----------
    filt
        The filter after its last :meth:`~InsFilter.run_until`.
    mode
        ``"whole"``: one RTS pass over the whole run (Chistyakov et al. (2021), Alg. 1), so a measurement at the
        end (the closed-loop constraint) corrects everything before it. ``"step"``: each step,
        from one step end to the next, is smoothed by its own zero-velocity updates given its
        start state; taken from the filter's :class:`StepSmoother` when it ran with one, else
        the run is replayed through one.

    Returns
    -------
    Smoothed
        Attitude (M, 4), velocity (M, 3), position (M, 3) of the concatenated samples of all
        feet (foot f's rows: :meth:`InsFilter.outputs` order); nav frame, SI units.
    """
    if mode not in ("whole", "step"):
        raise ValueError(f"unknown smoothing mode {mode!r}")
    if mode == "step" and filt.step_smoother is not None:
        return filt.step_smoother.result(filt)
    filt.close()
    cps = filt.checkpoints
    if mode == "step":  # the forward run again, through a step smoother, the caller's updates in place
        ss = StepSmoother(filt)
        for b in range(1, len(cps)):
            filt.replay(b - 1, b, MODE_STEP, ss.record, ss.smoothed, ss.fill, ss.mu, ss.d)
            for h, gain, sy, y in cps[b].updates:
                ss.add_update(filt, h, gain, sy, y)
        return ss.result(filt)
    big = filt.n_states * filt.n_feet
    sm = _copy_outputs(filt)
    sr = filt.segment_records
    if sr is not None:
        sr.finish()
    mu, d = np.zeros(big), np.zeros(big)
    record, fill = None, np.zeros(2, dtype=np.int64)  # for re-runs, made at the first
    b = len(cps) - 1
    while b > 0:  # last first: a chunk of segments at once, or (without chunks) one segment
        chunk = None if sr is None else sr.take(b)
        # the caller's updates at the segment's end that its chunk does not hold
        for h, gain, sy, _ in reversed(cps[b].updates[0 if chunk is None else sr.recorded(b) :]):
            mu += h.T @ (sy - gain.T @ mu)
        if chunk is None:  # a filter without chunks: re-run the segment to record it
            if record is None:
                longest = max(
                    cps[c].n_events - cps[c - 1].n_events + cps[c].n_log - cps[c - 1].n_log for c in range(1, len(cps))
                )
                record = empty_record(big, longest, filt.record_columns, bias_states=filt.n_states == 15)
            filt.replay(b - 1, b, MODE_WHOLE, record, sm, fill, mu, d)
            b -= 1
            continue
        first, cov, kept = chunk
        if kept is None:  # dropped: re-run its segments and updates into a chunk of the same events
            if record is None or len(record.k) < sr.capacity:
                record = sr.empty()
            fill[:] = 0
            for c in range(first, b + 1):
                filt.replay(c - 1, c, MODE_RECORD, record, sm, fill, mu, d)
                for h, gain, sy, y in cps[c].updates[: sr.recorded(c)]:
                    write_caller_update(record, fill, h, gain, sy, y)
            kept = record, fill
        filt.smooth_kept(kept[0], kept[1], cov, sm, mu, d)
        b = first - 1
    _correct_initial(filt, d.reshape(filt.n_feet, filt.n_states)[:, :9], sm)
    return sm


def _copy_outputs(filt: InsFilter) -> Smoothed:
    """Copies of the filter's attitude, velocity and position to be smoothed, at page offsets
    after the filter's own arrays (:mod:`footnav.estimators.ekf._buffers`)."""
    out = filt.outputs()
    outputs = (out.q, out.v, out.p)
    copies = staggered([(x.shape, x.dtype) for x in outputs], first=SMOOTHED_PLACE)
    for dst, src in zip(copies, outputs):
        dst[...] = src
    return Smoothed(*copies)


def _correct_initial(filt: InsFilter, d_start: NDArray[np.float64], sm: Smoothed) -> None:
    """Smooth each foot's initial state (and the samples before it) by its correction d_start[f]."""
    sm_q, sm_v, sm_p = sm
    out = filt.outputs()
    for f in range(filt.n_feet):
        d = d_start[f]
        a, k = filt.global_index(f, 0), int(filt.checkpoints[0].k[f])
        dq = quat.from_rotvec(d[:3])
        sm_q[a : k + 1] = quat.normalize(quat.multiply(dq, out.q[a : k + 1]))
        sm_v[a : k + 1] = out.v[a : k + 1] - d[3:6]
        sm_p[a : k + 1] = out.p[a : k + 1] - d[6:9]
