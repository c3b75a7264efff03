"""Both feet in one joint filter on a live stream: a coupled fusion online (:mod:`footnav.pipeline.online`).

A coupled fusion (``range``) ties the feet together at common instants, so online it runs on a
joint filter fed by both feet's final samples, and only as far as both feet have arrived. What it
does is what the fusion's offline run does (:func:`footnav.fusion.joint.fuse_on_common_span`),
step by step:

1. **Common span.** It starts at the later foot's first sample; each foot's samples before it
   are the foot estimated alone (the per-foot stream, :class:`~footnav.pipeline.online_foot.FootStream`,
   which runs beside the joint filter), continued rigidly from the fused estimate's start. It
   ends at the earlier foot's last sample, known at ``close``; a foot's samples after it are
   the foot alone again, continued from the fused end.
2. **Start.** Each foot's first-step heading (:func:`footnav.fusion.joint.first_step_yaw`) is
   found on its samples from the common start, once a step long enough has closed; then the
   estimator's ``start`` aligns both feet, ``step_width_m`` apart, in one filter.
3. **Run.** Each push gives the joint filter the final samples of both feet up to the newest time
   both have reached, and the fusion's session (:class:`footnav.core.component.FusionSession`)
   applies its measurements at times up to the last sample whose step end is known. With
   step-wise smoothing a step end of either foot closes the open step of both: every sample up
   to it is final.
4. **Segments.** The filter holds a bounded segment of samples; when it is full, a new one
   starts where the filter stands, with the samples not yet final and the smoother's open step
   (its record re-indexed): nothing is filtered twice, and a caller's updates stay in place.

The feet wait for each other: while one foot is silent, nothing of either becomes final (the
forward estimate still moves with the joint filter as far as both feet have arrived).
"""

from __future__ import annotations

import math
from collections import deque
from typing import Any

import numpy as np
from numpy.typing import NDArray

from footnav.core.errors import CompositionError, DataQualityWarning
from footnav.core.online_contract import OnlineFilter
from footnav.core.types import FootTrajectory, FusionResult, ImuData, StanceResult, stance_intervals
from footnav.core.warning_log import recording, warn
from footnav.fusion.independent import midpoint_path
from footnav.fusion.joint import (
    OUTSIDE_SPAN,
    FeetView,
    continue_rigidly,
    forward_only,
    fused_start,
    on_whole_span,
    start_filter,
)
from footnav.nav.heading import rotate_about_z
from footnav.nav.spans import CommonSpan, FootCut, common_bounds
from footnav.pipeline.online_foot import SEGMENT_SAMPLES, FootStream, _Grow
from footnav.pipeline.online_io import FootUpdate, ForwardEstimate, empty_update
from footnav.pipeline.online_steps import StepTracker, stance_runs

__all__ = ["JointFoot", "JointStream"]

_F8 = np.float64


class JointFoot:
    """One foot's part of a :class:`JointStream`: its fused final samples, the foot alone outside
    the common span, its closed steps. Global indices count the foot's samples since the stream
    began (as :class:`FootStream`'s)."""

    def __init__(self, alone: FootStream) -> None:
        self.alone = alone
        self.foot = alone.foot
        # fused final samples: t, q, v, p, position covariance (xx, xy, yy, zz), stance
        self.out = _Grow([((), _F8), ((4,), _F8), ((3,), _F8), ((3,), _F8), ((4,), _F8), ((), np.bool_)])
        self.n_out = 0  # fused samples final before this global index
        self.emitted = 0  # samples returned so far
        self.t_emitted = -math.inf  # the last one's time, s
        self.front_done = False
        self.steps = StepTracker(alone.foot, 0.0)  # the joint frame is the first step's already
        self.i0 = 0  # the first sample in the common span
        self.first = 0  # the first sample the result takes from the fused estimate
        self.yaw: float | None = None
        self.tries = 0  # closed stances when the first-step heading was last looked for
        self.n_fed = 0  # samples given to the joint filter
        self.seg0 = 0  # the segment's sample 0
        self.in_run = False  # the last fed sample is in stance
        self.runs_seen = 0  # stance runs begun in the common span (the first is no landing)
        self.run_starts: deque[int] = deque(maxlen=4)  # the latest stance starts fed, global
        self.anchor: tuple | None = None  # fused (position, quaternion) at `first` (the start state)
        self.finished = False
        #: (global index of a step end, newest received sample's global index when it became
        #: final) of the latest steps: the latency, measured
        self.step_final_at: deque[tuple[int, int]] = deque(maxlen=256)

    @property
    def t_last(self) -> float:
        """Time of the newest sample pushed, s (-inf before any)."""
        return self.alone.t_last

    def closed_until(self) -> float:
        """Every step of this foot that ends before this time (s) has been returned or is held
        with the released ones."""
        return min(self.t_emitted, self.steps.first_waiting_s - 1e-9)


class JointStream:
    """A coupled fusion's joint filter over two :class:`FootStream` s (module docstring).

    Parameters
    ----------
    stream
        The :class:`~footnav.pipeline.online.OnlineStream` (pipeline, ``keep``).
    feet
        Its left and right foot streams: detection, and each foot alone.
    """

    def __init__(self, stream: Any, feet: list[FootStream]) -> None:
        self.stream = stream
        self.fusion = stream.pipeline.fusion
        self.estimator = stream.pipeline.estimator
        self.forward = forward_only(self.estimator)
        self.smooth = self.estimator.smoother != "none"  # "whole": step-wise until close
        self.feet = [JointFoot(f) for f in feet]
        for f in feet:
            f.hold = 0  # every sample, until the joint filter has taken it
            f.steps.collect = False  # the steps are the fused feet's (JointFoot.steps)
            f.record_starts = bool(self.fusion.reads_feet_alone)
        self.start_s: float | None = None
        self.session: Any = None
        self.filt: OnlineFilter | None = None
        self.meta: list[dict] = []
        self.start_index = [0, 0]  # each foot's filter start, in the common span
        self.until = -math.inf  # the joint filter has run to this time
        self.n_checkpoints = 1
        self.result_meta: dict = {}
        self.span_end = math.inf  # the common span's end, s (known at the end)
        self._pending: list[list[NDArray]] = [[], []]  # landings (s) not yet given to the session

    # -- each push ----------------------------------------------------------------------------------
    def advance(self, final: bool = False) -> None:
        """Take the feet's new final samples as far as both have arrived; run the fusion on them."""
        if self.start_s is None and not self._span_start():
            return
        if self.filt is None and not self._start(final):
            return
        self._feed(final)
        self._run(final)
        self._harvest(final)
        for jf in self.feet:
            jf.alone.hold = jf.n_fed

    def _span_start(self) -> bool:
        """The common span's start (the later foot's first sample), once both feet have one."""
        if any(jf.alone.input.end == 0 for jf in self.feet):
            return False
        firsts = [float(jf.alone.input.rows(0, 1)[0][0]) for jf in self.feet]
        self.start_s = max(firsts)
        for jf in self.feet:
            t = jf.alone.input.rows(0, jf.alone.input.end)[0]
            jf.i0 = jf.n_fed = int(np.searchsorted(t, self.start_s, side="left"))
            jf.n_out = jf.seg0 = jf.out.start = jf.i0  # (out is empty: its rows count from i0)
        return True

    def _cut(self, jf: JointFoot, stop: int) -> tuple[ImuData, StanceResult]:
        """The foot's final samples from the common start to ``stop`` (global), as the offline
        run slices them."""
        t, acc, gyr, mask = (x.copy() for x in jf.alone.calibrated(jf.alone.input.rows(jf.i0, stop)))
        return ImuData(t=t, acc=acc, gyr=gyr, meta=jf.alone.input_meta()), StanceResult(mask=mask)

    def _cap(self, final: bool) -> float:
        """The newest time (s) whose samples belong to the common span for sure: the newest both
        feet have reached, or at the end the span's end."""
        if not final:
            return min(jf.t_last for jf in self.feet)
        if self.span_end == math.inf:
            self.span_end = common_bounds(*[self._span_of(jf) for jf in self.feet], fusion=self.fusion.name)[1]
        return self.span_end

    def _stop(self, jf: JointFoot, cap: float, final: bool) -> int:
        """The global index after the foot's last final sample at or before ``cap`` (s), not
        within a stance where the estimator needs each stance whole
        (:meth:`footnav.pipeline.online_foot.FootStream.whole_stances_until`)."""
        t = jf.alone.input.rows(jf.n_fed, jf.alone.n_final)[0]
        stop = jf.n_fed + int(np.searchsorted(t, cap, side="right"))
        return jf.alone.whole_stances_until(jf.n_fed, stop, final)

    def _first_step_yaw(self, jf: JointFoot, final: bool) -> None:
        """:func:`footnav.fusion.joint.first_step_yaw` as samples arrive: looked for on the samples
        up to a closed stance, when the closed stances have doubled since the last look (the
        forward filter is causal: the heading is the whole run's)."""
        n = self._stop(jf, self._cap(final), final)
        if final:
            with recording(quiet=True):
                jf.yaw = float(self.forward.estimate(*self._cut(jf, n)).meta.get("heading_rotation_rad", 0.0))
            return
        mask = jf.alone.input.rows(jf.i0, n)[3]
        closed = [e for _, e in stance_runs(mask) if e < len(mask)]
        if len(closed) < max(2, 2 * jf.tries):
            return
        jf.tries = len(closed)
        with recording(quiet=True):  # its warnings are the start's, given there
            traj = self.forward.estimate(*self._cut(jf, jf.i0 + closed[-1]))
        if "heading_rotation_rad" in traj.meta:
            jf.yaw = float(traj.meta["heading_rotation_rad"])

    def _start(self, final: bool) -> bool:
        """The joint filter, once both feet's first-step headings are known."""
        for jf in self.feet:
            if jf.yaw is None:
                self._first_step_yaw(jf, final)
        if any(jf.yaw is None for jf in self.feet):
            return False
        cap = self._cap(final)
        cuts = [self._cut(jf, self._stop(jf, cap, final)) for jf in self.feet]
        self.session = self.fusion.session(self.estimator, self.start_s)
        first = start_filter(
            self.estimator,
            [c[0] for c in cuts],
            [c[1] for c in cuts],
            [jf.yaw for jf in self.feet],
            self.session.step_width_m,
        )
        if not isinstance(first, OnlineFilter):
            raise CompositionError(
                f"online fusion {self.fusion.name!r} needs the estimator's filter in segments "
                "(footnav.core.online_contract.OnlineFilter); "
                f"estimator {self.estimator.name!r} gives a {type(first).__name__}"
            )
        self.meta = first.meta
        self.start_index = [first.start_index(f) for f in range(2)]
        samples = [(c[0].t, c[0].acc, c[0].gyr, c[1].mask) for c in cuts]
        size = [max(SEGMENT_SAMPLES, 2 * len(s[0])) for s in samples]
        self.filt = first.rebase([0, 0], size, at=0, step_smoother=self.smooth)  # from its aligned start
        self.filt.meta = first.meta
        for f, jf in enumerate(self.feet):
            jf.n_fed = jf.i0 + len(samples[f][0])
            jf.first = fused_start(first.meta[f], jf.i0)
            jf.anchor = (first.position(f), first.quaternion(f))
            self._landings(f, samples[f][3], samples[f][0], jf.i0)  # (the session takes them at its first run)
        self.n_checkpoints = 1
        return True

    def _landings(self, f: int, mask: NDArray[np.bool_], t: NDArray[np.float64], g0: int) -> None:
        """Stance starts among foot ``f``'s newly fed samples (the first at global index ``g0``),
        after its first stance in the span (the offline run's ``t[intervals[1:, 0]]``), queued
        for the session; every stance start's global index in ``JointFoot.run_starts``."""
        jf = self.feet[f]
        starts = [s for s, _ in stance_runs(mask) if s > 0 or not jf.in_run]
        jf.run_starts.extend(g0 + s for s in starts)
        if len(mask):
            jf.in_run = bool(mask[-1])
        skip = max(0, 1 - jf.runs_seen)
        jf.runs_seen += len(starts)
        new = t[starts[skip:]] if len(starts) > skip else t[:0]
        self._pending[f].append(new.copy())

    def _feed(self, final: bool) -> None:
        """Give the joint filter each foot's final samples up to the newest time both feet have
        reached (all of the common span at the end)."""
        cap = self._cap(final)
        stops = [self._stop(jf, cap, final) for jf in self.feet]
        if any(stop - jf.seg0 > self.filt.capacity(f) for f, (jf, stop) in enumerate(zip(self.feet, stops))):
            self._restart(stops)
        for f, (jf, stop) in enumerate(zip(self.feet, stops)):
            if stop <= jf.n_fed:
                continue
            rows, zupt = jf.alone.filter_rows(jf.n_fed, stop, first_whole=False)
            self.filt.extend(*rows, foot=f, **zupt)
            self._landings(f, rows[3], rows[0], jf.n_fed)
            jf.n_fed = stop

    def _span_of(self, jf: JointFoot) -> tuple[float, float]:
        return jf.alone.first_t, jf.t_last

    def _run(self, final: bool) -> None:
        """The fusion's measurements and the filter up to the last sample of both feet whose step
        end is known (everything fed, at the end)."""
        filt = self.filt
        landings = [np.concatenate(p) if p else np.empty(0) for p in self._pending]
        for p in self._pending:
            p.clear()

        view = self._view()
        if self.fusion.reads_feet_alone:
            for f, jf in enumerate(self.feet):
                self.session.feet_alone(f, jf.alone.alone_starts)
                jf.alone.alone_starts = []
        if final:
            self.session.advance(filt, self.span_end, landings, view, stop_s=self.span_end)
            filt.run_until()
            self.result_meta = self.session.finish()
            if self.fusion.calibrates_feet:  # as the offline fuse records it
                self.result_meta["calibration"] = {jf.foot: jf.alone.calibration for jf in self.feet}
            return
        ends = []
        for f, jf in enumerate(self.feet):
            last = jf.n_fed - jf.seg0 - 1  # a step end needs the next sample's decision
            ends.append(float(filt.samples(f).t[last - 1]) if last >= 1 else -math.inf)
        until = self.session.known_until(view, min(ends))
        self.session.advance(filt, until, landings, view)
        if until > self.until:
            filt.run_until(until)
            self.until = until

    def _view(self) -> FeetView:
        """The feet as the session reads them: the segment's samples (its own indexing)."""
        fed = [self.filt.samples(f) for f in range(2)]
        return FeetView([x.t for x in fed], [x.stance for x in fed], [jf.alone.rate_hz for jf in self.feet])

    def _harvest(self, final: bool) -> None:
        """Move the samples up to the last closed step (all of them at the end; with no
        smoother, every filtered sample) to the outputs."""
        filt = self.filt
        cps = filt.checkpoints
        ends = None
        if final or not self.smooth:
            if final:
                filt.close_open_step()
            ends = [filt.index(f) for f in range(2)]
        else:
            for i in range(self.n_checkpoints, len(cps)):
                if cps[i].step_end:
                    ends = [int(cps[i].k[f]) - int(filt.global_index(f, 0)) for f in range(2)]
                    self._note_latency(ends)
        # seen checkpoints serve nothing more (a restart starts where the filter stands, the step
        # smoother needs none): without this they would pile up with the fusion's updates
        del cps[:-1]
        self.n_checkpoints = 1
        if ends is None:
            return
        for f, jf in enumerate(self.feet):
            a, b = jf.n_out - jf.seg0, ends[f] + 1
            if b <= a:
                continue
            q, v, p, pcov = filt.final_outputs(f)
            fed = filt.samples(f)
            jf.out.append(fed.t[a:b], q[a:b], v[a:b], p[a:b], pcov[a:b], fed.stance[a:b])
            jf.n_out = jf.seg0 + b

    def _note_latency(self, ends: list[int]) -> None:
        """For the foot whose stance ends at a step-end checkpoint (segment indices ``ends``):
        (global index of the step end, the foot's newest sample received), in
        ``JointFoot.step_final_at``."""
        for f, (jf, k) in enumerate(zip(self.feet, ends)):
            stance = self.filt.samples(f).stance
            if k + 1 < len(stance) and stance[k] and not stance[k + 1]:
                jf.step_final_at.append((jf.seg0 + k, jf.alone.input.end - 1))

    def _restart(self, need: list[int]) -> None:
        """A new segment where the filter stands (:meth:`OnlineFilter.rebase`), holding each
        foot's samples not yet final (and the one before, which a step's smoothing chains to),
        room for its samples up to global index ``need[f]``, and the smoother's open step."""
        old = self.filt
        shift, size = [], []
        for f, jf in enumerate(self.feet):
            k_now = old.index(f)
            # the session reads back to history_s before the foot's latest stance start
            back = math.ceil(self.session.history_s * jf.alone.rate_hz) + 1 if self.session.history_s > 0 else 0
            s = min(jf.n_out - jf.seg0 - 1, k_now - back)
            started = [g for g in jf.run_starts if g <= jf.seg0 + k_now]
            if back and started:
                s = min(s, started[-1] - jf.seg0 - back)
            first = old.open_step_start(f)
            if first is not None:
                s = min(s, first - 1)
            s = max(s, 0)
            shift.append(s)
            size.append(max(SEGMENT_SAMPLES, 2 * (need[f] - jf.seg0 - s)))
        self.filt = old.rebase(shift, size)
        for f, jf in enumerate(self.feet):
            jf.seg0 += shift[f]
        self.n_checkpoints = 1

    # -- what a push returns --------------------------------------------------------------------------
    def take(self, final: bool = False) -> list[FootUpdate]:
        """Each foot's samples that became final since the last take, in its own order: before
        the common span the foot alone continued to the fused start, then the fused samples,
        after the span (at the end) the foot alone continued from the fused end."""
        forward = self.forward_estimates()
        updates = []
        for f, jf in enumerate(self.feet):
            alone = jf.alone
            rows: list[tuple] = []
            if not jf.front_done and self.filt is not None:
                if jf.first == 0:
                    jf.front_done = True
                elif alone.psi is not None and alone.n_out > jf.first:
                    rows.append(self._alone_rows(jf, 0, jf.first, jf.first, jf.anchor))
                    jf.front_done = True
                jf.emitted = jf.first if jf.front_done else 0
            if jf.front_done and jf.n_out > jf.emitted:
                t, q, v, p, _, stance = jf.out.rows(jf.emitted, jf.n_out)
                rows.append((t.copy(), q.copy(), v.copy(), p.copy(), stance.copy()))
                jf.emitted = jf.n_out
            if final and jf.front_done and alone.n_out > jf.n_out:
                k = jf.n_out - 1
                _, q, _, p, _, _ = jf.out.rows(k, k + 1)
                rows.append(self._alone_rows(jf, jf.n_out, alone.n_out, k, (p[0].copy(), q[0].copy())))
                jf.emitted = alone.n_out
            if not self.stream.keep:
                jf.out.drop_before(jf.emitted - 1)
                if jf.front_done:  # the foot alone is needed from the fused end's anchor on
                    alone.out.drop_before(min(jf.n_out - 1, alone.n_out))
            if not rows:
                updates.append(empty_update(forward[f]))
                continue
            t, q, v, p, stance = (np.concatenate(x) for x in zip(*rows))
            nxt = self._next_stance(jf) if not final else False
            jf.steps.add(t, p, stance, nxt)
            jf.t_emitted = float(t[-1])
            updates.append(FootUpdate(t, p, v, q, forward[f], stance))
        return updates

    def _alone_rows(self, jf: JointFoot, a: int, b: int, anchor: int, fused: tuple) -> tuple:
        """The foot alone, samples ``a:b``, turned into its first step's frame as the per-foot
        stream turns them, then continued rigidly so that its sample ``anchor`` meets the
        ``fused`` (position, quaternion) there."""
        lo, hi = min(a, anchor), max(b, anchor + 1)
        t, q, v, p, pcov, stance, _ = (x.copy() for x in jf.alone.out.rows(lo, hi))
        if jf.alone.psi:
            rotate_about_z(-jf.alone.psi, p, v, q, pcov)
        i = anchor - lo
        p, v, q = continue_rigidly((p, v, q), (p[i].copy(), q[i].copy()), fused)
        keep = slice(a - lo, b - lo)
        return t[keep], q[keep], v[keep], p[keep], stance[keep]

    def _next_stance(self, jf: JointFoot) -> bool:
        """The stance decision of the sample after the last one returned (True when unknown: a
        stance is not closed before its end is seen)."""
        f = self.feet.index(jf)
        k = jf.emitted - jf.seg0
        fed = self.filt.samples(f)
        return bool(fed.stance[k]) if 0 <= k < len(fed.t) else True

    def forward_estimates(self) -> list[ForwardEstimate | None]:
        """The joint filter's state at each foot's newest filtered sample (the feet's common frame)."""
        filt = self.filt
        if filt is None:
            return [None, None]
        cov = filt.covariance
        out = []
        for f in range(2):
            sl = filt.block(f, "pos")
            out.append(
                ForwardEstimate(
                    filt.time(f), filt.position(f), filt.velocity(f), filt.quaternion(f), cov[sl, sl].copy()
                )
            )
        return out

    # -- the end --------------------------------------------------------------------------------------
    def finish(self) -> None:
        """Every remaining sample final: the common span's end, the fusion's last measurements,
        the last step closed."""
        if self.start_s is None:
            self._span_start()
        if self.filt is None:
            self._start(final=True)
        self.advance(final=True)
        for jf in self.feet:
            jf.finished = True
            jf.steps.finish()

    def result(self, alone: list[FootTrajectory]) -> FusionResult:
        """The fusion's result on both feet's whole sample grids (``keep=True``), as the offline
        :func:`~footnav.fusion.joint.fuse_on_common_span` makes it; ``alone``: each foot's
        estimate alone (:meth:`FootStream.trajectory`)."""
        est = self.estimator
        fused, cuts = [], []
        for f, jf in enumerate(self.feet):
            t, q, v, p, pcov, mask = (np.array(x) for x in jf.out.rows(jf.i0, jf.n_out))
            runs = stance_intervals(mask)
            traj = est.package(
                t,
                q,
                v,
                p,
                pcov,
                self.start_index[f],
                self.meta[f],
                runs,
                smoothed=self.smooth,
                heading=False,
                biases=est.final_biases(self.filt, f),
            )
            fused.append(traj)
            n = jf.alone.input.end
            t_first, t_end = self._span_of(jf)
            cuts.append(
                FootCut(
                    jf.i0, jf.n_out, n, max(0.0, float(self.start_s - t_first)), max(0.0, float(t_end - self.span_end))
                )
            )
        span = CommonSpan(
            float(self.start_s), float(self.span_end), cuts[0], cuts[1], *[self._span_of(jf) for jf in self.feet]
        )
        if span.warn:
            warn(span.message(self.fusion.name, OUTSIDE_SPAN), DataQualityWarning, stacklevel=4)
        joint = FusionResult(
            left=fused[0], right=fused[1], path=midpoint_path(fused[0], fused[1]), meta=self.result_meta
        )
        return on_whole_span(joint, span, lambda foot: alone[foot])
