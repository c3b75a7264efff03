"""The report of one result: plan, height, stances, strides, warnings and self-checks, provenance."""

from __future__ import annotations

from collections.abc import Mapping
from types import SimpleNamespace
from typing import Any

import numpy as np

from footnav.data.results import file_sha256, versions
from footnav.nav.strides import stride_parameters
from footnav.report import figures
from footnav.report.page import checks_html, esc, figure, page, provenance_html, scrub, table, warnings_html

__all__ = ["MAX_TABLE_ROWS", "input_hashes", "input_places", "nothing_final_html", "result_html", "steady_mask"]

#: Stride rows shown per foot at most: the first and last half of them (strides.csv has all).
MAX_TABLE_ROWS = 300
#: A steady stride turns less than this (deg); the definition of PipelineResult.strides' example.
STEADY_TURN_DEG = 20.0
#: Stride columns shown (strides.csv has them all) and their decimals.
_STRIDE_SHOWN = {
    "foot": None,
    "start_s": 2,
    "length_m": 3,
    "cadence_spm": 1,
    "stance_s": 3,
    "swing_s": 3,
    "clearance_m": 3,
    "elevation_m": 3,
    "turn_deg": 1,
    "kind": None,
    "level": None,
}


def steady_mask(strides) -> np.ndarray:
    """Steady strides: not a walk's first or last, no standstill, turning under 20 deg, level.

    ``strides``: a stride table, :data:`~footnav.nav.strides.STRIDE_DTYPE` rows or the DataFrame
    of :meth:`~footnav.pipeline.result.PipelineResult.strides`; None or empty gives an empty mask.
    """
    if strides is None or len(strides) == 0:
        return np.zeros(0, dtype=bool)
    col = {c: np.asarray(strides[c]) for c in ("first", "last", "standstill", "turn_deg", "kind")}
    return (
        ~col["first"].astype(bool)
        & ~col["last"].astype(bool)
        & ~col["standstill"].astype(bool)
        & (np.abs(col["turn_deg"]) < STEADY_TURN_DEG)
        & (col["kind"] == "level")
    )


def input_places(meta: Mapping[str, Any]) -> list[str]:
    """The input files' paths as the run named them, for :func:`~footnav.report.page.scrub`."""
    out = []
    for m in (meta.get("input") or {}).values():
        src = (m or {}).get("source")
        if isinstance(src, str) and src:
            out.append(src)
            out.append(src.rsplit(" (", 1)[0])
    return out


def input_hashes(meta: Mapping[str, Any]) -> dict[str, str]:
    """SHA-256 of each input file that exists, by its path (the page shows the name only)."""
    out = {}
    for src in input_places(meta):
        try:
            out.setdefault(src, file_sha256(src))
        except OSError:
            continue
    return out


def _feet(result) -> list[tuple[str, Any, Any]]:
    feet = [("left", result.left, result.stance_left)]
    if result.right is not None and result.stance_right is not None:
        feet.append(("right", result.right, result.stance_right))
    return feet


def _truths(feet, recording) -> dict[str, Any]:
    """Each foot's path truth, rigidly aligned in 2-D onto its estimate (the estimate is drawn as
    computed; the truth's own frame is another)."""
    out = {}
    for foot, traj, _ in feet:
        truth = None if recording is None else getattr(recording, f"truth_{foot}", None)
        if truth is None or len(truth.t) < 2 or getattr(truth, "frame", None) == "footprints":
            continue
        # here, not at the top: a run without truth (most) never loads analysis and scipy.optimize
        from footnav.analysis.evaluation import trajectory_at
        from footnav.analysis.metrics import rigid_align

        est, inside = trajectory_at(traj, truth.t)
        if len(est) < 2:
            continue
        aligned, _, _ = rigid_align(truth.position[inside], est, dims=2)
        out[foot] = SimpleNamespace(t=np.asarray(truth.t)[inside], position=np.asarray(aligned))
    return out


def _stance_rows(result, recording) -> list[tuple[str, np.ndarray, np.ndarray, np.ndarray, str]]:
    rows = []
    for foot, traj, stance in _feet(result):
        imu = None if recording is None else getattr(recording, foot, None)
        if imu is not None and imu.n_samples == len(stance.mask):
            rows.append(
                (foot, np.asarray(imu.t), np.linalg.norm(imu.gyr, axis=1), np.asarray(stance.mask), "gyroscope")
            )
        elif len(traj.t) == len(stance.mask):
            rate = figures.angular_rate_norm(traj.t, traj.quaternion)
            rows.append((foot, np.asarray(traj.t), rate, np.asarray(stance.mask), "from the estimated orientation"))
    return rows


def _strides_section(strides) -> str:
    if strides is None or len(strides) == 0:
        return '<p class="muted">No complete stride.</p>'
    steady = steady_mask(strides)
    parts = []
    summary_rows = []
    for foot in dict.fromkeys(strides["foot"]):
        sel = np.asarray(strides["foot"] == foot)
        s = strides[sel & steady]
        summary_rows.append(
            (
                foot,
                int(sel.sum()),
                len(s),
                float(s["length_m"].mean()) if len(s) else float("nan"),
                float(s["cadence_spm"].mean()) if len(s) else float("nan"),
                float(s["stance_s"].mean()) if len(s) else float("nan"),
                float(s["clearance_m"].mean()) if len(s) else float("nan"),
            )
        )
    parts.append(
        table(("foot", "strides", "steady", "length (m)", "cadence", "stance (s)", "clearance (m)"), summary_rows)
    )
    parts.append(
        '<p class="muted">Cadence in steps per minute. Steady strides (shaded green, mean above): '
        "not the first or last of a walk, "
        f"no standstill, turning less than {STEADY_TURN_DEG:g}°, level (not on stairs).</p>"
    )
    rows, classes = [], []
    for foot in dict.fromkeys(strides["foot"]):
        idx = np.flatnonzero(np.asarray(strides["foot"] == foot))
        shown = (
            idx
            if len(idx) <= MAX_TABLE_ROWS
            else np.concatenate([idx[: MAX_TABLE_ROWS // 2], idx[-MAX_TABLE_ROWS // 2 :]])
        )
        if len(shown) < len(idx):
            parts.append(
                f'<p class="muted">{esc(foot)}: the first and last {MAX_TABLE_ROWS // 2} of {len(idx)} strides '
                "shown; strides.csv holds them all.</p>"
            )
        for i in shown:
            r = strides[int(i)]
            rows.append(
                [r[c] if d is None else f"{round(r[c], d) + 0.0:.{d}f}" for c, d in _STRIDE_SHOWN.items()]
                + ["✓" if steady[i] else ""]
            )
            classes.append("steady" if steady[i] else "")
    header = (
        "foot",
        "start (s)",
        "length (m)",
        "cadence",
        "stance (s)",
        "swing (s)",
        "clearance (m)",
        "rise (m)",
        "turn (°)",
        "kind",
        "floor",
        "steady",
    )
    parts.append(table(header, rows, row_class=classes, text_columns=(0, 9)))
    return "".join(parts)


def result_html(
    result, *, recording=None, pipeline_toml: str | None = None, summary: Mapping[str, Any] | None = None
) -> str:
    """The report page of ``result`` as HTML text (see :func:`footnav.report.write_html`)."""
    meta = result.meta
    places = input_places(meta)
    feet = _feet(result)
    truths = _truths(feet, recording)
    try:
        # the table itself, not result.strides()'s DataFrame: writing a report never loads pandas
        strides = np.concatenate([stride_parameters(traj, st, foot=foot) for foot, traj, st in feet])
    except (ValueError, KeyError):
        strides = None
    ok = figures.available()
    names = sorted({scrub(p, places) for p in places if " (" not in p}) or ["a stream"]
    name = getattr(recording, "name", None) or ", ".join(names)
    pipe = " + ".join(c.get("name", k) for k, c in (meta.get("pipeline") or {}).items())
    duration = float(result.left.t[-1] - result.left.t[0]) if len(result.left.t) else 0.0
    subtitle = esc(f"{len(feet)} foot" if len(feet) == 1 else "both feet") + esc(
        f" · {duration / 60:.1f} min · pipeline {pipe}" + (" · with truth" if truths else "")
    )

    vertical = {foot: traj.meta.get("vertical") for foot, traj, _ in feet if traj.meta.get("vertical")}
    lengths = ", ".join(f"{foot} {traj.path_length_m:.1f} m, {st.n_stances} stances" for foot, traj, st in feet)
    plan = figure(
        figures.plan_svg(feet, result.path, truths) if ok else None,
        f"Plan view (nav frame, x along the first steps). Lines: each foot; circles: footprints (mid-stance); "
        "dashed: the fused path; big circle start, square end"
        f"{'; wide pale lines: truth, rigidly aligned in 2-D onto each foot' if truths else ''}. "
        f"{esc(lengths)}.",
        figures_ok=ok,
    )
    floors = "; ".join(
        f"{foot}: climb {abs(v.get('climb_m', 0)):.2f} m, descent {abs(v.get('descent_m', 0)):.2f} m, "
        f"floors up {v.get('floors_up', 0)}, "
        f"down {v.get('floors_down', 0)}"
        for foot, v in vertical.items()
    )
    height = figure(
        figures.height_svg(feet, strides, truths) if ok else None,
        "Height over time" + (f" ({esc(floors)})" if floors else "") + ". Thin line: each foot's height (a "
        "long walk's as a band per stride, from its lowest to its highest); thick: its footprints' heights; orange "
        "bands: stair strides; dotted: the floor of each stride (when the walk changes floors).",
        figures_ok=ok,
    )
    rows = _stance_rows(result, recording)
    window = figures.stance_window(rows[0][1]) if rows else (0.0, 0.0)
    stance = figure(
        figures.stance_svg(rows, window) if ok and rows else None,
        f"Angular rate norm from {window[0]:.1f} to {window[1]:.1f} s (the middle of the walk) with the "
        "samples the detector called stance (green): a stance should sit in every quiet trough.",
        figures_ok=ok,
    )
    if ok and not rows:
        stance = '<p class="muted">No per-sample stance to show.</p>'
    warnings = list(meta.get("warnings") or [])
    extra = {k: scrub(v, places) for k, v in (summary or {}).items() if k in ("complete", "ended_by")}
    hashes = input_hashes(meta)
    sections = [
        ("plan", "Plan", plan),
        ("height", "Height", height),
        ("stances", "Stances", stance),
        ("strides", "Strides", _strides_section(strides)),
        ("checks", "Warnings and self-checks", warnings_html(warnings, places) + checks_html(meta)),
        ("provenance", "Provenance", provenance_html(meta, versions(), hashes, pipeline_toml, extra)),
    ]
    return page(f"footnav: {name}", subtitle, sections)


def nothing_final_html(summary: Mapping[str, Any], warnings: list[str], pipeline_toml: str | None = None) -> str:
    """The page of a stream that ended before any sample was final (``footnav follow``): why it
    ended, its warnings and the provenance; nothing to draw."""
    why = esc(scrub(summary.get("ended_by", "")))
    body = (
        f'<p class="warn">The stream ended before any step was final ({why}): there is no walk to show. '
        "A step is final a few seconds after its stance; feed a longer recording, or wait longer with "
        "<code>--idle-s</code>.</p>"
    )
    sections = [
        ("checks", "Warnings and self-checks", body + warnings_html(warnings, ())),
        (
            "provenance",
            "Provenance",
            provenance_html({}, versions(), {}, pipeline_toml, {k: scrub(v) for k, v in summary.items()}),
        ),
    ]
    return page("footnav: nothing final", "a stream that ended before any step was final", sections)
