"""Rauch-Tung-Striebel smoothing of an :class:`~footnav.estimators.ekf.filter.InsFilter` run, step-wise or over the whole walk.

Chistyakov et al. (2021), Alg. 1 (Chistyakov et al. 2021) smooths the closed-loop error-state filter backwards
over the whole recording; OpenShoe's smoothed variant does it step by step. Both are computed
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
and at its caller's updates. The whole-walk smoother needs each segment's record backwards, last
segment first: the forward run keeps the records of its latest segments up to
``KEEP_RECORD_MB`` (:class:`SegmentRecords`), and the smoother re-runs from its checkpoint each
segment whose record was not kept. So memory is O(steps) plus at most that budget, and a
recording whose record fits in it is filtered once. A sample of one foot with 9 error states
takes 56 bytes, and 280 more when it has an update (the gain K is most of it; the
:class:`~footnav.estimators.ekf.records.Record` keeps one only for samples with updates): on the
simulator's walks (42 % of the samples in stance) about 175 bytes, so 64 MB per foot hold about
an hour of one foot at 100 Hz (31 minutes when every sample held a gain).
The step-wise smoother records each step as the filter runs and smooths it at its end, inside
the same compiled loop: two buffers' worth of memory whatever the length of the recording, and
no sample is run twice.
The backward pass itself is compiled in :mod:`footnav.estimators.ekf.backward` and run by the
forward loop's smoothing modes; this module decides what is recorded, kept and replayed.
"""

from __future__ import annotations

from typing import Literal

import numpy as np
from numpy.typing import NDArray

from footnav.nav import quaternion as quat
from footnav.estimators.ekf import filter as ekf_filter  # MAX_SEGMENT_EVENTS read at run time
from footnav.estimators.ekf.buffers import staggered
from footnav.estimators.ekf.filter import InsFilter
from footnav.estimators.ekf.loop import MODE_STEP, MODE_WHOLE
from footnav.estimators.ekf.records import SMOOTHED_PLACE, Record, Smoothed, empty_record

__all__ = ["KEEP_RECORD_MB", "SMOOTHERS", "SegmentRecords", "StepSmoother", "smooth"]

#: Smoothing modes: over the whole run, within each step, or none.
SMOOTHERS = ("whole", "step", "none")

#: Memory (MB) the forward run may keep of its record for the whole-walk smoother; segments
#: beyond it are re-run from their checkpoints instead.
KEEP_RECORD_MB = 64.0


class SegmentRecords:
    """The forward run's record of its latest segments, for the whole-walk smoother.

    Attach it as ``filt.segment_records`` before the filter runs: the compiled loop then records
    every sample (``MODE_RECORD``), and at each checkpoint the segment just finished is kept
    with the covariance after its last sample, before any caller's update at that instant (if
    it is long enough to be worth it, see :meth:`keep`). When the kept records exceed
    ``budget_mb`` the oldest are dropped; :func:`smooth` re-runs those segments instead. The
    backward pass starts at the end, so the latest segments are the ones worth keeping.

    Parameters
    ----------
    filt
        The filter, before it runs.
    budget_mb
        Largest memory of the kept records, MB (0: keep none; every segment is re-run).
    """

    def __init__(self, filt: InsFilter, budget_mb: float = KEEP_RECORD_MB) -> None:
        self.big = filt.n_states * filt.n_feet
        self.columns = filt.record_columns
        self.budget_bytes = int(budget_mb * 1e6)
        self.capacity = ekf_filter.MAX_SEGMENT_EVENTS  # the longest segment the filter makes
        self.bias_states = filt.n_states == 15
        self.record = self._empty()
        #: events and update rows recorded of the open segment
        self.fill = np.zeros(2, dtype=np.int64)
        #: checkpoint index -> (record, (events, update rows), covariance after the segment's
        #: last sample, bytes)
        self.kept: dict[int, tuple[Record, NDArray[np.int64], NDArray[np.float64], int]] = {}
        self.nbytes = 0

    def keep(self, checkpoint: int, cov: NDArray[np.float64]) -> None:
        """Keep the open segment, which ends at ``checkpoint``, and start the next one.

        The segment is kept as a copy of what it used, its update rows only for the samples
        with updates, and the buffer serves the next one: the copy costs a fraction of
        re-running the segment, which would filter its samples a second time.
        """
        used, rows = (int(x) for x in self.fill)
        fill = self.fill.copy()
        self.fill[:] = 0
        if used == 0 or self.budget_bytes <= 0:
            return
        rec = self.record.copy_head(used, rows, stagger=2 * used >= self.capacity)
        nbytes = _nbytes(rec) + cov.nbytes
        self.kept[checkpoint] = (rec, fill, cov.copy(), nbytes)
        self.nbytes += nbytes
        while self.nbytes > self.budget_bytes:
            self._drop(next(iter(self.kept)))  # the oldest: segments are kept in time order

    def _empty(self) -> Record:
        """A new, uninitialised buffer for the open segment."""
        return empty_record(self.big, self.capacity, self.columns, zero=False, bias_states=self.bias_states)

    def take(self, checkpoint: int) -> tuple[Record, NDArray[np.int64], NDArray[np.float64]] | None:
        """The kept segment ending at ``checkpoint`` (record, (events, update rows), covariance),
        released; or None."""
        if checkpoint not in self.kept:
            return None
        rec, fill, cov, _ = self.kept[checkpoint]
        self._drop(checkpoint)
        return rec, fill, cov

    def _drop(self, checkpoint: int) -> None:
        self.nbytes -= self.kept.pop(checkpoint)[3]


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
        self.record = empty_record(big, self.capacity, filt.record_columns, bias_states=self.bias_states)
        #: events and update rows recorded of the open step (an array the compiled loop updates)
        self.fill = np.zeros(2, dtype=np.int64)
        self.mu = np.zeros(big)
        self.d = np.zeros(big)
        self.smoothed = _copy_outputs(filt)

    def add_update(self, filt: InsFilter, h: NDArray, gain: NDArray, sy: NDArray, y: NDArray) -> None:
        """Record a caller's update (H, K, S^-1 y, y) after the open step's last sample."""
        m = len(y)
        if self.fill[0] == self.capacity:
            filt.close_step(self)
        if 2 * m > self.record.gain.shape[2]:  # more rows than any update so far: widen the record
            wide = empty_record(len(self.mu), self.capacity, 2 * m, bias_states=self.bias_states)
            for old, new in zip(self.record, wide):
                new[tuple(slice(0, s) for s in old.shape)] = old
            self.record = wide
        e, row = (int(x) for x in self.fill)
        rec = self.record
        rec.nu[e] = -m
        rec.gain[row, :, :m] = gain
        rec.gain[row, :, m : 2 * m] = h.T
        rec.sy[row, :m] = sy
        rec.y[row, :m] = y
        self.fill[:] = e + 1, row + 1

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
    kept = set() if sr is None else set(sr.kept)
    # a segment's record: its samples and the loop's own updates between them
    longest = max(
        (cps[b].n_events - cps[b - 1].n_events + cps[b].n_log - cps[b - 1].n_log for b in range(1, len(cps)) if b not in kept), default=0,
    )
    record = empty_record(big, longest, filt.record_columns, bias_states=filt.n_states == 15)
    fill = np.zeros(2, dtype=np.int64)
    mu, d = np.zeros(big), np.zeros(big)
    for b in range(len(cps) - 1, 0, -1):  # one segment at a time, last first
        for h, gain, sy, _ in reversed(cps[b].updates):  # the caller's updates at the segment's end
            mu += h.T @ (sy - gain.T @ mu)
        seg = None if sr is None else sr.take(b)
        if seg is None:  # not kept: re-run it from its checkpoint to record it
            filt.replay(b - 1, b, MODE_WHOLE, record, sm, fill, mu, d)
        else:
            filt.smooth_kept(seg[0], seg[1], seg[2], sm, mu, d)
    _correct_initial(filt, d.reshape(filt.n_feet, filt.n_states)[:, :9], sm)
    return sm


def _copy_outputs(filt: InsFilter) -> Smoothed:
    """Copies of the filter's attitude, velocity and position to be smoothed, at page offsets
    after the filter's own arrays (:mod:`footnav.estimators.ekf.buffers`)."""
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
