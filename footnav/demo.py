"""``footnav demo``: the default pipeline on the bundled real recording, measured against its truth.

The recording is azure_fgo (MIT, Azurehappen/Constrained-ZUPT-FGO; licence in
``footnav/data/azure_fgo/``): both feet, 60 Hz, 120 s of walking back and forth, with per-sample
position truth for each foot.
"""

from __future__ import annotations

import logging
from contextlib import ExitStack
from dataclasses import dataclass
from importlib import resources
from pathlib import Path as FilePath

from footnav.analysis.evaluation import EvaluationReport, evaluate
from footnav.core.types import Recording
from footnav.data.output import OutputClaim, claim_output, is_footnav_figure
from footnav.pipeline.factory import make_pipeline

__all__ = ["demo_recording", "run_demo", "DemoReport", "REFERENCE_ATE_2D_M"]

log = logging.getLogger(__name__)

#: gaitmap 2.6 RtsKalman with defaults, each foot alone, 2-D rigidly aligned RMSE (shared/data/README.md).
REFERENCE_ATE_2D_M = {"left": 0.36, "right": 0.76}


def demo_recording() -> Recording:
    """The bundled azure_fgo recording with its truth (z up)."""
    from footnav.data.io import read_azure_fgo

    folder = resources.files("footnav") / "data" / "azure_fgo"
    with resources.as_file(folder) as path:
        return read_azure_fgo(FilePath(path))


@dataclass(frozen=True)
class DemoReport:
    """What :func:`run_demo` gives: the evaluation, its printed table and the figure's path (or None)."""

    report: EvaluationReport
    text: str
    figure: str | None


def run_demo(plot: str | None = "footnav-demo.png") -> DemoReport:
    """Run the default pipeline on the bundled recording; print-ready table and optional figure.

    The figure replaces an earlier demo figure but never a file footnav did not write
    (:func:`footnav.data.output.claim_output`); it is claimed before the run.
    """
    with ExitStack() as claims:
        claim = None
        if plot:
            try:
                import matplotlib  # noqa: F401
            except ImportError:
                claim = "no matplotlib"
            else:
                claim = claims.enter_context(
                    claim_output(plot, kind="file", force=True, signature=is_footnav_figure, what="figure")
                )
        return _run_demo(claim, plot)


def _run_demo(claim: OutputClaim | str | None, plot: str | None) -> DemoReport:
    rec = demo_recording()
    pipeline = make_pipeline()
    report = evaluate(pipeline, rec, pipeline_name="default")
    rows = []
    for foot in ("left", "right"):
        rows.append(
            (
                foot,
                f"{report.value('path_length', foot):.1f}",
                f"{report.value('reference_path_length', foot):.1f}",
                f"{report.value('ate_2d', foot):.3f}",
                f"{REFERENCE_ATE_2D_M[foot]:.2f}",
            )
        )
    header = ("foot", "path length (m)", "truth length (m)", "2-D RMSE (m)", "gaitmap RtsKalman (m)")
    widths = [max(len(h), *(len(r[i]) for r in rows)) for i, h in enumerate(header)]
    lines = [
        f"footnav demo: {pipeline!r}",
        f"recording: azure_fgo, both feet, {rec.left.rate_hz:.0f} Hz, {rec.left.duration_s:.0f} s "
        "(MIT, Azurehappen/Constrained-ZUPT-FGO)",
        "",
        "  ".join(h.ljust(w) for h, w in zip(header, widths)),
        "  ".join("-" * w for w in widths),
        *("  ".join(c.ljust(w) for c, w in zip(r, widths)) for r in rows),
        "",
        f"final foot separation E_s: {report.value('final_separation', 'both'):.3f} m",
        f"runtime: {report.value('runtime', 'both'):.2f} s (includes numba compilation on the first run)",
    ]
    figure = None
    if claim == "no matplotlib":
        lines.append("(install the 'plot' extra for a trajectory figure)")
    elif isinstance(claim, OutputClaim):
        from footnav.analysis.plot import plot_trajectories

        with claim.staged() as staged:
            plot_trajectories(report.results[(rec.name, "default")], rec, staged)
        figure = str(plot)
        lines.append(f"figure: {figure}")
    return DemoReport(report=report, text="\n".join(lines), figure=figure)
