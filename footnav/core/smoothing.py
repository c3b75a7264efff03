"""Rauch-Tung-Striebel smoothing of an :class:`~footnav.core.ins_filter.InsFilter` run.

Seed 002 Alg. 1 (Chistyakov et al. 2021) smooths the closed-loop error-state filter backwards
over the whole recording; OpenShoe's smoothed variant does it step by step. Both are computed
here in the Bryson-Frazier form of the RTS smoother (Bierman 1977; Simon 2006 sec. 9.4), which
needs no n x n inversion: with the adjoint ``mu`` (mu = 0 after the last sample),

    delta_e = P+_e mu                                 (smoothed minus filtered error at event e)
    mu <- H' S^-1 y + (I - K H)' mu                   (each update at e, in reverse order)
    mu <- F_e' mu                                     (the transition into e)

and the smoothed state is the filtered nominal state corrected by ``-delta`` like a filter
update (attitude C <- (I + [delta_phi x]) C). The filter's closed-loop resets only move the
linearisation point: the recursion runs on the error relative to each sample's predicted
nominal state.

Memory: the filter keeps a checkpoint (state, covariance) per step; each segment between two
checkpoints is re-run from its first checkpoint to record what the backward pass needs, so the
smoother holds one segment at a time: O(steps + longest segment), not O(samples).
"""

from __future__ import annotations

from typing import Literal

import numpy as np
from numba import njit
from numpy.typing import NDArray

from footnav.core import quaternion as quat
from footnav.core.ins_filter import MAX_SEGMENT_EVENTS, InsFilter, _empty_record, _ft_apply
from footnav.core.quaternion import from_rotvec_nb, multiply_nb, normalize_nb

__all__ = ["smooth", "StepSmoother", "backward", "SMOOTHERS"]

#: Smoothing modes: over the whole run, within each step, or none.
SMOOTHERS = ("whole", "step", "none")


@njit(cache=True, error_model="numpy")
def backward(mu, n, lo, hi, ev_foot, ev_k, ev_f, ev_c, ev_dt, ev_prows, ev_m, ev_idx, ev_gain, ev_sy, out_q, out_v, out_p, sm_q, sm_v, sm_p):
    """Backward pass over the recorded events ``lo:hi``: sm[k] = filtered out[k] corrected by -delta."""
    big = len(mu)
    d = np.zeros(9)
    dq = np.zeros(4)
    q_tmp = np.zeros(4)
    kt = np.zeros(6)
    for e in range(hi - 1, lo - 1, -1):
        f = ev_foot[e]
        o = f * n
        k = ev_k[e]
        for i in range(9):
            acc = 0.0
            for j in range(big):
                acc += ev_prows[e, i, j] * mu[j]
            d[i] = acc
        from_rotvec_nb(d[0], d[1], d[2], dq)
        multiply_nb(dq, out_q[k], q_tmp)
        normalize_nb(q_tmp)
        for i in range(4):
            sm_q[k, i] = q_tmp[i]
        for i in range(3):
            sm_v[k, i] = out_v[k, i] - d[3 + i]
            sm_p[k, i] = out_p[k, i] - d[6 + i]
        m = ev_m[e]
        for a in range(m):
            acc = 0.0
            for i in range(big):
                acc += ev_gain[e, i, a] * mu[i]
            kt[a] = acc
        for a in range(m):
            mu[ev_idx[e, a]] += ev_sy[e, a] - kt[a]
        _ft_apply(mu, o, n, ev_f[e, 0], ev_f[e, 1], ev_f[e, 2], ev_c[e], ev_dt[e])


@njit(cache=True, error_model="numpy")
def _shift(lo, hi, ev_foot, ev_k, offset, sm_p):
    """Add ``offset[f]`` (m) to the smoothed position of every event ``lo:hi`` of foot f."""
    for e in range(lo, hi):
        f = ev_foot[e]
        k = ev_k[e]
        for i in range(3):
            sm_p[k, i] += offset[f, i]


def _smooth_group(filt: InsFilter, segments: list, mu: NDArray[np.float64], sm: tuple, relative: bool) -> None:
    """Backward pass over consecutive segments, newest first; ``segments`` holds (record arrays,
    first and last + 1 event in them, index of the checkpoint that ends the segment) in forward
    order and ``mu`` the adjoint after the last.

    ``relative``: the group is one step, smoothed by its own measurements (mu = 0 at its end).
    Position is an integral, so the step's position corrections are taken relative to its
    start: the step starts where the step before it ended (continuity), and its smoothed
    displacement is added. Velocity and attitude are the step's smoothed values as they are.
    """
    out = (filt._out_q, filt._out_v, filt._out_p)
    n = filt.n_states
    for rec, lo, hi, b in reversed(segments):
        for h, gain, sy in reversed(filt.checkpoints[b].updates):
            mu += h.T @ (sy - gain.T @ mu)  # mu <- H' S^-1 y + (I - K H)' mu
        backward(mu, n, lo, hi, *rec, *out, *sm)
    start = segments[0][3] - 1
    d_start = (filt.checkpoints[start].cov @ mu).reshape(filt.n_feet, n)[:, :9]
    if relative:
        # sm_p = out_p - d_k + d_start + (what the step before moved the start sample by)
        offset = np.empty((filt.n_feet, 3))
        for f in range(filt.n_feet):
            k = int(filt.checkpoints[start].k[f])
            offset[f] = d_start[f, 6:9] + sm[2][k] - filt._out_p[k]
        for rec, lo, hi, _ in segments:
            _shift(lo, hi, rec[0], rec[1], offset, sm[2])
    elif start == 0:
        _correct_initial(filt, d_start, sm)


def _correct_initial(filt: InsFilter, d_start: NDArray[np.float64], sm: tuple) -> None:
    """Smooth each foot's initial state (and the samples before it) by its correction d_start[f]."""
    sm_q, sm_v, sm_p = sm
    for f in range(filt.n_feet):
        d = d_start[f]
        a, k = filt.global_index(f, 0), int(filt.checkpoints[0].k[f])
        dq = quat.from_rotvec(d[:3])
        sm_q[a : k + 1] = quat.normalize(quat.multiply(dq, filt._out_q[a : k + 1]))
        sm_v[a : k + 1] = filt._out_v[a : k + 1] - d[3:6]
        sm_p[a : k + 1] = filt._out_p[a : k + 1] - d[6:9]


class StepSmoother:
    """Step-wise RTS smoothing during the forward run (OpenShoe's smoothed variant).

    The filter records every sample into this smoother's buffer; when the next step starts, the
    finished step is smoothed backwards from its end (mu = 0 there) and its buffer is reused.
    Memory: two buffers of ``capacity`` samples, whatever the length of the recording; no sample
    is run twice. A foot standing still longer than ``capacity`` samples is cut into pieces there.
    """

    def __init__(self, filt: InsFilter, capacity: int = MAX_SEGMENT_EVENTS) -> None:
        big = filt.n_states * filt.n_feet
        self.capacity = capacity
        self._bufs = [_empty_record(big, capacity), _empty_record(big, capacity)]
        self._cur = 0
        self._used = 0  # events recorded in the current buffer
        self._open = 0  # where the events not yet closed by a checkpoint start
        self._target = (0, 0)
        self._pending: list[tuple[int, int, int]] = []  # (offset, events, index of end checkpoint)
        self._sm = tuple(x.copy() for x in (filt._out_q, filt._out_v, filt._out_p))

    def before_run(self, filt: InsFilter) -> tuple[tuple, int, int]:
        step_done = filt.checkpoints[-1].step_end and self._pending and self._open == self._used
        self._target = (1 - self._cur, 0) if step_done else (self._cur, self._used)
        b, off = self._target
        return self._bufs[b], off, self.capacity - off

    def after_run(self, filt: InsFilter, events: int) -> None:
        if events == 0:
            return
        b, off = self._target
        if b != self._cur:  # a new step began: no more updates can come for the previous one
            self._flush(filt)
            self._cur, self._used, self._open = b, 0, 0
        self._used = off + events

    def on_checkpoint(self, filt: InsFilter) -> None:
        if self._used > self._open:
            self._pending.append((self._open, self._used - self._open, len(filt.checkpoints) - 1))
            self._open = self._used

    def _flush(self, filt: InsFilter) -> None:
        if self._pending:
            buf = self._bufs[self._cur]
            segments = [(buf, off, off + ev, b) for off, ev, b in self._pending]
            _smooth_group(filt, segments, np.zeros(filt.n_states * filt.n_feet), self._sm, relative=True)
        self._pending = []

    def result(self, filt: InsFilter) -> tuple[NDArray, NDArray, NDArray]:
        """Smoothed attitude, velocity, position of all samples (the run so far ends a step)."""
        filt.close()
        self._flush(filt)
        self._used = self._open = 0
        return self._sm


def smooth(filt: InsFilter, mode: Literal["whole", "step"] = "whole") -> tuple[NDArray, NDArray, NDArray]:
    """Smoothed attitude, velocity and position of every sample of a finished filter run.

    Parameters
    ----------
    filt
        The filter after its last :meth:`~InsFilter.run_until`.
    mode
        ``"whole"``: one RTS pass over the whole run (seed 002 Alg. 1), so a measurement at the
        end (the closed-loop constraint) corrects everything before it. ``"step"``: each step,
        from one step end to the next, is smoothed by its own zero-velocity updates given its
        start state; taken from the filter's :class:`StepSmoother` when it ran with one.

    Returns
    -------
    tuple of ndarray
        Attitude (M, 4), velocity (M, 3), position (M, 3) of the concatenated samples of all
        feet (foot f's rows: :meth:`InsFilter.outputs` order); nav frame, SI units.
    """
    if mode not in ("whole", "step"):
        raise ValueError(f"unknown smoothing mode {mode!r}")
    if mode == "step" and isinstance(filt.recorder, StepSmoother):
        return filt.recorder.result(filt)
    filt.close()
    sm = tuple(x.copy() for x in (filt._out_q, filt._out_v, filt._out_p))
    big = filt.n_states * filt.n_feet
    cps = filt.checkpoints
    if mode == "whole":
        mu = np.zeros(big)
        for b in range(len(cps) - 1, 0, -1):  # one segment at a time: memory O(one segment)
            rec = filt.replay(b - 1, b)
            _smooth_group(filt, [(rec, 0, len(rec[0]), b)], mu, sm, relative=False)
        return sm
    # step-wise from checkpoints: the segments between two step ends make a group; groups in
    # forward order, as the StepSmoother meets them, so each starts where the one before ended
    group: list = []
    for b in range(1, len(cps)):
        rec = filt.replay(b - 1, b)
        group.append((rec, 0, len(rec[0]), b))
        if cps[b].step_end or b == len(cps) - 1:
            _smooth_group(filt, group, np.zeros(big), sm, relative=True)
            group = []
    return sm
