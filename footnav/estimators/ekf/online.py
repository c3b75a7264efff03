"""The EKF's online filter: :class:`InsFilter` in bounded segments, as a stream runs it.

A stream (:mod:`footnav.pipeline.online`) fills a segment with the samples that became final
(:meth:`~InsFilter.extend`) and, when it is full, starts the next one with :meth:`OnlineInsFilter.rebase`:
the samples it still needs, the state where the filter stands (or at a checkpoint) and the
step-wise smoother's open step, its record re-indexed to the new segment. Every index this
module takes or gives is a foot's own sample index in the segment (:meth:`InsFilter.index`'s);
the record's layout (:class:`~footnav.estimators.ekf._records.Record`) stays inside the EKF.
This is the reference implementation of :class:`footnav.core.component.OnlineFilter`.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

from footnav.estimators.ekf._records import EV_SAMPLE, Record, Samples
from footnav.estimators.ekf.filter import InsFilter
from footnav.estimators.ekf.smoother import StepSmoother

__all__ = ["OnlineInsFilter"]


class OnlineInsFilter(InsFilter):
    """:class:`InsFilter` with what a stream needs to run it in segments (the
    :class:`footnav.core.component.OnlineFilter` contract): :meth:`rebase`, the smoother's open step
    (:meth:`open_step_start`, :meth:`close_open_step`) and the final per-sample estimate
    (:meth:`final_outputs`). :meth:`footnav.estimators.ekf.EkfEstimator.start` returns one."""

    def open_step_start(self, foot: int) -> int | None:
        """The first sample of ``foot``'s open step (recorded by the step-wise smoother, not yet
        smoothed), or None when there is none: a :meth:`rebase` keeps the sample before it."""
        ss = self.step_smoother
        fill = int(ss.fill[0]) if ss is not None else 0
        if not fill:
            return None
        rec = ss.record
        mine = (rec.foot[:fill] == foot) & (rec.kind[:fill] == EV_SAMPLE)
        if not mine.any():
            return None
        return int(rec.k[:fill][mine].min()) - self.global_index(foot, 0)

    def close_open_step(self) -> None:
        """Smooth the step-wise smoother's open step now (at the end of a stream); nothing
        without one."""
        if self.step_smoother is not None:
            self.close_step(self.step_smoother)

    def final_outputs(self, foot: int) -> tuple[NDArray[np.float64], ...]:
        """``foot``'s per-sample attitude, velocity, position (step-wise smoothed where the
        filter smooths steps, the forward estimate otherwise) and forward position covariance
        (xx, xy, yy, zz); views, valid up to the last closed step."""
        q, v, p, pcov = self.outputs(foot)
        if self.step_smoother is not None:
            g0 = self.global_index(foot, 0)
            q, v, p = (x[g0 : g0 + self.capacity(foot)] for x in self.step_smoother.smoothed)
        return q, v, p, pcov

    def rebase(
        self,
        keep_from: Sequence[int],
        capacity: Sequence[int],
        *,
        at: int | None = None,
        step_smoother: bool | None = None,
    ) -> OnlineInsFilter:
        """The next segment: a filter holding each foot's samples from ``keep_from[f]`` on (those
        given so far), with room for ``capacity[f]``, a checkpoint at every step end.

        ``at`` None: it continues where this filter stands, with the outputs (and smoothed
        outputs) of the samples kept up to there, and the step-wise smoother's open step
        (``keep_from[f]`` at most the sample before :meth:`open_step_start`). ``at`` a
        checkpoint's index: it resumes from that checkpoint (a step end, where the open step is
        empty; one where the filter stands closes its open step first), the kept samples after
        it to be run again (the loop is deterministic: the same numbers). ``step_smoother``:
        smooth step-wise (default: as this filter does).
        """
        if step_smoother is None:
            step_smoother = self.step_smoother is not None
        keep = [int(s) for s in keep_from]
        if at is None:
            state, index = self.state(), [self.index(f) for f in range(self.n_feet)]
            for f, s in enumerate(keep):
                first = self.open_step_start(f)
                if first is not None and s > first - 1:
                    raise ValueError(f"rebase: foot {f}'s open step starts at sample {first}; keep_from {s} drops it")
        else:
            cp = self.checkpoints[at]
            state, index = cp.state, [int(cp.k[f]) - self.global_index(f, 0) for f in range(self.n_feet)]
            if index == [self.index(f) for f in range(self.n_feet)]:
                self.close_open_step()  # the cut the next sample would make
        base = [k - s for k, s in zip(index, keep)]
        new = self._segment(keep, capacity, base, step_smoother)
        new.resume(state, base)
        self._copy_outputs(new, keep, base)
        if at is None:
            self._carry_open_step(new, keep)
        new.meta = self.meta
        return new

    def _segment(
        self, keep: list[int], capacity: Sequence[int], base: list[int], step_smoother: bool
    ) -> OnlineInsFilter:
        """A filter over the kept samples (its noise and initial covariance this one's)."""
        n, feet = self.n_states, range(self.n_feet)
        samples = [Samples._make(x[keep[f] :] for x in self.samples(f)) for f in feet]
        new = OnlineInsFilter(
            [x[0] for x in samples],
            [x[1] for x in samples],
            [x[2] for x in samples],
            [x[3] for x in samples],
            list(base),
            [self.quaternion(f) for f in feet],
            [self.position(f) for f in feet],
            [self.biases(f)[1] for f in feet],
            np.diag(self.covariance)[:n],
            self.noise,
            n,
            capacity=[int(c) for c in capacity],
            zupt=[x[4] for x in samples],
        )
        new.step_stops = True
        if step_smoother:
            new.step_smoother = StepSmoother(new)
        return new

    def _copy_outputs(self, new: OnlineInsFilter, keep: list[int], base: list[int]) -> None:
        """The outputs (and smoothed outputs) of the kept samples up to the new start."""
        ss, nss = self.step_smoother, new.step_smoother
        for f, (s, b) in enumerate(zip(keep, base)):
            for src, dst in zip(self.outputs(f), new.outputs(f)):
                dst[: b + 1] = src[s : s + b + 1]
            if ss is not None and nss is not None:
                go, gn = self.global_index(f, 0), new.global_index(f, 0)
                for src, dst in zip(ss.smoothed, nss.smoothed):
                    dst[gn : gn + b + 1] = src[go + s : go + s + b + 1]

    def _carry_open_step(self, new: OnlineInsFilter, keep: list[int]) -> None:
        """The step-wise smoother's open step, its samples re-indexed to ``new``'s."""
        ss, nss = self.step_smoother, new.step_smoother
        fill = int(ss.fill[0]) if ss is not None else 0
        if not fill or nss is None:
            return
        rec = Record(*(np.array(x) for x in ss.record))
        for f in range(self.n_feet):
            mine = (rec.foot[:fill] == f) & (rec.kind[:fill] == EV_SAMPLE)
            rec.k[:fill][mine] += new.global_index(f, 0) - self.global_index(f, 0) - keep[f]
        nss.record = rec
        nss.fill[:] = ss.fill
