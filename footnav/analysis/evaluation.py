"""The evaluation harness: run a pipeline on a recording and measure it against the recording's truth.

Every accuracy figure footnav reports comes from :func:`evaluate`. It computes each metric the
recording supports (see :mod:`footnav.analysis.metrics` for the definitions):

* per foot: path length; with reference positions, the 2-D and 3-D absolute trajectory error
  after rigid alignment (``ate_2d``, ``ate_3d``) and the vertical RMSE after removing the best
  constant height offset (``height_rmse``);
  with reference stance, per-sample F1 and steps found / missed / false;
* per foot, with footprint truth (``FootTruth.frame == "footprints"``, the gait-driven set):
  ``footprint_rmse`` and ``footprint_final_error`` (m) after one rigid 2-D fit, instead of the
  ATE rows (which would compare the same points again, and 3-D against footprints at z = 0);
* per foot, with labelled swings inside trial boundaries (the IPOL set, ``meta["labelled"]``):
  ``step_f1``, ``steps_found`` / ``steps_missed`` / ``steps_false`` and a per-sample
  ``stance_f1``, all computed inside the labelled span only (outside it the truth says nothing);
* per foot, with reference positions: the papers' errors after aligning the start and the
  initial heading only (:func:`footnav.analysis.metrics.align_at_start`): ``end_error_2d`` /
  ``end_error_3d`` (Zhao et al. 2019's E_p, eq. 8, is the 3-D one; Li et al. 2018's end-to-end
  error the 2-D one), ``travelled_distance_error_percent`` (Li et al. 2018, Table 2),
  ``max_deviation_2d`` (Chistyakov et al. 2021, Table 2) and, where the truth marks waypoints
  (the simulator does), ``waypoint_error_mean`` / ``_max`` (Lee, Cho & Park 2022, Table 3);
  for walks that return to their start ``loop_closure_2d`` / ``loop_closure_3d`` (m and %) and the
  end-to-start height change ``loop_closure_dz`` (m, signed);
* both feet: the final foot separation E_s (Zhao et al. 2019, eq. 8, 3-D) and the DTW distance
  between the feet's tracks ``dtw_distance_feet`` (Chistyakov et al. 2021, Table 1);
* over several recordings or seeds, :meth:`EvaluationReport.summary`: mean +- std of each;
* the runtime of the pipeline.

Before any metric, each foot's truth is checked against the estimate
(:func:`footnav.analysis.truth_checks.check_truth`: time base, coverage of the walk, length unit,
mirrored frame, z down, the 3-D fit's tilt): a truth that cannot be right (mm, cm, times in ms, no
overlap) raises InvalidInputError; a suspect one warns, and every check's figure is in
:attr:`EvaluationReport.checks` (the warnings listed under :meth:`EvaluationReport.to_text`).

A run that raises does not have to end a batch: ``evaluate(..., on_error="record")`` (the default
of :func:`footnav.evaluate_many`) returns a report holding an :class:`EvaluationFailure` instead
of metrics, shown as an ``error`` row in :meth:`EvaluationReport.to_text` and
:meth:`EvaluationReport.to_csv`.
"""

from __future__ import annotations

import csv
import io
import time
import traceback as tb
from dataclasses import dataclass, field
from typing import Any, Literal

import numpy as np

from footnav.analysis import metrics
from footnav.analysis.truth_checks import TruthCheck, check_truth
from footnav.core.errors import FootnavWarning, InvalidParameterError, MetricNotFoundError
from footnav.core.types import FootTrajectory, FootTruth, Recording, StanceResult
from footnav.core.warning_log import warn
from footnav.nav.interpolation import interp_columns
from footnav.pipeline.factory import Pipeline
from footnav.pipeline.result import PipelineResult

__all__ = ["Metric", "EvaluationFailure", "EvaluationReport", "TruthCheck", "evaluate", "trajectory_at"]

#: ``on_error`` values of :func:`evaluate` and :func:`footnav.evaluate_many`.
ON_ERROR = ("raise", "record")
#: Name of the row a failed run gets in :meth:`EvaluationReport.to_text` and ``to_csv``.
ERROR_ROW = "error"


@dataclass(frozen=True)
class Metric:
    """One measured number: what, of which foot, in which unit, on which recording and pipeline."""

    recording: str
    pipeline: str
    foot: str
    name: str
    value: float
    unit: str


@dataclass(frozen=True)
class EvaluationFailure:
    """A (recording, pipeline) run that raised instead of giving metrics.

    ``error_type`` is the exception's class name (``CompositionError``, ``PluginError`` for a
    third-party component's bug, ``LinAlgError`` ...), ``message`` its text; ``traceback`` is the
    formatted traceback, for a bug report (left out of ``repr`` and comparisons).
    """

    recording: str
    pipeline: str
    error_type: str
    message: str
    traceback: str = field(default="", repr=False, compare=False)

    @classmethod
    def from_exception(cls, recording: str, pipeline: str, exc: BaseException) -> EvaluationFailure:
        """The record of ``exc``, raised by ``pipeline`` on ``recording``, with its traceback."""
        return cls(recording, pipeline, type(exc).__name__, str(exc), "".join(tb.format_exception(exc)))

    def __str__(self) -> str:
        message = " ".join(self.message.split())  # one line, whatever the exception's text
        return f"{self.recording} / {self.pipeline}: {self.error_type}: {message}"


def fatal(exc: BaseException) -> BaseException | None:
    """The exception that must end a batch instead of being recorded, or None.

    Recorded: any :class:`Exception` -- footnav's own errors, a component's (a plugin's bug or
    ``sys.exit`` arrives as a PluginError naming it). Fatal: KeyboardInterrupt, SystemExit and
    MemoryError, including a MemoryError a PluginError wraps (then the MemoryError is returned).
    """
    if not isinstance(exc, Exception):
        return exc
    cause: BaseException | None = exc
    while cause is not None:
        if isinstance(cause, MemoryError):
            return cause
        cause = cause.__cause__
    return None


@dataclass(frozen=True)
class EvaluationReport:
    """The metrics of one or more (pipeline, recording) runs, the runs' results, the runs that
    failed (``failures``: one :class:`EvaluationFailure` each, no metrics, no result) and the
    checks of each foot's truth (``checks``: one :class:`TruthCheck` per check and foot, its
    figure and ``status`` ``"ok"`` or ``"warning"``; :attr:`warnings` the latter)."""

    metrics: tuple[Metric, ...]
    results: dict[tuple[str, str], PipelineResult] = field(default_factory=dict, compare=False)
    failures: tuple[EvaluationFailure, ...] = ()
    checks: tuple[TruthCheck, ...] = ()

    @property
    def warnings(self) -> tuple[TruthCheck, ...]:
        """The truth checks that warned (a suspect truth: part of the walk, mirrored, odd scale)."""
        return tuple(c for c in self.checks if c.status == "warning")

    def value(self, name: str, foot: str = "left", recording: str | None = None, pipeline: str | None = None) -> float:
        """The value of one metric (the first match).

        Raises
        ------
        MetricNotFoundError
            No such metric for ``foot`` (the message says when the run that would have given it
            failed); a KeyError too.
        """
        for m in self.metrics:
            if (
                m.name == name
                and m.foot == foot
                and (recording is None or m.recording == recording)
                and (pipeline is None or m.pipeline == pipeline)
            ):
                return m.value
        failed = [
            f
            for f in self.failures
            if (recording is None or f.recording == recording) and (pipeline is None or f.pipeline == pipeline)
        ]
        if failed:
            raise MetricNotFoundError(f"no metric {name!r} for foot {foot!r}: the run failed ({failed[0]})")
        raise MetricNotFoundError(f"no metric {name!r} for foot {foot!r}")

    def __add__(self, other: EvaluationReport) -> EvaluationReport:
        return EvaluationReport(
            self.metrics + other.metrics,
            {**self.results, **other.results},
            self.failures + other.failures,
            self.checks + other.checks,
        )

    def rows(self) -> list[dict[str, Any]]:
        """The rows of :meth:`to_csv`, as dicts: each metric, then an ``error`` row per failure."""
        rows = [m.__dict__.copy() for m in self.metrics]
        if not self.failures:
            return rows
        for row in rows:
            row["error"] = ""
        return rows + [
            {
                "recording": f.recording,
                "pipeline": f.pipeline,
                "foot": "both",
                "name": ERROR_ROW,
                "value": float("nan"),
                "unit": "",
                "error": f"{f.error_type}: {f.message}",
            }
            for f in self.failures
        ]

    def to_csv(self) -> str:
        """The metrics as CSV: ``recording,pipeline,foot,name,value,unit``, one row per metric.

        With failures, a last column ``error`` is added: empty for the metrics, and one row per
        failed run with ``name`` ``error``, ``foot`` ``both``, ``value`` nan and ``error``
        ``"ErrorType: message"`` -- so ``pandas.read_csv`` keeps ``value`` numeric and
        ``df[df.name == "error"]`` lists the failures. (Without failures the header stays the
        six columns earlier versions wrote.)
        """
        buf = io.StringIO()
        fields = ["recording", "pipeline", "foot", "name", "value", "unit"] + (["error"] if self.failures else [])
        writer = csv.DictWriter(buf, fieldnames=fields)
        writer.writeheader()
        writer.writerows(self.rows())
        return buf.getvalue()

    def summary(self) -> list[dict[str, Any]]:
        """Each metric's mean and standard deviation over the recordings, per pipeline and foot.

        The papers report mean +- std over repeated walks; with the simulator, repeat by seed::

            runs = [functools.partial(footnav.simulate, "rectangle", seed=s) for s in range(10)]
            footnav.evaluate_many(pipe, runs).summary()

        Returns
        -------
        list of dict
            Rows with ``pipeline, foot, name, unit, mean, std, n`` (``std`` with ddof=1: the
            sample standard deviation, nan for one recording); non-finite values are left out
            of both and not counted in ``n``, and so are failed runs (``failures``).
        """
        groups: dict[tuple[str, str, str, str], list[float]] = {}
        for m in self.metrics:
            groups.setdefault((m.pipeline, m.foot, m.name, m.unit), []).append(m.value)
        rows = []
        for (pipe, foot, name, unit), values in groups.items():
            v = np.asarray([x for x in values if np.isfinite(x)], dtype=float)
            rows.append(
                {
                    "pipeline": pipe,
                    "foot": foot,
                    "name": name,
                    "unit": unit,
                    "mean": float(v.mean()) if len(v) else float("nan"),
                    "std": float(v.std(ddof=1)) if len(v) > 1 else float("nan"),
                    "n": int(len(v)),
                }
            )
        return rows

    def summary_text(self) -> str:
        """:meth:`summary` as a table: one row per (metric, foot), ``mean +- std (n)`` per pipeline."""
        rows = self.summary()
        pipelines = list(dict.fromkeys(r["pipeline"] for r in rows))
        keys = list(dict.fromkeys((r["name"], r["foot"], r["unit"]) for r in rows))
        cell = {
            (r["name"], r["foot"], r["unit"], r["pipeline"]): f"{_fmt(r['mean'])} +- {_fmt(r['std'])} ({r['n']})"
            for r in rows
        }
        table = _table(
            ["metric", "foot", "unit"] + pipelines,
            [list(k) + [cell.get(k + (p,), "") for p in pipelines] for k in keys],
        )
        return table + self._failures_text() + self._warnings_text()

    def to_text(self) -> str:
        """A table: one row per (recording, metric, foot), one column per pipeline.

        A failed run shows its error type in an ``error`` row of its recording (its other cells
        stay empty), and after the table one line per failure gives the message, then one line
        per truth check that warned.
        """
        pipelines = list(dict.fromkeys([m.pipeline for m in self.metrics] + [f.pipeline for f in self.failures]))
        by_recording: dict[str, list[tuple[str, str, str, str]]] = {}
        for m in self.metrics:
            by_recording.setdefault(m.recording, []).append((m.recording, m.name, m.foot, m.unit))
        for f in self.failures:
            by_recording.setdefault(f.recording, []).append((f.recording, ERROR_ROW, "both", ""))
        keys = list(dict.fromkeys(k for ks in by_recording.values() for k in ks))
        table: dict[tuple[str, ...], str] = {
            (m.recording, m.name, m.foot, m.unit, m.pipeline): _fmt(m.value) for m in self.metrics
        }
        table.update({(f.recording, ERROR_ROW, "both", "", f.pipeline): f.error_type for f in self.failures})
        header = ["recording", "metric", "foot", "unit"] + pipelines
        return (
            _table(header, [list(k) + [table.get(k + (p,), "") for p in pipelines] for k in keys])
            + self._failures_text()
            + self._warnings_text()
        )

    def _warnings_text(self) -> str:
        warned = self.warnings
        if not warned:
            return ""
        return f"\n\ntruth warnings ({len(warned)}):" + "".join(f"\n  {c}" for c in warned)

    def _failures_text(self) -> str:
        if not self.failures:
            return ""
        runs = len(
            {(m.recording, m.pipeline) for m in self.metrics} | {(f.recording, f.pipeline) for f in self.failures}
        )
        return f"\n\nfailed ({len(self.failures)} of {runs} runs):" + "".join(f"\n  {f}" for f in self.failures)


def _table(header: list[str], rows: list[list[Any]]) -> str:
    widths = [max(len(str(r[i])) for r in [header] + rows) for i in range(len(header))]
    out = ["  ".join(str(c).ljust(w) for c, w in zip(header, widths)).rstrip()]
    out.append("  ".join("-" * w for w in widths))
    out += ["  ".join(str(c).ljust(w) for c, w in zip(r, widths)).rstrip() for r in rows]
    return "\n".join(out)


def _fmt(value: float | None) -> str:
    if value is None:
        return ""
    if not np.isfinite(value):
        return "nan"
    if float(value).is_integer() and abs(value) < 1e6:
        return str(int(value))
    return f"{value:.3f}"


def trajectory_at(traj: FootTrajectory, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Estimated positions linearly interpolated at times ``t`` within the estimate's span, and the
    boolean mask of the ``t`` that fall inside it."""
    inside = (t >= traj.t[0]) & (t <= traj.t[-1])
    tt = t[inside]
    pos = interp_columns(tt, traj.t, traj.position[:, :3])
    return pos, inside


def labelled_swings(truth: FootTruth) -> tuple[np.ndarray, tuple[int, int], np.ndarray] | None:
    """(labelled mask, half-open boundaries, (K, 2) swings) when the truth labels swings only inside
    trial boundaries (read_ipol), else None."""
    labelled = truth.meta.get("labelled")
    boundaries = truth.meta.get("trial_boundaries")
    if labelled is None or boundaries is None or not {"toe_off", "heel_strike"} <= set(truth.events):
        return None
    pairs = np.column_stack((truth.events["toe_off"], truth.events["heel_strike"]))
    return np.asarray(labelled, dtype=bool), (int(boundaries[0]), int(boundaries[1])), pairs


def _paper_metrics(est: np.ndarray, ref: np.ndarray, truth: FootTruth) -> list[tuple[str, float, str]]:
    """The papers' errors of a walk with a known start and initial heading
    (:func:`footnav.analysis.metrics.align_at_start`): end error (E_p of Zhao et al. 2019, eq. 8, in
    3-D; Li et al. 2018's end-to-end error in 2-D), travelled-distance error (Li et al. 2018,
    Table 2), maximum deviation (Chistyakov et al. 2021, Table 2) and, where the truth has
    waypoints, the waypoint error (Lee, Cho & Park 2022, Table 3)."""
    aligned = metrics.align_at_start(est, ref).aligned
    out: list[tuple[str, float, str]] = []
    for dims in (2, 3):
        end = metrics.end_to_end_error(aligned, ref, dims=dims)
        out.append((f"end_error_{dims}d", end.error_m, "m"))
        out.append((f"end_error_{dims}d_percent", end.error_percent, "%"))
    dist = metrics.travelled_distance_error(aligned, ref, dims=2)
    out.append(("travelled_distance_error_percent", dist.error_percent, "%"))
    dev = metrics.max_deviation(aligned, ref, dims=2)
    out.append(("max_deviation_2d", dev.max_deviation_m, "m"))
    out.append(("max_deviation_2d_percent", dev.max_deviation_percent, "%"))
    waypoints = truth.meta.get("waypoints_m")
    if waypoints is not None and len(waypoints):
        wp = metrics.waypoint_errors(aligned, ref, waypoints)
        if len(wp.errors_m):
            out.append(("waypoint_error_mean", wp.mean_m, "m"))
            out.append(("waypoint_error_max", wp.max_m, "m"))
    return out


#: The feet's tracks are compared at this rate, with matched points at most FEET_DTW_BAND_S apart
#: in time (Chistyakov et al. 2021, Sec. 3: "a limit on the maximum difference of indices").
FEET_DTW_RATE_HZ, FEET_DTW_BAND_S = 10.0, 2.0


def _feet_dtw(left: FootTrajectory, right: FootTrajectory) -> float:
    """Mean banded DTW distance between the two feet's horizontal tracks, m (Chistyakov et al.
    2021, Table 1), on their common span resampled to ``FEET_DTW_RATE_HZ``."""
    t = np.arange(max(left.t[0], right.t[0]), min(left.t[-1], right.t[-1]), 1.0 / FEET_DTW_RATE_HZ)
    if len(t) < 2:
        return float("nan")
    a, _ = trajectory_at(left, t)
    b, _ = trajectory_at(right, t)
    return float(metrics.dtw_distance(a, b, band=int(round(FEET_DTW_BAND_S * FEET_DTW_RATE_HZ)), dims=2).distance_m)


def _foot_metrics(
    traj: FootTrajectory, stance: StanceResult, truth: FootTruth | None, rate_hz: float
) -> list[tuple[str, float, str]]:
    out: list[tuple[str, float, str]] = [
        ("path_length", traj.path_length_m, "m"),
        ("stances", float(stance.n_stances), "count"),
    ]
    if truth is None:
        return out
    if truth.frame == "footprints":
        if len(truth.t) > 1:
            est, inside = trajectory_at(traj, truth.t)
            if inside.sum() >= 2:
                fp = metrics.footprint_errors(est, truth.position[inside])
                out.append(("footprint_rmse", fp.rmse_m, "m"))
                out.append(("footprint_final_error", fp.final_m, "m"))
                out.append(("reference_path_length", metrics.travelled_distance(truth.position[inside], dims=2), "m"))
    elif len(truth.t) > 1:
        est, inside = trajectory_at(traj, truth.t)
        ref = truth.position[inside]
        out.append(("ate_2d", metrics.ate_rmse(est, ref, dims=2), "m"))
        out.append(("ate_3d", metrics.ate_rmse(est, ref, dims=3), "m"))
        out.append(("height_rmse", metrics.height_rmse(est, ref), "m"))
        out.append(("reference_path_length", metrics.travelled_distance(ref, dims=2), "m"))
        if len(ref) >= 2:
            out += _paper_metrics(est, ref, truth)
    if truth.closed_loop:
        for dims in (2, 3):
            loop = metrics.loop_closure_error(traj.position, dims=dims)
            out.append((f"loop_closure_{dims}d", float(loop.error_m), "m"))
            out.append((f"loop_closure_{dims}d_percent", float(loop.error_percent), "%"))
        out.append(("loop_closure_dz", float(traj.position[-1, 2] - traj.position[0, 2]), "m"))
    tolerance = max(1, round(0.1 * rate_hz))
    swings = labelled_swings(truth)
    if swings is not None:
        labelled, boundaries, pairs = swings
        if len(labelled) == len(stance.mask) and truth.stance is not None:
            scores = metrics.sample_scores(stance.mask[labelled], truth.stance[labelled])
            out.append(("stance_f1", float(scores.f1), ""))
            steps = metrics.step_detection_from_swings(stance.mask, pairs, boundaries, tolerance_samples=tolerance)
            out.append(("step_f1", float(steps.f1), ""))
            out.append(("steps_found", float(steps.found), "count"))
            out.append(("steps_missed", float(steps.missed), "count"))
            out.append(("steps_false", float(steps.false), "count"))
    elif truth.stance is not None and len(truth.stance) == len(stance.mask):
        scores = metrics.sample_scores(stance.mask, truth.stance)
        out.append(("stance_f1", float(scores.f1), ""))
        steps = metrics.step_detection(stance.mask, truth.stance, tolerance_samples=tolerance)
        out.append(("steps_found", float(steps.found), "count"))
        out.append(("steps_missed", float(steps.missed), "count"))
        out.append(("steps_false", float(steps.false), "count"))
    return out


def evaluate(
    pipeline: Pipeline,
    recording: Recording,
    *,
    pipeline_name: str | None = None,
    on_error: Literal["raise", "record"] = "raise",
) -> EvaluationReport:
    """Run ``pipeline`` on ``recording`` and measure every metric its truth supports.

    Parameters
    ----------
    pipeline
        A composed pipeline (:func:`footnav.make_pipeline` / :func:`footnav.load_pipeline`).
    recording
        The data and its truth (:func:`footnav.load`, :func:`footnav.simulate`).
    pipeline_name
        Column name in the table; default ``detector+estimator+fusion``.
    on_error
        ``"raise"`` (default): an error of the run propagates. ``"record"``: it is returned as
        the report's one :class:`EvaluationFailure` (no metrics), with a warning -- what
        :func:`footnav.evaluate_many` does for each pair so that one failure does not end a
        batch. KeyboardInterrupt, SystemExit and MemoryError always propagate.

    Raises
    ------
    InvalidInputError
        (``on_error="raise"``) A foot's truth fails a check before any metric is computed
        (:func:`footnav.analysis.truth_checks.check_truth`: positions not in m, times not in s,
        no overlap with the recording); the message gives the figures and the conversion.
        Suspect truths only warn, recorded in the report's ``checks``.

    Examples
    --------
    >>> walk = footnav.simulate("rectangle", seed=3)
    >>> one_foot = footnav.Recording(left=walk.left, truth_left=walk.truth_left, name="left only")
    >>> report = footnav.evaluate(footnav.make_pipeline(fusion="step-vector"), one_foot, on_error="record")
    >>> report.failures[0].error_type
    'CompositionError'
    """
    if on_error not in ON_ERROR:
        raise InvalidParameterError(
            f"evaluate: on_error={on_error!r} is invalid; expected one of {', '.join(ON_ERROR)}"
        )
    name = pipeline_name or "+".join(c.name for c in pipeline.components)
    if on_error == "raise":
        return _evaluate(pipeline, recording, name)
    report = evaluate_or_record(pipeline, recording, name)
    if report.failures:
        warn(f"evaluate: the run failed: {report.failures[0]}", FootnavWarning, stacklevel=2)
    return report


def recording_label(recording: Recording) -> str:
    """The name a recording's rows carry: its ``name``, else its source."""
    return recording.name or str(recording.meta.get("source", "recording"))


def evaluate_or_record(pipeline: Pipeline, recording: Recording, pipeline_name: str) -> EvaluationReport:
    """:func:`evaluate` with ``on_error="record"``, without the warning (the batch warns once)."""
    try:
        return _evaluate(pipeline, recording, pipeline_name)
    except Exception as exc:  # KeyboardInterrupt and SystemExit pass by themselves
        if (end := fatal(exc)) is not None:
            raise end  # noqa: B904 - the exception itself, or the MemoryError it wraps
        return EvaluationReport(
            (), failures=(EvaluationFailure.from_exception(recording_label(recording), pipeline_name, exc),)
        )


def _evaluate(pipeline: Pipeline, recording: Recording, name: str) -> EvaluationReport:
    t0 = time.perf_counter()
    result = pipeline.run(recording.left, recording.right)
    runtime = time.perf_counter() - t0
    rows: list[Metric] = []
    rec_name = recording_label(recording)
    feet: list[tuple[str, Any, Any, Any]] = [("left", result.left, result.stance_left, recording.truth_left)]
    if result.right is not None:
        feet.append(("right", result.right, result.stance_right, recording.truth_right))
    checks: list[TruthCheck] = []
    for foot, traj, _, truth in feet:  # every truth first: an impossible one scores nothing
        if truth is not None and len(truth.t) > 1:
            checks += check_truth(traj, truth, foot=foot, recording=rec_name, pipeline=name)
    for foot, traj, stance, truth in feet:
        imu = recording.left if foot == "left" else recording.right
        for metric, value, unit in _foot_metrics(traj, stance, truth, imu.rate_hz):
            rows.append(Metric(rec_name, name, foot, metric, float(value), unit))
    if result.right is not None:
        rows.append(
            Metric(
                rec_name,
                name,
                "both",
                "final_separation",
                metrics.final_separation(result.left.position, result.right.position),
                "m",
            )
        )
        rows.append(Metric(rec_name, name, "both", "dtw_distance_feet", _feet_dtw(result.left, result.right), "m"))
    rows.append(Metric(rec_name, name, "both", "runtime", runtime, "s"))
    return EvaluationReport(tuple(rows), {(rec_name, name): result}, checks=tuple(checks))
