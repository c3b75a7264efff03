"""Comparing stance detectors on one recording: the table (and picture) a gait class looks at.

For each detector and foot, against whatever reference the recording has:

* with hand-labelled swings inside trial boundaries (IPOL): steps found / missed / false by
  :func:`~footnav.analysis.metrics.step_detection_from_swings`, per-sample scores inside the labelled
  span;
* with a reference stance mask (simulator truth, proxy labels): steps found / missed / false by
  matching stance phases (:func:`~footnav.analysis.metrics.step_detection`), per-sample precision,
  recall and F1;
* with one reference event per stance (mocap-derived ``mid_stance``, as in the gaitmap example;
  each ``footprint`` of the gait-driven set):
  steps found / missed / false by :func:`~footnav.analysis.metrics.step_detection_from_events`;
* for every gait event both the detector and the reference give (heel strike, foot flat, heel
  off, toe off): the mean absolute timing error (Li et al. (2018), Table 1 counts, plus timing);
* without any reference: the gait cycles with no stance and the stances holding a swing, from the
  angular rate's swing peaks (:mod:`footnav.nav.stance_check`);
* the runtime of the detector on the recording.
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

from footnav.analysis import metrics
from footnav.analysis.evaluation import EvaluationReport, Metric, labelled_swings
from footnav.core.component import StanceDetector
from footnav.core.errors import FootnavError
from footnav.core.types import FootTruth, ImuData, Recording, StanceResult
from footnav.nav.stance_check import check_stances

__all__ = ["DetectorComparison", "compare_detectors", "DEFAULT_TOLERANCE_S"]

#: Largest distance between a detected and a reference stance or event for a match, s (about a
#: quarter of a stride at normal walking speed).
DEFAULT_TOLERANCE_S = 0.15
_EVENTS = ("heel_strike", "foot_flat", "heel_off", "toe_off")


@dataclass(frozen=True)
class DetectorComparison:
    """The metrics of each detector (``report``, one column per detector) and its stance results."""

    recording: Recording
    report: EvaluationReport
    stances: dict[str, tuple[StanceResult, StanceResult | None]] = field(default_factory=dict)
    #: Detectors that raised a footnav error on this recording, with the message.
    failures: dict[str, str] = field(default_factory=dict)

    def to_text(self) -> str:
        """The metrics table as text, then one line per detector that failed."""
        text = self.report.to_text()
        return text + "".join(f"\n{label} failed: {msg}" for label, msg in self.failures.items())

    def to_csv(self) -> str:
        """The metrics table as CSV (the failures are in :attr:`failures`)."""
        return self.report.to_csv()

    def plot(self, path: Any, *, seconds: tuple[float, float] | None = None):
        """Gyro norm with each detector's stance stacked below it (needs matplotlib)."""
        from footnav.analysis.plot import plot_stance_comparison

        return plot_stance_comparison(self, path, seconds=seconds)


def _resolve(detectors: Sequence[Any] | None, two_feet: bool) -> list[tuple[str, StanceDetector]]:
    from footnav.pipeline.factory import _registry

    reg = _registry()
    if detectors is None:
        detectors = [n for n in reg.names("detector") if two_feet or not reg.get("detector", n).cls.needs_two_feet]
    out = []
    for d in detectors:
        if isinstance(d, tuple):
            label, det = d
        elif isinstance(d, StanceDetector):
            label, det = d.name, d
        else:
            label, det = str(d), reg.create("detector", str(d))
        out.append((label, det))
    return out


def _foot_metrics(
    stance: StanceResult, truth: FootTruth | None, imu: ImuData, tol_s: float
) -> list[tuple[str, float, str]]:
    check = check_stances(imu, stance)
    rows: list[tuple[str, float, str]] = [
        ("stances", float(stance.n_stances), "count"),
        ("cycles_without_stance", float(len(check.missed_s)), "count"),
        ("stances_over_swing", float(len(check.over_swing_s)), "count"),
    ]
    rate_hz = imu.rate_hz
    if truth is None:
        return rows
    tol = tol_s * rate_hz
    steps = None
    swings = labelled_swings(truth)
    if swings is not None and len(swings[0]) == len(stance.mask) and truth.stance is not None:
        # hand-labelled swings inside trial boundaries (IPOL): outside them the truth says nothing
        labelled, boundaries, pairs = swings
        steps = metrics.step_detection_from_swings(stance.mask, pairs, boundaries, tolerance_samples=tol)
        scores = metrics.sample_scores(stance.mask[labelled], truth.stance[labelled])
        rows += [("precision", scores.precision, ""), ("recall", scores.recall, ""), ("f1", scores.f1, "")]
    elif truth.stance is not None and len(truth.stance) == len(stance.mask):
        steps = metrics.step_detection(stance.mask, truth.stance, tolerance_samples=tol)
        scores = metrics.sample_scores(stance.mask, truth.stance)
        rows += [("precision", scores.precision, ""), ("recall", scores.recall, ""), ("f1", scores.f1, "")]
    else:
        # one reference instant per stance: mocap mid-stance (gaitmap), a footprint (gaitdriven)
        event = next((e for e in ("mid_stance", "footprint") if len(truth.events.get(e, ()))), None)
        if event is not None:
            steps = metrics.step_detection_from_events(stance.mask, truth.events[event], tolerance_samples=tol)
    if steps is not None:
        rows = (
            rows[:3]
            + [
                ("steps_reference", float(steps.n_reference), "count"),
                ("steps_found", float(steps.n_found), "count"),
                ("steps_missed", float(steps.n_missed), "count"),
                ("steps_false", float(steps.n_false), "count"),
                ("step_f1", float(steps.f1), ""),
            ]
            + rows[3:]
        )
    for event in _EVENTS:
        det, ref = stance.events.get(event), truth.events.get(event)
        if det is None or ref is None or len(det) == 0 or len(ref) == 0:
            continue
        timing = metrics.event_timing_error(det, ref, tolerance=tol, rate_hz=rate_hz)
        if timing.n_matched:
            rows.append((f"{event}_error", 1e3 * timing.mean_abs_error_s, "ms"))
    return rows


def compare_detectors(
    recording: Recording,
    detectors: Sequence[str | StanceDetector | tuple[str, StanceDetector]] | None = None,
    *,
    tolerance_s: float = DEFAULT_TOLERANCE_S,
) -> DetectorComparison:
    """Run each detector on ``recording`` and measure it against the recording's reference.

    Parameters
    ----------
    recording
        One or two feet, with truth (:func:`footnav.simulate`, :func:`footnav.load`, a shared
        dataset); without truth only stance counts and runtimes are reported.
    detectors
        Registered names, detector instances or ``(label, detector)`` pairs; default every
        registered detector the recording can feed (two-foot detectors need two feet).
    tolerance_s
        Matching tolerance for stances and events, s.

    Examples
    --------
    >>> cmp = compare_detectors(footnav.simulate("straight", distance_m=20), ["threshold", "glrt"])  # doctest: +SKIP
    >>> print(cmp.to_text()); cmp.plot("detectors.png")  # doctest: +SKIP
    """
    rows: list[Metric] = []
    stances: dict[str, tuple[StanceResult, StanceResult | None]] = {}
    failures: dict[str, str] = {}
    name = recording.name or "recording"
    for label, det in _resolve(detectors, recording.right is not None):
        t0 = time.perf_counter()
        try:
            left, right = det.detect_pair(recording.left, recording.right)
        except FootnavError as exc:  # a method that cannot handle this recording is a result too
            rows.append(Metric(name, label, "both", "failed", 1.0, ""))
            failures[label] = str(exc)
            continue
        runtime = time.perf_counter() - t0
        stances[label] = (left, right)
        feet = [("left", left, recording.truth_left, recording.left)]
        if right is not None:
            feet.append(("right", right, recording.truth_right, recording.right))
        for foot, stance, truth, imu in feet:
            for metric, value, unit in _foot_metrics(stance, truth, imu, tolerance_s):
                rows.append(Metric(name, label, foot, metric, float(value), unit))
        rows.append(Metric(name, label, "both", "runtime", 1e3 * runtime, "ms"))
    return DetectorComparison(
        recording=recording, report=EvaluationReport(tuple(rows)), stances=stances, failures=failures
    )
