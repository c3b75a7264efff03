"""Online mode: a pipeline on a live stream, final one step after it happens, in bounded memory.

:meth:`footnav.pipeline.factory.Pipeline.online` returns an :class:`OnlineStream`. Samples arrive in
chunks of any size (one sample to minutes), per foot and on each foot's own schedule;
:meth:`OnlineStream.push` returns what became final since the last push, and
:meth:`OnlineStream.close` the :class:`~footnav.pipeline.result.PipelineResult` of the offline run of
the same pipeline (identical on the simulated and shared recordings; the tests allow 1e-9 m).

How it stays equal to the offline run, per foot (:mod:`footnav.pipeline.online_foot`):

1. **Detection** is re-run on a short buffer: the last ``margin`` final samples and the samples
   not yet final. A detector declares its latency (``StanceDetector.latency_s``): its decision
   on a sample depends on nothing later than that, so decisions older than the latency (plus
   two samples) are final; decisions within ``margin`` of the buffer's start are never used (the
   buffer's start has edge effects of the same reach). A detector may decide in blocks
   (``online_block_s``: each block on the window of fixed samples ending ``latency_s`` after it,
   the same however the samples are chunked) and wait for its first decisions
   (``online_startup_s``); the adaptive detector does both (its windowed decisions are the
   offline ones but where the window's typical stride is not the walk's, ``online_exact`` False).
   A detector without a bounded latency (``latency_s = None``: the HMM's Viterbi path needs the
   whole recording) is refused.
2. **The forward filter** (the estimator's :class:`~footnav.core.online_contract.OnlineFilter`, e.g.
   the EKF's ``OnlineInsFilter``, aligned by ``estimator.start`` once the first stance is
   final) runs on the final samples. The filter
   is built over a fixed-size *segment* of samples that the stream fills as they become final;
   when the segment is full, a new one starts from the filter's last checkpoint at a step end
   (its state, covariance and the step-wise smoother's chaining value there). The filter is
   deterministic, so the continued run is the offline run, sample for sample.
3. **Step-wise smoothing** (``smoother="step"``, and live with ``"whole"``) closes each step at its
   end: every sample up to
   the last closed step is final, and is returned by the next push. The frame's heading (the
   first step along +x) is known once the first step longer than 0.2 m has closed; samples are
   held until then.

Latency: a step (from one stance's end to the next stance's end) is final once that stance's end
is detected, i.e. when the sample after it is final: ``latency_s`` plus 3 samples after the
stance's last sample arrives, after a detector's start-up (measured by
``benchmarks/bench_online.py``, ``tests/pipeline/test_online.py`` and, for the default pipeline,
``tests/pipeline/test_online_default.py``; ``stats()["step_latency_s"]`` gives each step's).

Close: the whole result is made from the stream's final samples, or, with the whole-walk
smoother or a detector that is not ``online_exact`` (the default pipeline), by the offline run of
the pipeline on every sample kept (``keep=True``): the offline result, checks and meta, with
``meta["online"]`` added. With ``keep=False`` nothing is returned and ``stats()["close"]`` says
the whole-walk smoother was not possible.

Memory: the input buffer, the detection buffer and the filter segment are bounded; with
``keep=False`` nothing grows with the walk (``close`` then returns None). ``keep=True`` keeps every
final sample for ``close``'s result, as the offline run would.

Fusions: ``independent`` runs on the per-foot filters. A coupled fusion that offers a session
(:class:`footnav.core.component.FusionSession`: ``range``, ``step-vector``, ``particle`` in footnav's
mode) runs on one joint filter fed by both feet as far as both have arrived
(:mod:`footnav.pipeline.online_joint`), with the offline run's common-span rules (step-vector's
fitted leg length is fitted on the steps so far: ``close`` reruns offline); the others (DTW
averages the whole walk; the particle fusion's paper mode runs its own filters) are refused with
a message.
"""

from __future__ import annotations

import time
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

from footnav.core.errors import DataQualityWarning, InvalidInputError, InvalidParameterError
from footnav.core.types import FusionResult
from footnav.core.warning_log import recording, warn
from footnav.fusion.independent import midpoint_path
from footnav.nav.clock_sync import ClockMap
from footnav.nav.floors import LEVEL_RISE_MAX_M, FloorHolder
from footnav.nav.initial_alignment import bridged_gaps_message
from footnav.pipeline.online_composition import (
    COUPLED_ONLINE_FUSIONS,
    OFFLINE_ONLY_FUSIONS,
    ONLINE_FUSIONS,
    check_online,
)
from footnav.pipeline.online_floors import held_step, hold_update
from footnav.pipeline.online_foot import FootStream
from footnav.pipeline.online_io import ClosedStep, FootUpdate, ForwardEstimate, as_chunk, empty_update
from footnav.pipeline.online_joint import JointStream
from footnav.pipeline.online_pair import PairDetection
from footnav.pipeline.result import PipelineResult

__all__ = [
    "COUPLED_ONLINE_FUSIONS",
    "OFFLINE_ONLY_FUSIONS",
    "ONLINE_FUSIONS",
    "ClosedStep",
    "FootUpdate",
    "ForwardEstimate",
    "OnlineStream",
    "OnlineUpdate",
]


_FEET = ("left", "right")


@dataclass(frozen=True)
class OnlineUpdate:
    """What a :meth:`OnlineStream.push` made final: per foot, and the closed steps in time order."""

    left: FootUpdate
    right: FootUpdate | None
    steps: list[ClosedStep] = field(default_factory=list)


class OnlineStream:
    """A pipeline on a live stream; make it with :meth:`Pipeline.online`.

    Parameters
    ----------
    pipeline
        A pipeline whose components run online: a detector with a bounded ``latency_s``, an
        estimator with a step-able filter and any ``smoother`` (``"whole"``: step-wise live, the
        whole walk at close), an online fusion (:data:`ONLINE_FUSIONS`).
    feet
        1 (``left`` only) or 2.
    max_wait_s
        How long (s, in the faster foot's time) a closed step waits for the other foot before
        it is returned out of time order (``ClosedStep.late``).
    clock_offset_s
        Per foot, added to its time stamps to put both feet on one clock, e.g.
        ``{"right": -0.012}``.
    clocks
        Per foot, a :class:`~footnav.nav.clock_sync.ClockMap` applied to its time stamps (an
        offset and a rate), e.g. ``{"right": fit_clock(tm1, ti, tm2)}`` from the message
        exchanges of Chistyakov et al. (2021), Sec. 5B logged before the walk. A foot takes an
        offset or a map, not both.
    keep
        Keep every final sample for :meth:`close`'s result; False keeps nothing of the past
        (memory independent of the walk's length) and ``close`` returns None.
    rate_hz
        The sampling rate the detector's windows are counted at, Hz; default: 1 / the median
        interval of the first second. The offline run takes the whole recording's median
        interval: with jittered sampling, a window on the edge of rounding to another number of
        samples differs unless this is the same (``recording.left.rate_hz``).
    input_meta
        Per foot, where its samples come from, as a recording's meta says it: ``"source"`` (a
        file or device: named in errors, warnings and the result) and ``"units_in"`` (the units
        the caller converted from, for the unit checks' hints), e.g. ``{"left": {"source":
        "left.csv", "units_in": {"t": "ms"}}}``.

    Notes
    -----
    Every chunk passes the input checks of a recording (:mod:`footnav.pipeline.online_checks`:
    the same errors and warnings as offline) before it is taken, both feet's chunks of a push
    before either is: a push that raises InvalidInputError took nothing, and can be retried with
    good data. A component that fails inside a push ends the stream: later pushes are refused,
    and :meth:`close` returns what was final before (see there).
    """

    def __init__(
        self,
        pipeline: Any,
        *,
        feet: int = 2,
        max_wait_s: float = 2.0,
        clock_offset_s: Mapping[str, float] | None = None,
        clocks: Mapping[str, ClockMap] | None = None,
        keep: bool = True,
        rate_hz: float | None = None,
        input_meta: Mapping[str, Mapping[str, Any]] | None = None,
    ) -> None:
        if feet not in (1, 2):
            raise InvalidParameterError(f"online: feet={feet!r} is invalid; expected 1 or 2")
        if not (isinstance(max_wait_s, (int, float)) and max_wait_s >= 0):
            raise InvalidParameterError(f"online: max_wait_s={max_wait_s!r} is invalid; expected a number >= 0 s")
        offsets = dict(clock_offset_s or {})
        unknown = set(offsets) - set(_FEET[:feet])
        if unknown:
            raise InvalidParameterError(
                f"online: clock_offset_s names {sorted(unknown)}; expected {list(_FEET[:feet])}"
            )
        self.clocks = dict(clocks or {})
        for foot, clock in self.clocks.items():
            if foot not in _FEET[:feet]:
                raise InvalidParameterError(f"online: clocks names {foot!r}; expected one of {list(_FEET[:feet])}")
            if not isinstance(clock, ClockMap):
                raise InvalidParameterError(
                    f"online: clocks[{foot!r}] is a {type(clock).__name__}; expected a footnav.nav.clock_sync.ClockMap"
                )
            if foot in offsets:
                raise InvalidParameterError(
                    f"online: the {foot} foot has both a clock_offset_s and a clock map; give one"
                )
        if rate_hz is not None and not (isinstance(rate_hz, (int, float)) and 0 < rate_hz < 1e6):
            raise InvalidParameterError(
                f"online: rate_hz={rate_hz!r} is invalid; expected a number in (0, 1e6) Hz or None"
            )
        self.rate_hz = rate_hz
        self.pipeline = pipeline
        self.latency_s = check_online(pipeline, feet)
        #: ``close`` reruns the offline pipeline on the whole input (``keep=True``) rather than
        #: assembling the stream's final samples: the whole-walk smoother needs the whole walk,
        #: and a detector or fusion whose online decisions may differ from its offline ones (its
        #: ``online_exact`` False: adaptive's typical stride, step-vector's fitted leg length)
        #: would give other stances or steps
        self.rerun = (
            getattr(pipeline.estimator, "smoother", None) == "whole"
            or not getattr(pipeline.detector, "online_exact", True)
            or not getattr(pipeline.fusion, "online_exact", True)
        )
        self.n_feet = feet
        self.max_wait_s = float(max_wait_s)
        self.keep = bool(keep)
        inputs = dict(input_meta or {})
        unknown = set(inputs) - set(_FEET[:feet])
        if unknown:
            raise InvalidParameterError(f"online: input_meta names {sorted(unknown)}; expected {list(_FEET[:feet])}")
        self.feet = [FootStream(self, foot, offsets.get(foot, 0.0), inputs.get(foot)) for foot in _FEET[:feet]]
        #: both feet's stance decided together (a detector that needs both feet: dual-gait)
        self.pair = PairDetection(self, self.feet) if getattr(pipeline.detector, "needs_two_feet", False) else None
        #: both feet in the coupled fusion's joint filter (None for 'independent')
        self.joint = JointStream(self, self.feet) if pipeline.fusion.name not in ONLINE_FUSIONS else None
        self._held: list[ClosedStep] = []
        est = pipeline.estimator
        #: each foot's live height hold (the estimator's ``vertical="floors"``), as offline
        bound = getattr(est, "level_rise_max_m", LEVEL_RISE_MAX_M)
        self._floors = (
            [FloorHolder(bound, keep_strides=keep) for _ in self.feet]
            if getattr(est, "vertical", "free") == "floors"
            else None
        )
        self._closed = False
        #: the exception that ended the stream inside a push (a component's failure), if any
        self.failure: BaseException | None = None
        self._outcome: tuple[PipelineResult | None, BaseException | None] | None = None
        self._t0 = time.perf_counter()
        self._push_s = 0.0
        #: the warnings raised so far, each message once, in order (``close``'s ``meta["warnings"]``)
        self.warnings: list[str] = []
        self._seen_warnings: set[str] = set()
        self.n_pushes = 0

    def __repr__(self) -> str:
        n = [f.input.end for f in self.feet]
        final = [f.n_out for f in self.feet]
        return f"OnlineStream(feet={self.n_feet}, samples={n}, final={final}, latency_s={self.latency_s:.3g})"

    def push(self, left: Any = None, right: Any = None) -> OnlineUpdate:
        """Add samples of either foot or both; returns what became final since the last push.

        Both chunks are checked before either is taken (:mod:`footnav.pipeline.online_checks`):
        on InvalidInputError (its ``foot`` attribute says whose chunk) the stream is as before the
        push.
        """
        if self._closed:
            raise InvalidInputError("the stream is closed; start a new one with pipeline.online()", field="push")
        if self.failure is not None:
            raise InvalidInputError(
                f"the stream ended when a push failed ({type(self.failure).__name__}: {self.failure}); close() "
                "returns what was final before it",
                field="push",
            )
        if right is not None and self.n_feet == 1:
            raise InvalidInputError("a one-foot stream (feet=1) takes left=... only", field="right")
        t0 = time.perf_counter()
        with recording() as caught:
            checked = []
            for foot, chunk in zip(self.feet, (left, right)):
                if chunk is not None:
                    try:
                        checked.append((foot, *foot.checks.check(*as_chunk(chunk, foot.foot))))
                    except InvalidInputError as exc:
                        exc.foot = foot.foot  # type: ignore[attr-defined] # which chunk (the text is the offline one)
                        raise
            try:
                for foot, (t, acc, gyr), pending in checked:
                    foot.checks.accept(pending)
                    self._feed(foot, t, acc, gyr)
                if self.pair is not None:
                    self.pair.advance()
                if self.joint is not None:
                    self.joint.advance()
            except BaseException as exc:
                # the feet may have taken part of the push: the stream cannot go on consistently
                self.failure = exc
                raise
            finally:
                self._note(caught)
        out = self._update(final=False)
        self._push_s += time.perf_counter() - t0
        self.n_pushes += 1
        return out

    def _feed(self, foot: FootStream, t: Any, acc: Any, gyr: Any) -> None:
        """Pass checked samples on to a foot (on the common clock)."""
        if len(t):
            clock = self.clocks.get(foot.foot)
            foot.push(t if clock is None else clock(t), acc, gyr)

    def describe_input(
        self, foot: str, *, source: str | None = None, units_in: Mapping[str, str] | None = None
    ) -> None:
        """Say where a foot's samples come from (``input_meta``) once it is known, e.g. the units of
        a file's ``# units:`` line read with its first rows."""
        checks = self.feet[_FEET.index(foot)].checks
        if source is not None:
            checks.meta["source"] = checks.path = source
        if units_in is not None:
            checks.meta["units_in"] = dict(units_in)

    def _note(self, caught: list) -> None:
        """Keep the warnings a push raised (each message once) for :meth:`close`'s ``meta``:
        they were shown when they happened, and the result records them as the offline run's does."""
        for w in caught:
            text = str(w)
            if text not in self._seen_warnings:
                self._seen_warnings.add(text)
                self.warnings.append(text)

    def _update(self, final: bool) -> OnlineUpdate:
        if self.joint is None:
            sources: list[Any] = self.feet
            updates = [f.take() for f in self.feet]
        else:
            sources = self.joint.feet
            updates = self.joint.take(final)
        if self._floors is not None:
            updates = [hold_update(h, u, src, final) for h, u, src in zip(self._floors, updates, sources)]
        for f in sources:
            self._held.extend(f.steps.pending)
            f.steps.pending.clear()
        self._held.sort(key=lambda s: (s.t, s.foot))
        released: list[ClosedStep] = []
        if final or self.n_feet == 1:
            released, self._held = self._held, []
        else:
            keep = []
            for step in self._held:
                other = sources[1 - _FEET.index(step.foot)]
                own = sources[_FEET.index(step.foot)]
                if other.closed_until() >= step.t or other.finished:
                    released.append(step)
                elif own.t_last - step.t > self.max_wait_s:
                    released.append(
                        ClosedStep(
                            step.t,
                            step.foot,
                            step.position,
                            step.stride_length_m,
                            step.heading_rad,
                            step.index,
                            late=True,
                        )
                    )
                else:
                    keep.append(step)
            self._held = keep
        if self._floors is not None:
            released = [held_step(self._floors[_FEET.index(s.foot)], s) for s in released]
        return OnlineUpdate(updates[0], updates[1] if self.n_feet == 2 else None, released)

    def close(self) -> PipelineResult | None:
        """End the stream: every remaining sample becomes final (the last step is closed as the
        offline run closes it). Returns the whole :class:`PipelineResult` (``keep=True``) or None;
        :attr:`last_update` holds what the end made final.

        The result's ``meta["complete"]`` is True and ``meta["ended_by"]`` ``"close"``. When the
        end cannot be made (a foot never sent a sample, a component fails, the stream had failed
        in a push), close raises that failure (its own type and message) carrying what could be
        made as attributes: ``partial``, a PipelineResult of each foot's own estimate up to where it
        was final (the left foot's required; ``meta["complete"]`` False, ``meta["ended_by"]``
        the reason), ``feet``, each foot's ``(trajectory, stance)`` or None, and ``reason``.
        Closing again returns (or raises) the same.
        """
        if self._outcome is not None:
            result, error = self._outcome
            if error is not None:
                raise error
            return result
        self._closed = True
        failures: dict[str, BaseException] = {}
        with recording() as caught:
            try:
                if self.failure is None:
                    for f in self.feet:
                        try:
                            self._feed(f, *f.checks.finish())  # the samples held back for their neighbours
                            if self.pair is None:
                                f.finish()
                        except Exception as exc:  # kept with the other foot's partial result
                            failures[f.foot] = exc
                    if self.pair is not None and not failures:
                        try:  # both feet decided together, then each filtered; a foot's own failure is its own
                            failures.update(self.pair.finish())
                        except Exception as exc:
                            failures["both feet"] = exc
                    if self.joint is not None and not failures:
                        try:
                            self.joint.finish()
                        except Exception as exc:
                            failures["both feet"] = exc
            finally:
                self._note(caught)
        if self.failure is None and not failures:
            self.last_update = self._update(final=True)
            try:
                result = self._result() if self.keep else None
            except Exception as exc:  # the fusion's result: each foot's own is still there
                failures["both feet"] = exc
            else:
                self._outcome = (result, None)
                return result
        try:  # what the end made final for the feet that could finish (the steps a live user sees)
            self.last_update = self._update(final=True)
        except Exception:  # the error raised below says why the stream could not end whole
            self.last_update = OnlineUpdate(empty_update(None), None if self.n_feet == 1 else empty_update(None), [])
        error = self._incomplete(failures)
        self._outcome = (None, error)
        raise error

    def _result(self) -> PipelineResult:
        if self.rerun:
            return self._offline_result()
        trajs = [f.trajectory() for f in self.feet]
        # the whole recording's checks, as the offline run makes them: units, rest, saturation
        # (online they saw the first seconds) and each foot's stances against its gait cycles
        with recording() as caught:
            try:
                for f, (traj, _) in zip(self.feet, trajs):
                    gaps = f.bridged_gaps()
                    if gaps:
                        traj.meta["gaps_bridged"] = gaps
                        warn(bridged_gaps_message(f.checks.label, gaps), DataQualityWarning, stacklevel=2)
                imus = [f.whole_input() for f in self.feet]
                for f, imu in zip(self.feet, imus):
                    if imu is not None:
                        f.checks.finish_whole(imu)
                pair = imus + [None] * (2 - len(imus))
                stances = [tr[1] for tr in trajs] + [None] * (2 - len(trajs))
                stance_check = self.pipeline._check_stances(pair[0], stances[0], pair[1], stances[1])
            finally:
                self._note(caught)
        if self.joint is None:
            left, right = trajs[0][0], trajs[1][0] if self.n_feet == 2 else None
            path, fusion_meta = midpoint_path(left, right), {"fusion": self.pipeline.fusion.describe()}
        else:
            with recording() as caught:
                try:
                    fused = self.joint.result([tr[0] for tr in trajs])
                finally:
                    self._note(caught)
            left, right, path, fusion_meta = fused.left, fused.right, fused.path, dict(fused.meta)
        held = self.pipeline._hold_floors(FusionResult(left, right, path, fusion_meta))
        left, right, path = held.left, held.right, held.path
        with recording() as caught:
            try:
                vertical_check = self.pipeline._check_vertical(left, right)
            finally:
                self._note(caught)
        meta = self._meta(fusion_meta, complete=True, ended_by="close")
        meta["stance_check"] = stance_check
        meta["vertical_check"] = vertical_check
        return PipelineResult(
            left=left,
            right=right,
            path=path,
            stance_left=trajs[0][1],
            stance_right=trajs[1][1] if self.n_feet == 2 else None,
            meta=meta,
        )

    def _offline_result(self) -> PipelineResult:
        """The offline run of the pipeline on every sample pushed (on the common clock): its
        result, checks and meta, with the stream's ``meta["online"]`` (its live warnings there)."""
        imus = [f.whole_input() for f in self.feet]
        with recording(quiet=True):  # its warnings were said live, as the samples arrived
            result = self.pipeline.run(imus[0], imus[1] if self.n_feet == 2 else None)
        result.meta["online"] = {**self.stats(), "warnings": list(self.warnings)}
        result.meta["runtime_s"] = self._push_s + result.meta.get("runtime_s", 0.0)
        result.meta.update(complete=True, ended_by="close")
        for f in self.feet:
            result.meta["input"][f.foot] = {
                **(result.meta["input"].get(f.foot) or {}),
                "online": True,
                "samples": f.input.end,
            }
        return result

    def _meta(self, fusion_meta: dict, complete: bool, ended_by: str) -> dict[str, Any]:
        from footnav._version import __version__

        return {
            "pipeline": self.pipeline.config(),
            "footnav_version": __version__,
            "warnings": list(self.warnings),
            "stance_check": {},
            "vertical_check": {},
            "fusion": fusion_meta,
            "runtime_s": self._push_s,
            "input": {
                foot.foot: {**foot.checks.meta, **foot.checks.records, "online": True, "samples": foot.input.end}
                for foot in self.feet
            },
            "online": self.stats(),
            "complete": complete,
            "ended_by": ended_by,
        }

    def _incomplete(self, failures: dict[str, BaseException]) -> BaseException:
        """The error of a close that could not make the whole result, with each foot's own."""
        causes = ([("a push", self.failure)] if self.failure is not None else []) + list(failures.items())
        reason = "; ".join(f"{where}: {type(exc).__name__}: {exc}" for where, exc in causes)
        feet: dict[str, Any] = {}
        for f in self.feet:
            alone = self._foot_alone(f, failures)
            if alone is not None:
                feet[f.foot] = alone
                continue
            try:
                feet[f.foot] = f.trajectory() if f.n_out > 1 and f.filt is not None else None
                if feet[f.foot] is not None:
                    traj, stance = feet[f.foot]
                    feet[f.foot] = (
                        self.pipeline._hold_floors(FusionResult(traj, None, midpoint_path(traj, None))).left,
                        stance,
                    )
            except Exception:  # nothing of this foot can be made
                feet[f.foot] = None
        partial = None
        if self.keep and feet.get("left") is not None:
            (left, stance_left), right_pair = feet["left"], feet.get("right")
            right, stance_right = right_pair if right_pair is not None else (None, None)
            partial = PipelineResult(
                left=left,
                right=right,
                path=midpoint_path(left, right),
                stance_left=stance_left,
                stance_right=stance_right,
                meta=self._meta({"fusion": "none: the stream ended before the feet could be fused"}, False, reason),
            )
        # the cause itself, its type and message as they were: a caller catching it gets the
        # partial result on it
        error = causes[0][1]
        error.partial = partial  # type: ignore[union-attr]
        error.feet = feet  # type: ignore[union-attr]
        error.reason = reason  # type: ignore[union-attr]
        return error

    def _foot_alone(self, f: FootStream, failures: dict[str, BaseException]) -> tuple[Any, Any] | None:
        """A foot that ended whole, when ``close`` reruns offline: its own offline run (the
        pipeline's detector and estimator, independent), so a partial result holds what the
        complete one would (the whole-walk smoother, the offline stances); else None."""
        if not (self.rerun and self.keep and f.finished and self.failure is None and f.foot not in failures):
            return None
        if self.pipeline.fusion.name not in ONLINE_FUSIONS:
            return None  # a coupled fusion's feet are not each foot alone
        from footnav.pipeline.factory import make_pipeline

        try:
            with recording(quiet=True):  # said live
                result = make_pipeline(self.pipeline.detector, self.pipeline.estimator, "independent").run(
                    f.whole_input()
                )
        except Exception:  # the stream's own samples below
            return None
        return result.left, result.stance_left

    def stats(self) -> dict[str, Any]:
        """Samples received and final per foot, the detector's latency, time spent in push."""
        return {
            "latency_s": self.latency_s,
            "samples": {f.foot: f.input.end for f in self.feet},
            "received": {f.foot: f.checks.n for f in self.feet},
            "final": {f.foot: f.n_out for f in self.feet},
            "pushes": self.n_pushes,
            "push_time_s": self._push_s,
            # what ``close`` returns: the offline rerun ("whole input"), the stream's final samples
            # ("stream"), or nothing (keep=False: the past is not kept, no whole-walk smoothing)
            "close": ("whole input" if self.rerun else "stream")
            if self.keep
            else "none: keep=False keeps no past"
            + (
                ", the whole-walk smoother was not possible (the stream's samples are smoothed step-wise)"
                if getattr(self.pipeline.estimator, "smoother", None) == "whole"
                else ""
            ),
            # (step end, when it became final) of each foot's latest steps, s after the step's end
            "step_latency_s": {
                f.foot: [round((b - a) / f.rate_hz, 6) for a, b in f.step_final_at] if f.rate_hz else []
                for f in self.feet
            },
            # a coupled fusion's own record of what it applied live (step-vector's fitted leg length per update)
            "fusion": self.joint.session.finish()
            if self.joint is not None and self.joint.session is not None
            else None,
        }
