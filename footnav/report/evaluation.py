"""The report of an evaluation: per recording, the metrics of every pipeline with the best of
each row marked, and every pipeline's path overlaid on the truth; then the failures, the
warnings and the provenance."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from footnav.analysis import metrics as _metrics
from footnav.analysis.evaluation import trajectory_at
from footnav.data.results import versions
from footnav.report import figures
from footnav.report.page import esc, figure, page, provenance_html, scrub, table, warnings_html
from footnav.report.result import input_hashes, input_places

__all__ = ["best_of_row", "evaluation_html"]

#: Metrics that describe the walk rather than score it: no best among pipelines.
_DESCRIPTIVE = {"path_length", "reference_path_length", "stances", "steps_found"}


def best_of_row(name: str, values: Sequence[float], decimals: int = 3) -> set[int]:
    """Indices of the best values of a metric row, as shown (rounded to ``decimals``): the
    highest for an F1 score, the smallest in size for an error (a signed one too). None marked
    for a descriptive metric, fewer than two values, or when every value ties (nothing is better)."""
    finite = [
        (i, round(abs(v) if not name.endswith("f1") else v, decimals))
        for i, v in enumerate(values)
        if v is not None and math.isfinite(v)
    ]
    if name in _DESCRIPTIVE or len(finite) < 2:
        return set()
    best = max(v for _, v in finite) if name.endswith("f1") else min(v for _, v in finite)
    marked = {i for i, v in finite if v == best}
    return set() if len(marked) == len(finite) else marked


def _metrics_table(report, recording: str, pipelines: list[str]) -> str:
    cells: dict[tuple[str, str, str], dict[str, float]] = {}
    for m in report.metrics:
        if m.recording == recording:
            cells.setdefault((m.name, m.foot, m.unit), {})[m.pipeline] = m.value
    rows, marks = [], {}
    for i, ((name, foot, unit), by_pipe) in enumerate(cells.items()):
        values = [by_pipe.get(p, float("nan")) for p in pipelines]
        for j in best_of_row(name, values):
            marks[(i, 3 + j)] = "best"
        shown = [f"{v:.0f}" if unit == "count" and math.isfinite(v) else v for v in values]
        rows.append([name, foot, unit] + shown)
    return table(("metric", "foot", "unit", *pipelines), rows, cell_class=marks, text_columns=(0, 1, 2))


def _overlay(report, recording: str, rec) -> str | None:
    truths = {}
    for foot in ("left", "right"):
        truth = None if rec is None else getattr(rec, f"truth_{foot}", None)
        if truth is not None and len(truth.t) > 1 and getattr(truth, "frame", None) != "footprints":
            truths[foot] = truth
    if not truths:
        return None
    estimates = []
    for (rname, pname), result in report.results.items():
        if rname != recording:
            continue
        for foot, truth in truths.items():
            traj = getattr(result, foot, None)
            if traj is None:
                continue
            est, inside = trajectory_at(traj, truth.t)
            if len(est) < 2:
                continue
            aligned, _, _ = _metrics.rigid_align(est, truth.position[inside], dims=2)
            estimates.append((pname, foot, np.asarray(aligned)[:, :2]))
    return figures.overlay_svg(truths, estimates) if estimates else None


def evaluation_html(
    report,
    recordings: Sequence[Any] = (),
    *,
    pipelines_toml: Mapping[str, str] | None = None,
    warnings: Sequence[str] = (),
    batch: Mapping[str, Any] | None = None,
) -> str:
    """The report page of an :class:`~footnav.EvaluationReport` as HTML text. ``recordings``
    (by their ``name``) give the truths to draw; ``pipelines_toml`` each pipeline as written."""
    by_name = {getattr(r, "name", None): r for r in recordings}
    pipelines = list(dict.fromkeys([m.pipeline for m in report.metrics] + [f.pipeline for f in report.failures]))
    names = list(dict.fromkeys([m.recording for m in report.metrics] + [f.recording for f in report.failures]))
    metas = [res.meta for res in report.results.values()]
    places = [p for meta in metas for p in input_places(meta)]
    ok = figures.available()
    sections = []
    for i, name in enumerate(names):
        parts = [
            _metrics_table(report, name, pipelines),
            (
                '<p class="muted">★ the best pipeline of each row: the smallest error, the highest F1, as '
                "shown (none when all tie; path lengths and counts describe the walk and have none).</p>"
            ),
        ]
        svg = _overlay(report, name, by_name.get(name)) if ok else None
        if svg is not None or not ok:
            parts.append(
                figure(
                    svg,
                    "Each pipeline's path (solid: left foot, dashed: right) rigidly aligned in 2-D "
                    "onto the truth (wide grey), as the ate_2d metric aligns it.",
                    figures_ok=ok,
                )
            )
        else:
            parts.append('<p class="muted">No path truth to overlay for this recording.</p>')
        failed = [f for f in report.failures if f.recording == name]
        if failed:
            parts.append(
                '<div class="warn"><p>Failed runs:</p><ul>'
                + "".join(f"<li>{esc(scrub(f, places))}</li>" for f in failed)
                + "</ul></div>"
            )
        sections.append((f"rec{i}", f"Recording {scrub(name, places)}", "".join(parts)))
    checks = list(getattr(report, "warnings", ()))
    all_warnings = list(dict.fromkeys([*map(str, warnings), *(str(w) for m in metas for w in m.get("warnings", ()))]))
    body = warnings_html(all_warnings, places)
    if checks:
        body += (
            '<div class="warn"><p>The truth looks suspect here (part of the walk, mirrored, another scale): its '
            "metrics mean less.</p><ul>" + "".join(f"<li>{esc(scrub(c, places))}</li>" for c in checks) + "</ul></div>"
        )
    sections.append(("warnings", "Warnings", body))
    hashes: dict[str, str] = {}
    for meta in metas:
        hashes.update(input_hashes(meta))
    extra = {k: v for k, v in (batch or {}).items() if v is not None}
    prov = provenance_html({}, versions(), hashes, None, extra)
    prov += "".join(f"<h3>Pipeline {esc(p)} (TOML)</h3><pre>{esc(t)}</pre>" for p, t in (pipelines_toml or {}).items())
    sections.append(("provenance", "Provenance", prov))
    subtitle = esc(f"{len(pipelines)} pipeline(s) on {len(names)} recording(s)")
    return page("footnav evaluation", subtitle, sections)
