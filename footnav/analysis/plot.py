"""Figures (needs the ``plot`` extra: matplotlib).

Importing this module raises ImportError when matplotlib is not installed.
"""

from __future__ import annotations

from pathlib import Path as FilePath

import matplotlib

matplotlib.use("Agg")  # files only: footnav never opens windows
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from footnav.analysis import metrics  # noqa: E402
from footnav.analysis.evaluation import trajectory_at  # noqa: E402
from footnav.core.types import Recording  # noqa: E402
from footnav.pipeline.result import PipelineResult  # noqa: E402

__all__ = ["plot_trajectories", "plot_stance_comparison", "plot_position_errors", "plot_steps", "has_path_truth"]


def _save(fig, path: FilePath, dpi: int) -> None:
    """Save and close; a PNG names footnav as its software, so that ``--force`` may replace it
    (:func:`footnav.data.output.is_footnav_figure`)."""
    from footnav._version import __version__
    from footnav.data.output import FIGURE_SOFTWARE

    png = FilePath(path).suffix.lower() == ".png"
    fig.savefig(path, dpi=dpi, metadata={"Software": f"{FIGURE_SOFTWARE} {__version__}"} if png else None)
    plt.close(fig)


def _recording_name(result: PipelineResult, recording: Recording | None) -> str:
    """What a title calls the recording: its name, else its (left) input file's name, else ""."""
    if recording is not None and recording.name:
        return str(recording.name)
    for meta in (result.meta.get("input") or {}).values():
        source = (meta or {}).get("source")
        if isinstance(source, str) and source:
            return FilePath(source).name
    return ""


def _path_truth(recording: Recording | None, foot: str):
    """The foot's truth when it is a path (not footprints) with at least two points, else None."""
    truth = None if recording is None else getattr(recording, f"truth_{foot}")
    return truth if truth is not None and len(truth.t) > 1 and truth.frame != "footprints" else None


def has_path_truth(recording: Recording | None) -> bool:
    """Whether :func:`plot_position_errors` has an error curve to draw for ``recording``."""
    return any(_path_truth(recording, foot) is not None for foot in ("left", "right"))


#: Legends go below their axes, outside the data.
_LEGEND_BELOW = {"loc": "upper center", "bbox_to_anchor": (0.5, -0.1), "fontsize": "small"}


def plot_trajectories(result: PipelineResult, recording: Recording | None, path: str | FilePath) -> FilePath:
    """Top view of each foot's estimate, rigidly aligned (2-D) onto its truth when there is one,
    and beside it each foot's height over time.

    Each estimate's start is marked with a circle and its end with a square; with a truth, the
    legend gives each foot's 2-D ATE (RMSE after the alignment) and its end error (after aligning
    the start only, :func:`footnav.analysis.metrics.align_at_start`), the figures the demo prints.
    The height panel shows the truth's height from the estimate's start height when there is one,
    and in its legend each foot's climb, descent and floors changed (``meta["vertical"]``).
    Writes a PNG to ``path`` and returns it.
    """
    fig, (ax, ax_z) = plt.subplots(1, 2, figsize=(13, 6), width_ratios=(3, 2), constrained_layout=True)
    feet = [("left", result.left, "tab:blue"), ("right", result.right, "tab:red")]
    _height_panel(ax_z, feet, recording)
    for foot, traj, color in feet:
        if traj is None:
            continue
        truth = _path_truth(recording, foot)
        if truth is not None:
            est, inside = trajectory_at(traj, truth.t)
            ref = truth.position[inside]
            aligned, _, _ = metrics.rigid_align(est, ref, dims=2)
            ate = metrics.ate_rmse(est, ref, dims=2)
            end = metrics.end_to_end_error(metrics.align_at_start(est, ref).aligned, ref, dims=2).error_m
            ax.plot(truth.position[:, 0], truth.position[:, 1], color=color, lw=3, alpha=0.25, label=f"{foot} truth")
            shown = aligned
            label = f"{foot} estimate (aligned): ATE {ate:.2f} m, end error {end:.2f} m"
        else:
            shown = traj.position
            label = f"{foot} estimate"
        ax.plot(shown[:, 0], shown[:, 1], color=color, lw=1, label=label)
        ax.plot(*shown[0, :2], "o", color=color, ms=7, mfc="white", label=f"{foot} start")
        ax.plot(*shown[-1, :2], "s", color=color, ms=7, label=f"{foot} end")
    if result.right is not None and not (recording is not None and recording.truth_left is not None):
        # the pedestrian (the fusion's path) in the estimate's own frame
        ax.plot(
            result.path.position[:, 0], result.path.position[:, 1], color="0.2", lw=1, ls="--", label="pedestrian path"
        )
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    name = _recording_name(result, recording)
    components = " + ".join(c.get("name", kind) for kind, c in result.meta["pipeline"].items())
    ax.set_title(f"footnav {name}: {components}" if name else f"footnav: {components}")
    ax.legend(ncol=2, **_LEGEND_BELOW)  # below the plan, as the height panel's: never over the path
    ax.grid(True, alpha=0.3)
    path = FilePath(path)
    _save(fig, path, 120)
    return path


def _height_panel(ax, feet, recording: Recording | None) -> None:
    """Each foot's height (m) over time (s), its truth's from the same start height."""
    for foot, traj, color in feet:
        if traj is None:
            continue
        truth = _path_truth(recording, foot)
        if truth is not None:
            z0 = float(np.interp(truth.t[0], traj.t, traj.position[:, 2]))
            ax.plot(
                truth.t,
                truth.position[:, 2] - truth.position[0, 2] + z0,
                color=color,
                lw=3,
                alpha=0.25,
                label=f"{foot} truth",
            )
        vertical = traj.meta.get("vertical")
        label = f"{foot} estimate"
        if vertical:
            label += (
                f": climb {vertical['climb_m']:.2f} m, descent {vertical['descent_m']:.2f} m, "
                f"floors up {vertical['floors_up']}, down {vertical['floors_down']}"
            )
        ax.plot(traj.t, traj.position[:, 2], color=color, lw=1, label=label)
    ax.set_xlabel("time (s)")
    ax.set_ylabel("height z (m)")
    ax.set_title("height")
    ax.legend(**_LEGEND_BELOW)  # below: never over the data
    ax.grid(True, alpha=0.3)


def plot_steps(steps, path: str | FilePath, *, title: str = "") -> FilePath:
    """Top view of the footprints of closed steps (online mode's ``ClosedStep``: ``foot``,
    ``position`` in m, nav frame), one line per foot, the newest footprint of each foot marked
    with a square. What ``footnav follow --plot`` redraws while a walk goes on.
    """
    fig, ax = plt.subplots(figsize=(7, 5.5), constrained_layout=True)
    for foot, color in (("left", "tab:blue"), ("right", "tab:red")):
        xy = np.array([s.position[:2] for s in steps if s.foot == foot]).reshape(-1, 2)
        if len(xy) == 0:
            continue
        ax.plot(xy[:, 0], xy[:, 1], ".-", color=color, lw=1, ms=5, label=f"{foot}: {len(xy)} steps")
        ax.plot(*xy[-1], "s", color=color, ms=8)
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_title(title or "footnav: closed steps")
    if steps:
        ax.legend(loc="best", fontsize="small")
    ax.grid(True, alpha=0.3)
    path = FilePath(path)
    _save(fig, path, 100)
    return path


def plot_stance_comparison(comparison, path: str | FilePath, *, seconds: tuple[float, float] | None = None) -> FilePath:
    """Each foot's angular-rate norm with every detector's stance (and the reference) stacked below.

    ``comparison`` is a :class:`~footnav.analysis.comparison.DetectorComparison`; ``seconds`` limits
    the time axis to ``(start, stop)``. Writes a PNG to ``path`` and returns it.
    """
    rec = comparison.recording
    labels = list(comparison.stances)
    feet = [("left", rec.left, rec.truth_left, 0)] + (
        [("right", rec.right, rec.truth_right, 1)] if rec.right is not None else []
    )
    # one signal row per foot, then one band per detector (and the reference stance when known)
    rows: list[tuple] = []
    for foot, imu, truth, col in feet:
        rows.append(("signal", foot, imu, truth))
        rows += [("band", lab, imu, comparison.stances[lab][col].mask) for lab in labels]
        if truth is not None and truth.stance is not None and len(truth.stance) == imu.n_samples:
            rows.append(("band", "reference", imu, truth.stance))
    ratios = [3 if r[0] == "signal" else 1 for r in rows]
    fig, axes = plt.subplots(
        len(rows),
        1,
        sharex=True,
        figsize=(11, 1.0 + 0.5 * len(rows) + 1.2 * len(feet)),
        gridspec_kw={"height_ratios": ratios},
        constrained_layout=True,
    )
    axes = np.atleast_1d(axes)
    for ax, (kind, name, imu, data) in zip(axes, rows):
        if kind == "signal":
            ax.plot(imu.t, np.linalg.norm(imu.gyr, axis=1), color="0.2", lw=0.7)
            ax.set_ylabel(f"{name}\n|w| (rad/s)")
            if data is not None and data.stance is None and len(data.events.get("mid_stance", ())):
                ax.vlines(
                    imu.t[data.events["mid_stance"]],
                    0,
                    1,
                    transform=ax.get_xaxis_transform(),
                    color="tab:green",
                    lw=0.8,
                    alpha=0.6,
                    label="reference mid-stance",
                )
                ax.legend(loc="upper right", fontsize="x-small")
        else:
            ax.fill_between(
                imu.t, 0, 1, where=data, step="mid", color="tab:green" if name == "reference" else "tab:blue", lw=0
            )
            ax.set_yticks([])
            ax.set_ylim(0, 1)
            ax.set_ylabel(name, rotation=0, ha="right", va="center", fontsize="small")
    axes[-1].set_xlabel("t (s)")
    if seconds is not None:
        axes[-1].set_xlim(*seconds)
    fig.suptitle(f"stance per detector: {rec.name or 'recording'}")
    path = FilePath(path)
    _save(fig, path, 110)
    return path


def plot_position_errors(result: PipelineResult, recording: Recording, path: str | FilePath) -> FilePath | None:
    """Horizontal position error of each foot against its truth over time, after the same 2-D rigid
    alignment as the ``ate_2d`` metric, with the stance phases shaded. Writes a PNG, returns it;
    without a path truth for either foot (:func:`has_path_truth`) there is no error to draw, and
    nothing is written (None)."""
    if not has_path_truth(recording):
        return None
    fig, ax = plt.subplots(figsize=(10, 4.6), constrained_layout=True)
    for foot, color in (("left", "tab:blue"), ("right", "tab:red")):
        traj, truth = getattr(result, foot), _path_truth(recording, foot)
        if traj is None or truth is None:
            continue
        est, inside = trajectory_at(traj, truth.t)
        aligned, _, _ = metrics.rigid_align(est, truth.position[inside], dims=2)
        err = np.linalg.norm(aligned[:, :2] - truth.position[inside, :2], axis=1)
        ax.plot(truth.t[inside], err, color=color, lw=1, label=f"{foot} (RMSE {np.sqrt(np.mean(err**2)):.3f} m)")
    stance = result.stance_left
    t_left = result.left.t
    ax.fill_between(
        t_left,
        0,
        1,
        where=stance.mask,
        transform=ax.get_xaxis_transform(),
        color="0.85",
        lw=0,
        step="mid",
        label="left stance",
    )
    ax.set_xlabel("t (s)")
    ax.set_ylabel("horizontal error (m)")
    ax.legend(ncol=3, **{**_LEGEND_BELOW, "bbox_to_anchor": (0.5, -0.16)})  # below the x label
    ax.grid(True, alpha=0.3)
    name = _recording_name(result, recording)
    ax.set_title(f"position error: {name}" if name else "position error")
    path = FilePath(path)
    _save(fig, path, 110)
    return path
