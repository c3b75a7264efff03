"""Figures (needs the ``plot`` extra: matplotlib).

Importing this module raises ImportError when matplotlib is not installed.
"""

from __future__ import annotations

from pathlib import Path as FilePath

import matplotlib

matplotlib.use("Agg")  # files only: footnav never opens windows
import matplotlib.pyplot as plt  # noqa: E402

from footnav.core import metrics  # noqa: E402
from footnav.core.evaluation import trajectory_at  # noqa: E402
from footnav.core.types import PipelineResult, Recording  # noqa: E402

import numpy as np  # noqa: E402

__all__ = ["plot_trajectories", "plot_stance_comparison"]


def plot_trajectories(result: PipelineResult, recording: Recording | None, path: str | FilePath) -> FilePath:
    """Top view of each foot's estimate, rigidly aligned (2-D) onto its truth when there is one.

    Writes a PNG to ``path`` and returns it.
    """
    fig, ax = plt.subplots(figsize=(8, 6), constrained_layout=True)
    feet = [("left", result.left, "tab:blue"), ("right", result.right, "tab:red")]
    for foot, traj, color in feet:
        if traj is None:
            continue
        truth = None if recording is None else getattr(recording, f"truth_{foot}")
        if truth is not None and len(truth.t) > 1:
            est, inside = trajectory_at(traj, truth.t)
            aligned, _, _ = metrics.rigid_align(est, truth.position[inside], dims=2)
            ax.plot(truth.position[:, 0], truth.position[:, 1], color=color, lw=3, alpha=0.25, label=f"{foot} truth")
            ax.plot(aligned[:, 0], aligned[:, 1], color=color, lw=1, label=f"{foot} estimate (aligned)")
        else:
            ax.plot(traj.position[:, 0], traj.position[:, 1], color=color, lw=1, label=f"{foot} estimate")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    name = "" if recording is None else recording.name
    ax.set_title(f"footnav {name}: " + " + ".join(c["name"] for c in result.meta["pipeline"].values()))
    ax.legend(loc="best", fontsize="small")
    ax.grid(True, alpha=0.3)
    path = FilePath(path)
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def plot_stance_comparison(comparison, path: str | FilePath, *, seconds: tuple[float, float] | None = None) -> FilePath:
    """Each foot's angular-rate norm with every detector's stance (and the reference) stacked below.

    ``comparison`` is a :class:`~footnav.core.comparison.DetectorComparison`; ``seconds`` limits
    the time axis to ``(start, stop)``. Writes a PNG to ``path`` and returns it.
    """
    rec = comparison.recording
    labels = list(comparison.stances)
    feet = [("left", rec.left, rec.truth_left, 0)] + ([("right", rec.right, rec.truth_right, 1)] if rec.right is not None else [])
    rows_per_foot = 1 + len(labels) + 1
    ratios = ([3] + [1] * (rows_per_foot - 1)) * len(feet)
    fig, axes = plt.subplots(
        len(ratios), 1, sharex=True, figsize=(11, 1.2 + 0.45 * len(ratios) + 1.5 * len(feet)),
        gridspec_kw={"height_ratios": ratios}, constrained_layout=True,
    )
    axes = np.atleast_1d(axes)
    for f, (foot, imu, truth, col) in enumerate(feet):
        base = f * rows_per_foot
        ax = axes[base]
        ax.plot(imu.t, np.linalg.norm(imu.gyr, axis=1), color="0.2", lw=0.7)
        ax.set_ylabel(f"{foot}\n|w| (rad/s)")
        bands = [(lab, comparison.stances[lab][col].mask) for lab in labels]
        if truth is not None and truth.stance is not None and len(truth.stance) == imu.n_samples:
            bands.append(("reference", truth.stance))
        elif truth is not None and len(truth.events.get("mid_stance", ())):
            ax.vlines(imu.t[truth.events["mid_stance"]], 0, 1, transform=ax.get_xaxis_transform(), color="tab:green",
                      lw=0.8, alpha=0.6, label="reference mid-stance")
            ax.legend(loc="upper right", fontsize="x-small")
        for i, (lab, mask) in enumerate(bands):
            b = axes[base + 1 + i]
            b.fill_between(imu.t, 0, 1, where=mask, step="mid", color="tab:green" if lab == "reference" else "tab:blue", lw=0)
            b.set_yticks([])
            b.set_ylabel(lab, rotation=0, ha="right", va="center", fontsize="small")
            b.set_ylim(0, 1)
        for j in range(len(bands) + 1, rows_per_foot):
            axes[base + j].set_visible(False)
    axes[-1].set_xlabel("t (s)")
    if seconds is not None:
        axes[-1].set_xlim(*seconds)
    fig.suptitle(f"stance per detector: {rec.name or 'recording'}")
    path = FilePath(path)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path
