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

__all__ = ["plot_trajectories"]


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
