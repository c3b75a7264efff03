"""Two feet in one joint filter: what every coupled fusion starts and ends with.

A coupled fusion needs both feet in one nav frame. Each foot's IMU starts with its own, unknown
heading, so :func:`start_joint` first runs each foot alone (forward filter) over its first steps
to find the heading of its first step (:func:`first_step_yaw`), then starts the joint filter
(:class:`~footnav.core.component.JointFilter`) with each foot turned so that its first step points
along +x and the feet ``step_width_m`` apart across it (left foot at +y). :func:`finish_joint` has
the estimator finish the run (its own smoothing) and
returns both feet and their midpoint path. Fusions use only the members of
:class:`~footnav.core.component.StepableEstimator` and :class:`~footnav.core.component.JointFilter`,
so any estimator that implements them runs with every coupled fusion.

:func:`fuse_on_common_span` is what every coupled fusion's ``fuse`` is: the feet cut to their
common time span (:func:`footnav.nav.spans.common_span`; refused with InvalidInputError when
they share less than 3 s), fused there, and each foot's samples outside that span filled with
the foot estimated alone (the estimator on the whole foot), turned and moved rigidly so that it
continues the fused foot at the span's edge (for the start: at the fused estimate's first
stance). The returned trajectories stay sample-aligned with each foot's input;
``meta["span"]`` says which samples were fused and which estimated alone.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from typing import Any

import numpy as np

from footnav.core.component import JOINT_FILTER_MEMBERS, JointFilter, require_stepable
from footnav.core.errors import CompositionError, DataQualityWarning, InvalidInputError
from footnav.core.types import FootTrajectory, FusionResult, ImuData, StanceResult, stance_intervals
from footnav.core.warning_log import warn
from footnav.fusion.independent import midpoint_path
from footnav.nav import quaternion as quat
from footnav.nav.final_rest import final_rest
from footnav.nav.spans import CommonSpan, FootCut, common_span, slice_stance

__all__ = [
    "EventQueue",
    "FeetView",
    "check_two_feet",
    "close_loops",
    "closing_time",
    "continue_rigidly",
    "finish_joint",
    "first_step_yaw",
    "forward_only",
    "fuse_on_common_span",
    "fused_start",
    "on_whole_span",
    "require_stepable",
    "start_joint",
]

#: What a coupled fusion does with a foot's samples outside the common span (meta and warning).
OUTSIDE_SPAN = "each foot's samples outside it are that foot estimated alone, continued rigidly from the fused edge"

#: Feet indices in the joint filter.
LEFT, RIGHT = 0, 1


class FeetView:
    """What a fusion's session (:class:`footnav.core.component.FusionSession`) reads of the feet besides
    the joint filter, in the filter's own sample indexing: each foot's times (s), stance mask,
    sampling rate (Hz) and heel strikes (sample indices; none online). Offline the whole feet;
    online the samples the joint filter holds."""

    def __init__(self, times, masks, rates, heel_strikes=None) -> None:
        self.times = list(times)
        self.masks = [np.asarray(m, dtype=bool) for m in masks]
        self.rates = [float(r) for r in rates]
        self.heel_strikes = (
            list(heel_strikes) if heel_strikes is not None else [np.zeros(0, dtype=np.int64)] * len(self.times)
        )
        self._runs: list = [None] * len(self.times)

    @classmethod
    def of(cls, imus: Sequence[ImuData], stances: Sequence[StanceResult]) -> FeetView:
        """The view of whole recordings and their stance results."""
        return cls(
            [imu.t for imu in imus],
            [st.mask for st in stances],
            [imu.rate_hz for imu in imus],
            [np.asarray(st.events.get("heel_strike", []), dtype=np.int64) for st in stances],
        )

    def runs(self, foot: int) -> np.ndarray:
        """The foot's stance intervals, (K, 2) [start, stop) (computed once)."""
        if self._runs[foot] is None:
            self._runs[foot] = stance_intervals(self.masks[foot])
        return self._runs[foot]

    def standing(self, foot: int, k: int) -> bool:
        """Whether the foot is in stance at its sample ``k`` (the last one past the end)."""
        mask = self.masks[foot]
        return bool(mask[min(k, len(mask) - 1)])


class EventQueue:
    """A session's known events, ``(time s, foot)``, handed out in time order up to a time; none
    after ``closing_s`` (where the estimator's closed loop takes over), as the offline loops break."""

    def __init__(self, closing_s: float = np.inf) -> None:
        self.closing_s = float(closing_s)
        self._pending: list[tuple[float, int]] = []
        self._closed = False

    def add(self, t: float, foot: int) -> None:
        """Queue ``foot``'s event at time ``t`` (s)."""
        self._pending.append((float(t), foot))

    def due(self, until_s: float, everything: bool = False) -> list[tuple[float, int]]:
        """The events at or before ``until_s`` (all of them with ``everything``), in order, removed."""
        self._pending.sort()
        n = len(self._pending) if everything else sum(1 for t, _ in self._pending if t <= until_s)
        due, self._pending = self._pending[:n], self._pending[n:]
        if self._closed:
            return []
        for i, (t, _) in enumerate(due):
            if t > self.closing_s:
                self._closed = True
                return due[:i]
        return due


def check_two_feet(fusion: Any, estimator: Any, right: Any, stance_right: Any) -> None:
    """What every coupled fusion checks first: its parameters, both feet, a step-able estimator."""
    fusion.validate_params()
    if right is None or stance_right is None:
        raise CompositionError(f"fusion {fusion.name!r} needs both feet")
    require_stepable(fusion, estimator)


def forward_only(estimator: Any) -> Any:
    """The estimator as a forward filter (no smoother, no closed loop), its first step along +x."""
    changes: dict[str, Any] = {"smoother": "none", "heading": "first-step"}
    if getattr(estimator, "closed_loop", False):
        changes["closed_loop"] = False
    return estimator.clone(**changes)


def start_joint(
    estimator: Any,
    left: ImuData,
    stance_left: StanceResult,
    right: ImuData,
    stance_right: StanceResult,
    step_width_m: float,
    *,
    return_singles: bool = False,
):
    """The joint filter of both feet in one nav frame (x: the first step, z up, origin between
    the feet), ready to run; with ``return_singles`` also each foot's own forward solution
    (FootTrajectory, first step along +x)."""
    pairs = ((left, stance_left), (right, stance_right))
    forward = forward_only(estimator)
    if return_singles:
        singles = [forward.estimate(imu, stance) for imu, stance in pairs]
        yaws = [float(traj.meta.get("heading_rotation_rad", 0.0)) for traj in singles]
    else:
        yaws = [first_step_yaw(forward, imu, stance) for imu, stance in pairs]
    filt = start_filter(estimator, (left, right), (stance_left, stance_right), yaws, step_width_m)
    return (filt, singles) if return_singles else filt


def first_step_yaw(forward: Any, imu: ImuData, stance: StanceResult, first_steps: int = 4) -> float:
    """The turn (rad about z) that puts the foot's first step along +x: ``forward``'s
    ``meta["heading_rotation_rad"]`` (0 when the foot never stepped), found on the shortest
    prefix of the recording that holds it.

    ``forward`` (:func:`forward_only`) is causal, so its first step's heading depends only on the
    samples up to that step's end: it runs on the first ``first_steps`` stance phases, then on
    twice as many, until the heading is found or the prefix is the whole recording. A coupled
    fusion thus filters each sample once (in its joint filter), not once more per foot alone.
    """
    intervals = stance.intervals
    n = max(2, int(first_steps))
    while n < len(intervals):
        stop = int(intervals[n - 1, 1])  # the n-th stance phase ends here: its footprint is whole
        traj = forward.estimate(imu.slice(0, stop), slice_stance(stance, 0, stop))
        if "heading_rotation_rad" in traj.meta:
            return float(traj.meta["heading_rotation_rad"])
        n *= 2
    return float(forward.estimate(imu, stance).meta.get("heading_rotation_rad", 0.0))


def start_filter(
    estimator: Any, imus: Sequence[ImuData], stances: Sequence[StanceResult], yaws: Sequence[float], step_width_m: float
) -> JointFilter:
    """``estimator.start`` with the feet turned by ``yaws`` (rad) and ``step_width_m`` apart across
    +x (left at +y); what it returns is checked to be a :class:`JointFilter`."""
    half = 0.5 * float(step_width_m)
    filt = estimator.start(
        list(imus),
        list(stances),
        initial_yaw_rad=list(yaws),
        initial_position_m=[np.array([0.0, half, 0.0]), np.array([0.0, -half, 0.0])],
    )
    if not isinstance(filt, JointFilter):
        missing = [m for m in JOINT_FILTER_MEMBERS if not hasattr(filt, m)]
        raise CompositionError(
            f"estimator {estimator.name!r}: start() returned a {type(filt).__name__}, which lacks {', '.join(missing)} "
            "of footnav.core.component.JointFilter (what coupled fusions drive)"
        )
    return filt


def closing_time(estimator: Any, imus: Sequence[ImuData], stances: Sequence[StanceResult]) -> float:
    """Time (s) a fusion's own updates must stop at so that :func:`close_loops` can apply the
    closed loop at the first final rest: that rest's last sample, or inf without ``closed_loop``."""
    if not getattr(estimator, "closed_loop", False):
        return np.inf
    return min(
        float(imu.t[final_rest(imu.t, st, what=f"{estimator.name}: closed_loop")]) for imu, st in zip(imus, stances)
    )


def close_loops(
    estimator: Any, filt: JointFilter, imus: Sequence[ImuData], stances: Sequence[StanceResult]
) -> dict | None:
    """With the estimator's ``closed_loop``, each foot's start position as a measurement at its
    final standstill (Chistyakov et al. 2021, Alg. 1, here inside the two-foot filter of Alg. 2),
    in time order; the final rest is checked (:func:`footnav.nav.final_rest.final_rest`).
    Returns what was applied (for meta), or None without ``closed_loop``."""
    if not getattr(estimator, "closed_loop", False):
        return None
    std = float(estimator.closed_loop_std_m)
    applied, ends = {}, []
    for foot, (imu, stance, name) in enumerate(zip(imus, stances, ("left", "right"))):
        last = final_rest(imu.t, stance, what=f"{estimator.name}: closed_loop ({name} foot)")
        ends.append((float(imu.t[last]), foot))
        applied[name] = {"index": last, "std_m": std}
    starts = [filt.outputs(foot)[2][0].copy() for foot in range(len(imus))]  # samples up to the start hold p0
    t_first = min(t for t, _ in ends)
    for foot in range(len(imus)):
        if filt.time(foot) > t_first:  # a fusion's own events must stop at closing_time()
            raise RuntimeError(f"the joint filter ran past the final rest at {t_first:.6g} s")
    filt.run_until(t_first)
    # both feet at once while both stand (the usual case): closing one foot alone and then the
    # other would move the first again through their correlation
    k = [int(np.searchsorted(imu.t, t_first, side="right")) - 1 for imu in imus]
    if all(st.mask[min(max(kk, 0), len(st.mask) - 1)] for kk, st in zip(k, stances)):
        blocks = [filt.block(foot, "pos") for foot in range(len(imus))]
        h = filt.selection(np.concatenate([np.arange(b.start, b.start + 3) for b in blocks]))
        innov = np.concatenate([filt.position(foot) - starts[foot] for foot in range(len(imus))])
        filt.update(h, innov, np.full(len(innov), std**2))
        return applied
    for t, foot in sorted(ends):
        filt.run_until(t)
        filt.update_position(foot, starts[foot], std)
    return applied


def finish_joint(
    estimator: Any,
    filt: JointFilter,
    stance_left: StanceResult,
    stance_right: StanceResult,
    meta: dict,
    imus: Sequence[ImuData] | None = None,
) -> FusionResult:
    """Close the loops (the estimator's ``closed_loop``; needs ``imus``), run to the end, smooth
    as ``estimator.smoother`` says, and package both feet and the path."""
    if getattr(estimator, "closed_loop", False):
        if imus is None:
            raise CompositionError(
                f"{meta.get('fusion', {}).get('name', 'this fusion')!r} does not apply the estimator's closed_loop; "
                "turn closed_loop off, or use the 'dtw' or 'range' fusion"
            )
        meta["closed_loop"] = close_loops(estimator, filt, imus, (stance_left, stance_right))
    left, right = estimator.finish(filt, (stance_left, stance_right))
    return FusionResult(left=left, right=right, path=midpoint_path(left, right), meta=meta)


def continue_rigidly(alone: tuple, alone_anchor: tuple, fused_anchor: tuple) -> tuple:
    """A foot estimated alone (position (N, 3) m, velocity (N, 3) m/s, attitude (N, 4)), turned
    about z and moved so that its ``alone_anchor`` sample (position, attitude) lands on
    ``fused_anchor`` (position, attitude): what a coupled fusion puts outside the feet's common
    span. Returns the position, velocity and attitude."""
    pos, vel, q = alone
    turn = float(quat.yaw(fused_anchor[1]) - quat.yaw(alone_anchor[1]))
    c, s = np.cos(turn), np.sin(turn)
    rot = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
    return (pos - alone_anchor[0]) @ rot.T + fused_anchor[0], vel @ rot.T, quat.multiply(quat.from_yaw(turn), q)


def _continue_alone(fused: FootTrajectory, alone: FootTrajectory, cut: FootCut) -> tuple[FootTrajectory, dict]:
    """``fused`` (samples ``cut.start_index:cut.stop_index`` of the foot) on the foot's whole
    sample grid: outside, ``alone`` (the foot estimated alone) turned about z and moved so that
    it meets the fused foot at the anchor sample (the span's last sample after it; the fused
    estimate's start, i.e. its first stance, before it)."""
    i0, i1 = cut.start_index, cut.stop_index
    pos, vel, q = alone.position.copy(), alone.velocity.copy(), alone.quaternion.copy()
    std = alone.position_std.copy()
    first = fused_start(fused.meta, i0)  # the first fused sample kept
    s0 = first - i0
    pos[first:i1], vel[first:i1] = fused.position[s0:], fused.velocity[s0:]
    q[first:i1], std[first:i1] = fused.quaternion[s0:], fused.position_std[s0:]
    for lo, hi, anchor in ((0, first, first), (i1, cut.n_samples, i1 - 1)):
        if hi <= lo:
            continue
        k = anchor - i0  # in the fused trajectory
        pos[lo:hi], vel[lo:hi], q[lo:hi] = continue_rigidly(
            (alone.position[lo:hi], alone.velocity[lo:hi], alone.quaternion[lo:hi]),
            (alone.position[anchor], alone.quaternion[anchor]),
            (fused.position[k], fused.quaternion[k]),
        )
        # the fused uncertainty at the edge plus what the foot alone gained since (or before)
        grow = np.maximum(alone.position_std[lo:hi] ** 2 - alone.position_std[anchor] ** 2, 0.0)
        std[lo:hi] = np.sqrt(fused.position_std[k] ** 2 + grow)
    alone_idx = [[0, first], [i1, cut.n_samples]]
    info = {"fused_samples": [first, i1], "alone_samples": [r for r in alone_idx if r[1] > r[0]]}
    traj = FootTrajectory(
        t=alone.t,
        position=pos,
        velocity=vel,
        quaternion=q,
        position_std=std,
        steps=alone.steps,
        meta={
            **fused.meta,
            "span": info,
            "estimate_start_index": first if i0 > 0 else fused.meta.get("estimate_start_index", 0),
        },
    )
    return traj, info


def fused_start(meta: Mapping[str, Any], start_index: int) -> int:
    """The foot's first sample (its own index) that a coupled fusion's result takes from the
    fused estimate, the common span starting at the foot's sample ``start_index``: the span's
    start, or, when the span cuts the foot's start, the fused estimate's first stance (its
    ``meta["estimate_start_index"]``)."""
    return start_index + (int(meta.get("estimate_start_index", 0)) if start_index > 0 else 0)


def on_whole_span(
    result: FusionResult, span: CommonSpan, alone: Callable[[int], FootTrajectory] | None
) -> FusionResult:
    """A coupled fusion's ``result`` on the common ``span`` put on each foot's whole sample grid:
    outside the span, ``alone(foot)`` (0 left, 1 right; the foot estimated alone) continued
    rigidly from the fused edge; ``meta["span"]`` says which samples are which. (The caller
    warns when ``span.warn``.)"""
    if not span.cut:
        return FusionResult(
            result.left, result.right, result.path, meta={**result.meta, "span": {**span.as_meta(), "outside": None}}
        )
    assert alone is not None  # given with a span that cuts a foot
    out, infos = [], {}
    for foot, (cut, fused, name) in enumerate(
        zip((span.left, span.right), (result.left, result.right), ("left", "right"))
    ):
        assert fused is not None  # a coupled fusion's result has both feet
        if not cut.cut:
            out.append(fused)
            continue
        traj, infos[name] = _continue_alone(fused, alone(foot), cut)
        out.append(traj)
    meta = {
        **result.meta,
        "span": {**span.as_meta(), "outside": OUTSIDE_SPAN, **{f"{k}_samples": v for k, v in infos.items()}},
    }
    path = result.path
    return FusionResult(
        left=out[0],
        right=out[1],
        path=type(path)(t=path.t, position=path.position, meta={**path.meta, "span": [span.start_s, span.stop_s]}),
        meta=meta,
    )


def fuse_on_common_span(
    fusion: Any,
    estimator: Any,
    left: ImuData,
    stance_left: StanceResult,
    right: ImuData | None,
    stance_right: StanceResult | None,
    fuse_span: Callable[..., FusionResult],
) -> FusionResult:
    """Run ``fuse_span(estimator, left, stance_left, right, stance_right)`` on the feet's common
    time span (module docstring); ``meta["span"]`` records the span and each foot's cut.

    Raises
    ------
    CompositionError
        As :func:`check_two_feet`.
    InvalidInputError
        Field ``t``: the feet share no (or less than 3 s of) time span, or the common span holds
        no stance of a foot.
    """
    check_two_feet(fusion, estimator, right, stance_right)
    assert right is not None and stance_right is not None
    pairs = ((left, stance_left), (right, stance_right))
    if any(len(st.mask) != len(imu.t) for imu, st in pairs):
        return fuse_span(estimator, left, stance_left, right, stance_right)  # the estimator names the bad mask
    span = common_span(left, right, fusion=fusion.name)
    if not span.cut:
        return on_whole_span(fuse_span(estimator, left, stance_left, right, stance_right), span, None)
    if getattr(estimator, "closed_loop", False) and (
        span.left.stop_index < span.left.n_samples or span.right.stop_index < span.right.n_samples
    ):
        raise InvalidInputError(
            f"fusion {fusion.name!r}: closed_loop needs both feet's final rests inside their common span "
            f"({span.start_s:.6g}..{span.stop_s:.6g} s), but a foot goes on after it; cut the feet to a common end "
            "or turn closed_loop off",
            field="t",
        )
    if span.warn:
        warn(span.message(fusion.name, OUTSIDE_SPAN), DataQualityWarning, stacklevel=3)
    cuts = (span.left, span.right)
    feet, stances = [], []
    for (imu, st), cut, name in zip(pairs, cuts, ("left", "right")):
        st_cut = slice_stance(st, cut.start_index, cut.stop_index)
        if not st_cut.mask.any():
            raise InvalidInputError(
                f"fusion {fusion.name!r}: the common span {span.start_s:.6g}..{span.stop_s:.6g} s holds no stance "
                f"of the {name} foot; nothing to fuse there",
                field="t",
            )
        feet.append(imu.slice(cut.start_index, cut.stop_index))
        stances.append(st_cut)
    result = fuse_span(estimator, feet[0], stances[0], feet[1], stances[1])
    return on_whole_span(result, span, lambda foot: estimator.estimate(*pairs[foot]))
