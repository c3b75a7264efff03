"""Writing a pipeline's result to a folder that lasts: trajectories as CSV, summary and provenance
as JSON, the exact pipeline as TOML.

The folder is written under a temporary name beside its target and renamed at the end, so an
interrupted run never leaves a half-written result; an existing non-empty folder is replaced only
with ``force=True``.
"""

from __future__ import annotations

import json
import os
import shutil
import tempfile
from pathlib import Path as FilePath
from typing import Any, Mapping

import numpy as np

from footnav.core.errors import InvalidInputError
from footnav.core.types import FootTrajectory, Path, PipelineResult

__all__ = ["write_results", "TRAJECTORY_COLUMNS"]

TRAJECTORY_COLUMNS = (
    "t_s,pos_x_m,pos_y_m,pos_z_m,vel_x_mps,vel_y_mps,vel_z_mps,"
    "q_w,q_x,q_y,q_z,pos_std_x_m,pos_std_y_m,pos_std_z_m,stance"
)


def _write_trajectory(traj: FootTrajectory, stance_mask, path: FilePath) -> None:
    data = np.column_stack(
        [traj.t, traj.position, traj.velocity, traj.quaternion, traj.position_std, np.asarray(stance_mask, dtype=float)]
    )
    np.savetxt(path, data, delimiter=",", header=f"frame: nav (z up)\n{TRAJECTORY_COLUMNS}", fmt="%.9g")


def _jsonable(value: Any) -> Any:
    if isinstance(value, Mapping):
        return {str(k): _jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_jsonable(v) for v in value]
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, float) and not np.isfinite(value):
        return None
    return value


def write_results(
    result: PipelineResult,
    folder: str | os.PathLike,
    *,
    force: bool = False,
    summary: Mapping[str, Any] | None = None,
    pipeline_toml: str | None = None,
) -> FilePath:
    """Write ``result`` into ``folder``: ``left.csv`` (``right.csv``), ``path.csv``, ``summary.json``
    (``summary`` plus provenance: pipeline, version, warnings, inputs) and ``pipeline.toml``.

    Raises
    ------
    InvalidInputError
        ``folder`` exists and is not empty, and ``force`` is False.
    """
    folder = FilePath(folder)
    if folder.exists() and (not folder.is_dir() or any(folder.iterdir())) and not force:
        raise InvalidInputError(
            f"output folder {str(folder)!r} exists and is not empty; choose another or pass --force to replace it",
            field="out",
        )
    folder.parent.mkdir(parents=True, exist_ok=True)
    tmp = FilePath(tempfile.mkdtemp(prefix=f".{folder.name}.", suffix=".partial", dir=folder.parent))
    try:
        _write_trajectory(result.left, result.stance_left.mask, tmp / "left.csv")
        if result.right is not None:
            _write_trajectory(result.right, result.stance_right.mask, tmp / "right.csv")
        path: Path = result.path
        np.savetxt(
            tmp / "path.csv",
            np.column_stack([path.t, path.position]),
            delimiter=",",
            header="frame: nav (z up)\nt_s,pos_x_m,pos_y_m,pos_z_m",
            fmt="%.9g",
        )
        doc = {"summary": dict(summary or {}), "provenance": dict(result.meta)}
        (tmp / "summary.json").write_text(json.dumps(_jsonable(doc), indent=2) + "\n", encoding="utf-8")
        if pipeline_toml is not None:
            (tmp / "pipeline.toml").write_text(pipeline_toml, encoding="utf-8")
        if folder.exists():
            shutil.rmtree(folder) if folder.is_dir() else folder.unlink()
        os.replace(tmp, folder)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise
    return folder
