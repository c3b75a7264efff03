"""The evaluation harness: run a pipeline on a recording and measure it against the recording's truth.

Every accuracy figure footnav reports comes from :func:`evaluate`. It computes each metric the
recording supports (see :mod:`footnav.core.metrics` for the definitions):

* per foot: path length; with reference positions, the 2-D and 3-D absolute trajectory error
  after rigid alignment (``ate_2d_m``, ``ate_3d_m``); for closed walks, the loop-closure error;
  with reference stance, per-sample F1 and steps found / missed / false;
* per foot, with footprint truth (``FootTruth.frame == "footprints"``, the gait-driven set):
  ``footprint_rmse`` and ``footprint_final_error`` (m) after one rigid 2-D fit, instead of the
  ATE rows (which would compare the same points again, and 3-D against footprints at z = 0);
* per foot, with labelled swings inside trial boundaries (the IPOL set, ``meta["labelled"]``):
  ``step_f1``, ``steps_found`` / ``steps_missed`` / ``steps_false`` and a per-sample
  ``stance_f1``, all computed inside the labelled span only (outside it the truth says nothing);
* both feet: the final foot separation E_s (seed 001 eq. 8);
* the runtime of the pipeline.
"""

from __future__ import annotations

import csv
import io
import time
from dataclasses import dataclass, field
from typing import Any, Iterable

import numpy as np

from footnav.core import metrics
from footnav.core.pipeline import Pipeline
from footnav.core.types import FootTrajectory, FootTruth, PipelineResult, Recording, StanceResult

__all__ = ["Metric", "EvaluationReport", "evaluate", "trajectory_at"]


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
class EvaluationReport:
    """The metrics of one or more (pipeline, recording) runs, and the runs' results."""

    metrics: tuple[Metric, ...]
    results: dict[tuple[str, str], PipelineResult] = field(default_factory=dict, compare=False)

    def value(self, name: str, foot: str = "left", recording: str | None = None, pipeline: str | None = None) -> float:
        """The value of one metric (the first match)."""
        for m in self.metrics:
            if (
                m.name == name
                and m.foot == foot
                and (recording is None or m.recording == recording)
                and (pipeline is None or m.pipeline == pipeline)
            ):
                return m.value
        raise KeyError(f"no metric {name!r} for foot {foot!r}")

    def __add__(self, other: "EvaluationReport") -> "EvaluationReport":
        return EvaluationReport(self.metrics + other.metrics, {**self.results, **other.results})

    def rows(self) -> list[dict[str, Any]]:
        return [m.__dict__.copy() for m in self.metrics]

    def to_csv(self) -> str:
        buf = io.StringIO()
        writer = csv.DictWriter(buf, fieldnames=["recording", "pipeline", "foot", "name", "value", "unit"])
        writer.writeheader()
        writer.writerows(self.rows())
        return buf.getvalue()

    def to_text(self) -> str:
        """A table: one row per (recording, metric, foot), one column per pipeline."""
        pipelines = list(dict.fromkeys(m.pipeline for m in self.metrics))
        keys = list(dict.fromkeys((m.recording, m.name, m.foot, m.unit) for m in self.metrics))
        table = {(m.recording, m.name, m.foot, m.unit, m.pipeline): m.value for m in self.metrics}
        header = ["recording", "metric", "foot", "unit"] + pipelines
        rows = [list(k) + [_fmt(table.get(k + (p,))) for p in pipelines] for k in keys]
        widths = [max(len(str(r[i])) for r in [header] + rows) for i in range(len(header))]
        out = ["  ".join(str(c).ljust(w) for c, w in zip(header, widths)).rstrip()]
        out.append("  ".join("-" * w for w in widths))
        out += ["  ".join(str(c).ljust(w) for c, w in zip(r, widths)).rstrip() for r in rows]
        return "\n".join(out)


def _fmt(value: float | None) -> str:
    if value is None:
        return ""
    if float(value).is_integer() and abs(value) < 1e6:
        return str(int(value))
    return f"{value:.3f}"


def trajectory_at(traj: FootTrajectory, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Estimated positions linearly interpolated at times ``t`` within the estimate's span, and the
    boolean mask of the ``t`` that fall inside it."""
    inside = (t >= traj.t[0]) & (t <= traj.t[-1])
    tt = t[inside]
    pos = np.stack([np.interp(tt, traj.t, traj.position[:, i]) for i in range(3)], axis=1)
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
        out.append(("reference_path_length", metrics.travelled_distance(ref, dims=2), "m"))
    if truth.closed_loop:
        loop = metrics.loop_closure_error(traj.position, dims=2)
        out.append(("loop_closure", float(loop.error_m), "m"))
        out.append(("loop_closure_percent", float(loop.error_percent), "%"))
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
    """
    name = pipeline_name or "+".join(c.name for c in pipeline.components)
    t0 = time.perf_counter()
    result = pipeline.run(recording.left, recording.right)
    runtime = time.perf_counter() - t0
    rows: list[Metric] = []
    rec_name = recording.name or str(recording.meta.get("source", "recording"))
    feet: Iterable[tuple[str, Any, Any, Any]] = [("left", result.left, result.stance_left, recording.truth_left)]
    if result.right is not None:
        feet = list(feet) + [("right", result.right, result.stance_right, recording.truth_right)]
    for foot, traj, stance, truth in feet:
        imu = recording.left if foot == "left" else recording.right
        for metric, value, unit in _foot_metrics(traj, stance, truth, imu.rate_hz):
            rows.append(Metric(rec_name, name, foot, metric, float(value), unit))
    if result.right is not None:
        rows.append(
            Metric(rec_name, name, "both", "final_separation", metrics.final_separation(result.left.position, result.right.position), "m")
        )
    rows.append(Metric(rec_name, name, "both", "runtime", runtime, "s"))
    return EvaluationReport(tuple(rows), {(rec_name, name): result})

