"""footnav's own CSV format: one foot per file, SI units, exact round trip.

Format::

    # units: t s, acc m/s^2, gyr rad/s          <- optional comment lines ('#') before the header
    t,acc_x,acc_y,acc_z,gyr_x,gyr_y,gyr_z[,mag_x,mag_y,mag_z]
    0.0,0.12,-0.03,9.81,0.001,0.0,-0.002
    ...

* ``t`` time (default s), ``acc_*`` specific force (default m/s^2), ``gyr_*`` angular rate
  (default rad/s), optional ``mag_*`` magnetic field (default uT), all in the sensor's body frame.
* A ``# units:`` comment states the units of the file; the writer always writes one (SI).
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path as FilePath
from typing import Any

import numpy as np

from footnav.core.errors import InvalidInputError
from footnav.core.types import FootTruth, ImuData, Recording
from footnav.data.io._text import build_imu, changes_of, parse_table, read_text, split_header

__all__ = [
    "read_footnav_csv",
    "read_footnav_recording",
    "read_footnav_folder",
    "write_footnav_csv",
    "write_footnav_truth",
    "FOOTNAV_COLUMNS",
    "FOOTNAV_MAG_COLUMNS",
    "TRUTH_COLUMNS",
]

FORMAT = "footnav_csv"
#: Required columns, in the order the writer writes them.
FOOTNAV_COLUMNS = ("t", "acc_x", "acc_y", "acc_z", "gyr_x", "gyr_y", "gyr_z")
#: Optional magnetometer columns.
FOOTNAV_MAG_COLUMNS = ("mag_x", "mag_y", "mag_z")
#: SI units the reader assumes when neither the caller nor a ``# units:`` comment says otherwise.
_SI_UNITS = {"t": "s", "acc": "m/s^2", "gyr": "rad/s", "mag": "uT"}
_UNITS_PREFIX = "units:"


def _parse_units_comment(text: str, path: str, line: int) -> dict[str, str]:
    """``# units: t s, acc m/s^2, gyr rad/s`` -> {"t": "s", "acc": "m/s^2", "gyr": "rad/s"}."""
    body = text.lstrip("#").strip()[len(_UNITS_PREFIX) :]
    units = {}
    for part in body.split(","):
        words = part.split(None, 1)
        if not words:
            continue
        if len(words) != 2 or words[0] not in _SI_UNITS:
            raise InvalidInputError(
                f"cannot read units comment part {part.strip()!r}; expected e.g. '# units: t s, acc m/s^2, gyr rad/s'",
                path=path,
                line=line,
            )
        units[words[0]] = words[1].strip()
    return units


def read_footnav_csv(
    path: Any,
    *,
    acc_unit: str | None = None,
    gyr_unit: str | None = None,
    t_unit: str | None = None,
    mag_unit: str | None = None,
    drop_duplicates: bool = False,
    acc_full_scale_mps2: float | None = None,
) -> ImuData:
    """Read one foot from a footnav CSV file.

    Parameters
    ----------
    path
        The file: optional ``#`` comment lines, the header
        ``t,acc_x,acc_y,acc_z,gyr_x,gyr_y,gyr_z[,mag_x,mag_y,mag_z]`` (columns found by name, any
        order), then one row per sample.
    acc_unit, gyr_unit, t_unit, mag_unit
        Units of the file's columns (``"m/s^2"``/``"g"``, ``"rad/s"``/``"deg/s"``, ``"s"``/``"ms"``,
        ``"uT"``/``"T"``/``"gauss"``/``"a.u."``); converted to SI. None (default) takes the unit
        from the file's ``# units:`` comment, else SI. A unit given here that contradicts the
        comment is an error (one of the two is wrong, and the reader cannot know which).
    drop_duplicates
        Drop rows repeating the previous time stamp (recorded in ``meta["duplicates_dropped"]``);
        without it they raise.
    acc_full_scale_mps2
        The accelerometer's full scale, if known, for clipping detection.

    Returns
    -------
    ImuData
        Body frame, SI units; ``meta["source"]`` the path, ``meta["format"]`` ``"footnav_csv"``,
        ``meta["units_in"]`` the file's units.

    Raises
    ------
    DataNotFoundError
        The file does not exist.
    InvalidInputError
        Empty file, missing or unknown columns, wrong number of cells, non-numeric cell, truncated
        last line, duplicate (unless dropped) or backwards time; the message names file and line.
    """
    tf = read_text(path)
    k = 0
    file_units: dict[str, str] = {}
    units_line = None
    while k < len(tf.lines) and (not tf.lines[k].strip() or tf.lines[k].lstrip().startswith("#")):
        body = tf.lines[k].lstrip().lstrip("#").strip()
        if body.lower().startswith(_UNITS_PREFIX):
            file_units = _parse_units_comment(tf.lines[k], tf.path, k + 1)
            units_line = k + 1
        k += 1
    if k == len(tf.lines):
        raise InvalidInputError(
            "only comment lines; expected the header " + ",".join(FOOTNAV_COLUMNS), path=tf.path, line=k
        )
    header = split_header(tf.lines[k], ",")
    has_mag = any(c in header for c in FOOTNAV_MAG_COLUMNS)
    expected = FOOTNAV_COLUMNS + (FOOTNAV_MAG_COLUMNS if has_mag else ())
    if sorted(header) != sorted(expected):
        missing = [c for c in expected if c not in header]
        extra = [c for c in header if c not in expected]
        raise InvalidInputError(
            f"header {header} does not match {','.join(FOOTNAV_COLUMNS)}[,{','.join(FOOTNAV_MAG_COLUMNS)}]"
            + (f"; missing {missing}" if missing else "")
            + (f"; unknown {extra}" if extra else ""),
            path=tf.path,
            line=k + 1,
        )
    data, lines = parse_table(tf, k + 1, header, delimiter=",")
    col = {name: data[:, j] for j, name in enumerate(header)}

    units = {}
    for q, given in (("t", t_unit), ("acc", acc_unit), ("gyr", gyr_unit), ("mag", mag_unit)):
        in_file = file_units.get(q)
        if given is not None and in_file is not None and given != in_file:
            raise InvalidInputError(
                f"{q} unit {given!r} was given but the file's units comment says {in_file!r}",
                path=tf.path,
                line=units_line,
                field=q,
            )
        units[q] = given or in_file or _SI_UNITS[q]

    imu, _ = build_imu(
        col["t"],
        np.column_stack([col["acc_x"], col["acc_y"], col["acc_z"]]),
        np.column_stack([col["gyr_x"], col["gyr_y"], col["gyr_z"]]),
        np.column_stack([col["mag_x"], col["mag_y"], col["mag_z"]]) if has_mag else None,
        path=tf.path,
        fmt=FORMAT,
        line_numbers=lines,
        acc_unit=units["acc"],
        gyr_unit=units["gyr"],
        t_unit=units["t"],
        mag_unit=units["mag"],
        drop_duplicates=drop_duplicates,
        acc_full_scale_mps2=acc_full_scale_mps2,
        meta={"units_source": "units comment" if file_units else "caller / SI default"},
    )
    return imu


def read_footnav_recording(left_path: Any, right_path: Any = None, **options: Any) -> Recording:
    """Read one or two footnav CSV files (left, optional right) as a Recording without truth.

    ``options`` are passed to :func:`read_footnav_csv` for both files (units, ``drop_duplicates``).
    """
    left = read_footnav_csv(left_path, **options)
    right = None if right_path is None else read_footnav_csv(right_path, **options)
    left = replace(left, meta={**left.meta, "foot": "left"})
    if right is not None:
        right = replace(right, meta={**right.meta, "foot": "right"})
    changes = changes_of("left", left) + ([] if right is None else changes_of("right", right))
    return Recording(
        left=left,
        right=right,
        name=FilePath(left_path).stem,
        meta={
            "format": FORMAT,
            "source": str(left_path),
            "files": {"left": str(left_path), **({} if right_path is None else {"right": str(right_path)})},
            "units_converted": {
                "left": left.meta["units_converted"],
                **({} if right is None else {"right": right.meta["units_converted"]}),
            },
            "changes": changes,
        },
    )


def write_footnav_csv(imu: ImuData, path: Any) -> FilePath:
    """Write one foot as a footnav CSV file, SI units, every float exactly (``repr``).

    The file starts with ``# units: t s, acc m/s^2, gyr rad/s[, mag <unit>]`` and the header
    ``t,acc_x,...``; reading it back with :func:`read_footnav_csv` gives bit-identical arrays.
    The magnetometer unit is ``uT`` unless the data were read as ``a.u.`` (kept as is).

    Returns
    -------
    pathlib.Path
        The file written.
    """
    path = FilePath(path)
    cols = [imu.t[:, None], imu.acc, imu.gyr]
    names = list(FOOTNAV_COLUMNS)
    units = "# units: t s, acc m/s^2, gyr rad/s"
    if imu.mag is not None:
        cols.append(imu.mag)
        names += FOOTNAV_MAG_COLUMNS
        mag_unit = "a.u." if (imu.meta.get("units_in") or {}).get("mag") == "a.u." else "uT"
        units += f", mag {mag_unit}"
    table = np.hstack(cols).tolist()  # Python floats: repr is the shortest exact decimal
    with path.open("w", encoding="utf-8", newline="\n") as fh:
        fh.write(units + "\n")
        fh.write(",".join(names) + "\n")
        fh.writelines(",".join(map(repr, row)) + "\n" for row in table)
    return path


#: Columns of the truth files ``footnav simulate`` writes beside the recordings.
TRUTH_COLUMNS = ("t_s", "pos_x_m", "pos_y_m", "pos_z_m", "q_w", "q_x", "q_y", "q_z", "stance")


def write_footnav_truth(truth: FootTruth, path: Any) -> FilePath:
    """Write a foot's truth (time, nav position, attitude, stance) as CSV with a header that
    :func:`read_footnav_folder` reads back (``# closed_loop: true`` when the walk returns to its start)."""
    path = FilePath(path)
    stance = np.zeros(len(truth.t)) if truth.stance is None else truth.stance.astype(float)
    quat = np.full((len(truth.t), 4), np.nan) if truth.quaternion is None else truth.quaternion
    np.savetxt(
        path,
        np.column_stack([truth.t, truth.position, quat, stance]),
        delimiter=",",
        header=f"frame: {truth.frame} (z up)\nclosed_loop: {str(bool(truth.closed_loop)).lower()}\n"
        + ",".join(TRUTH_COLUMNS),
        fmt="%.17g",
    )
    return path


def _read_truth(path: FilePath) -> FootTruth:
    text = path.read_text(encoding="utf-8")
    closed = any(
        line.strip().lstrip("#").strip() == "closed_loop: true" for line in text.splitlines() if line.startswith("#")
    )
    data = np.loadtxt(path, delimiter=",", comments="#", ndmin=2)
    if data.shape[1] != len(TRUTH_COLUMNS):
        raise InvalidInputError(
            f"truth file has {data.shape[1]} columns; expected {len(TRUTH_COLUMNS)}: {','.join(TRUTH_COLUMNS)}",
            path=str(path),
        )
    quat = None if np.isnan(data[:, 4:8]).any() else data[:, 4:8]
    return FootTruth(
        t=data[:, 0],
        position=data[:, 1:4],
        quaternion=quat,
        stance=data[:, 8] > 0.5,
        closed_loop=closed,
        meta={"source": str(path), "stance_source": "file"},
    )


def read_footnav_folder(path: Any, **options: Any) -> Recording:
    """A folder holding ``left.csv`` (and ``right.csv``) in footnav CSV, with the truth files
    ``left_truth.csv`` / ``right_truth.csv`` when present (what ``footnav simulate`` writes)."""
    folder = FilePath(path)
    left, right = folder / "left.csv", folder / "right.csv"
    if not left.exists():
        raise InvalidInputError("footnav folder has no left.csv", path=str(folder))
    rec = read_footnav_recording(left, right if right.exists() else None, **options)
    truths = {
        foot: _read_truth(folder / f"{foot}_truth.csv") if (folder / f"{foot}_truth.csv").exists() else None
        for foot in ("left", "right")
    }
    return replace(
        rec,
        truth_left=truths["left"],
        truth_right=truths["right"] if rec.right is not None else None,
        name=folder.name,
        meta={**rec.meta, "format": "footnav_folder", "source": str(folder)},
    )
