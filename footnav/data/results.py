"""Results that last: a folder per run with the trajectories (CSV and npz), the summary and the
provenance (JSON: the pipeline, footnav's and its dependencies' versions, the input files'
SHA-256), and the exact pipeline as TOML; or, for an evaluation, the report as CSV and JSON.

Every folder is claimed before the work and written under a temporary name beside its target,
then put in place (:mod:`footnav.data.output`), so an interrupted run (Ctrl-C included) never
leaves a half-written result; an existing non-empty folder is replaced only with ``force=True``,
and only when footnav wrote everything in it (the marker lists what it wrote).
"""

from __future__ import annotations

import csv
import hashlib
import io
import json
import os
from collections.abc import Iterable, Iterator, Mapping
from contextlib import contextmanager
from pathlib import Path as FilePath
from typing import Any

import numpy as np

from footnav.core.types import FootTrajectory, Path
from footnav.core.warning_log import merge_warnings
from footnav.data.output import OutputClaim, claim_output
from footnav.nav.strides import STRIDE_COLUMNS, stride_parameters
from footnav.pipeline.result import PipelineResult

__all__ = [
    "TRAJECTORY_COLUMNS",
    "atomic_folder",
    "file_sha256",
    "merge_warnings",
    "versions",
    "with_warnings",
    "write_report",
    "write_results",
]

#: Packages whose versions are recorded with every result.
_DEPENDENCIES = ("numpy", "scipy", "numba", "hmmlearn", "scikit-learn", "pluggy", "pandas", "joblib")

TRAJECTORY_COLUMNS = (
    "t_s,pos_x_m,pos_y_m,pos_z_m,vel_x_mps,vel_y_mps,vel_z_mps,"
    "q_w,q_x,q_y,q_z,pos_std_x_m,pos_std_y_m,pos_std_z_m,stance"
)


def _write_trajectory(traj: FootTrajectory, stance_mask, path: FilePath) -> None:
    data = np.column_stack(
        [traj.t, traj.position, traj.velocity, traj.quaternion, traj.position_std, np.asarray(stance_mask, dtype=float)]
    )
    np.savetxt(path, data, delimiter=",", header=f"frame: nav (z up)\n{TRAJECTORY_COLUMNS}", fmt="%.9g")


#: Stride columns written as they are (text, integers, True/False): the rest are floats.
_VERBATIM = ("foot", "first", "last", "standstill", "kind", "level", "start_index", "end_index")


def _strides_csv(result: PipelineResult) -> str:
    """Both feet's strides (:func:`footnav.nav.strides.stride_parameters`) as CSV text, one header
    row of :data:`~footnav.nav.strides.STRIDE_COLUMNS` (``foot, start_s, end_s, length_m,
    duration_s`` first), left foot's strides first."""
    buf = io.StringIO()
    writer = csv.writer(buf, lineterminator="\n")
    writer.writerow(STRIDE_COLUMNS)
    for foot, traj, stance in (("left", result.left, result.stance_left), ("right", result.right, result.stance_right)):
        if traj is None or stance is None:
            continue
        for row in stride_parameters(traj, stance, foot=foot):
            writer.writerow([row[c] if c in _VERBATIM else f"{row[c]:.9g}" for c in STRIDE_COLUMNS])
    return buf.getvalue()


def with_warnings(result: PipelineResult, earlier: Iterable[Any]) -> PipelineResult:
    """``result`` with the warnings issued before its run (reading its files: clipping, an
    accelerometer off g) first in ``meta["warnings"]``.

    A reader warns and records its findings in the data's meta once, so the pipeline's own checks
    do not repeat them and its warning log, which starts with the run, does not hold them; the
    command line records what it printed while reading and joins it here, so that summary.json
    lists every warning shown.
    """
    from dataclasses import replace

    merged = merge_warnings(earlier, result.meta.get("warnings", ()))
    return replace(result, meta={**result.meta, "warnings": merged})


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


def versions() -> dict[str, str | None]:
    """Python's, footnav's and its dependencies' versions (None where not installed)."""
    import platform
    from importlib import metadata

    out: dict[str, str | None] = {"python": platform.python_version()}
    for name in ("footnav",) + _DEPENDENCIES:
        try:
            out[name] = metadata.version(name)
        except metadata.PackageNotFoundError:
            out[name] = None
    return out


def file_sha256(path: str | os.PathLike) -> str:
    """SHA-256 of a file's bytes, hex."""
    h = hashlib.sha256()
    with open(path, "rb") as fh:
        for block in iter(lambda: fh.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def _input_hashes(metas: list[Mapping[str, Any]]) -> dict[str, str]:
    """SHA-256 of every input file named in the inputs' meta (``source``), by path."""
    out = {}
    for meta in metas:
        src = (meta or {}).get("source")
        if isinstance(src, str) and os.path.isfile(src):
            out[src] = file_sha256(src)
    return out


@contextmanager
def atomic_folder(
    folder: str | os.PathLike | OutputClaim, *, force: bool = False, inputs: Iterable[str | os.PathLike] = ()
) -> Iterator[FilePath]:
    """Write into a temporary folder beside ``folder`` and put it in place on success.

    ``folder`` is claimed first (:func:`footnav.data.output.claim_output`: never the working
    folder or one above it, a folder holding an input, or a non-empty folder footnav did not
    write; another footnav run's folder is refused) unless it is a claim already. On any exception
    (KeyboardInterrupt included) the temporary folder is removed and ``folder`` is left as it was.

    Raises
    ------
    InvalidInputError
        ``folder`` cannot be claimed; the message says why (``field="out"``).
    """
    if isinstance(folder, OutputClaim):
        with folder.staged() as tmp:
            yield tmp
        return
    with claim_output(folder, kind="folder", force=force, inputs=inputs, what="output folder") as claim:
        with claim.staged() as tmp:
            yield tmp


def write_report(
    report: Any,
    folder: str | os.PathLike | OutputClaim,
    *,
    force: bool = False,
    pipelines: Mapping[str, str] | None = None,
    warnings: Iterable[Any] = (),
    batch: Mapping[str, Any] | None = None,
    html: bool = False,
    recordings: Iterable[Any] = (),
) -> FilePath:
    """Write an evaluation report into ``folder``: ``report.csv``, ``report.json`` (metrics,
    truth checks, ``warnings``: the given ones, then every run's ``meta["warnings"]``, each once;
    versions, input hashes, ``batch``: how it ran) and each pipeline's TOML (``pipelines``: name -> TOML text);
    with ``html``, ``report.html`` too (:func:`footnav.report.evaluation_html`: the metrics with the
    best of each row marked, each pipeline's path over the truth of ``recordings``)."""
    sources = [
        m["source"]
        for res in report.results.values()
        for m in res.meta.get("input", {}).values()
        if m and isinstance(m.get("source"), str)
    ]
    with atomic_folder(folder, force=force, inputs=sources) as tmp:
        (tmp / "report.csv").write_text(report.to_csv(), encoding="utf-8")
        metas = [m for res in report.results.values() for m in res.meta.get("input", {}).values() if m]
        doc = {
            "metrics": report.rows(),
            "truth_checks": [c.__dict__.copy() for c in getattr(report, "checks", ())],
            "warnings": merge_warnings(warnings, *(res.meta.get("warnings", ()) for res in report.results.values())),
            **({"batch": dict(batch)} if batch else {}),
            "versions": versions(),
            "input_sha256": _input_hashes(metas),
        }
        (tmp / "report.json").write_text(json.dumps(_jsonable(doc), indent=2) + "\n", encoding="utf-8")
        for name, toml in (pipelines or {}).items():
            (tmp / f"pipeline-{name}.toml").write_text(toml, encoding="utf-8")
        if html:
            from footnav.report import REPORT_NAME
            from footnav.report.evaluation import evaluation_html

            page = evaluation_html(
                report, list(recordings), pipelines_toml=pipelines, warnings=doc["warnings"], batch=batch
            )
            (tmp / REPORT_NAME).write_text(page, encoding="utf-8")
    return folder.target if isinstance(folder, OutputClaim) else FilePath(folder)


def write_results(
    result: PipelineResult,
    folder: str | os.PathLike | OutputClaim,
    *,
    force: bool = False,
    summary: Mapping[str, Any] | None = None,
    pipeline_toml: str | None = None,
    html: bool = False,
    recording: Any = None,
) -> FilePath:
    """Write ``result`` into ``folder``: ``left.csv`` (``right.csv``), ``path.csv``,
    ``strides.csv`` (gait parameters per stride and foot, :meth:`PipelineResult.strides`),
    ``trajectories.npz`` (the same arrays), ``summary.json`` (``summary`` plus provenance: pipeline,
    versions, warnings, inputs and their SHA-256) and ``pipeline.toml``; with ``html``,
    ``report.html`` (:mod:`footnav.report`; ``recording``, optional, gives the truth and the
    gyroscope it draws). Everything is listed in the folder's marker, as footnav's.

    Raises
    ------
    InvalidInputError
        ``folder`` cannot be claimed (:func:`atomic_folder`): not empty and ``force`` False, not
        written by footnav or holding files footnav did not write, not writable, the working
        folder, an input or a folder holding one.
    """
    sources = [m["source"] for m in result.meta.get("input", {}).values() if m and isinstance(m.get("source"), str)]
    with atomic_folder(folder, force=force, inputs=sources) as tmp:
        arrays = {}
        for foot, traj, stance in (
            ("left", result.left, result.stance_left),
            ("right", result.right, result.stance_right),
        ):
            if traj is None:
                continue
            _write_trajectory(traj, stance.mask, tmp / f"{foot}.csv")
            arrays.update(
                {f"{foot}_{k}": getattr(traj, k) for k in ("t", "position", "velocity", "quaternion", "position_std")}
            )
            arrays[f"{foot}_stance"] = np.asarray(stance.mask)
        path: Path = result.path
        np.savetxt(
            tmp / "path.csv",
            np.column_stack([path.t, path.position]),
            delimiter=",",
            header="frame: nav (z up)\nt_s,pos_x_m,pos_y_m,pos_z_m",
            fmt="%.9g",
        )
        arrays.update(path_t=path.t, path_position=path.position)
        (tmp / "strides.csv").write_text(_strides_csv(result), encoding="utf-8")
        # plain arrays: np.load(..., allow_pickle=False). Not compressed: deflating the float
        # arrays took 0.1 s for a one-minute walk at 400 Hz and saved 15 % of the size.
        np.savez(tmp / "trajectories.npz", **arrays)
        inputs = [m for m in result.meta.get("input", {}).values() if m]
        doc = {
            "summary": dict(summary or {}),
            "provenance": dict(result.meta),
            "versions": versions(),
            "input_sha256": _input_hashes(inputs),
        }
        (tmp / "summary.json").write_text(json.dumps(_jsonable(doc), indent=2) + "\n", encoding="utf-8")
        if pipeline_toml is not None:
            (tmp / "pipeline.toml").write_text(pipeline_toml, encoding="utf-8")
        if html:
            from footnav.report import REPORT_NAME
            from footnav.report.result import result_html

            page = result_html(result, recording=recording, pipeline_toml=pipeline_toml, summary=summary)
            (tmp / REPORT_NAME).write_text(page, encoding="utf-8")
    return folder.target if isinstance(folder, OutputClaim) else FilePath(folder)
