"""Helpers shared by the file readers: text tables with line numbers, honest ImuData construction.

Every reader goes through these functions so that all of them

* raise :class:`~footnav.core.errors.DataNotFoundError` for a missing file;
* raise :class:`~footnav.core.errors.InvalidInputError` naming the file, the 1-based line and the
  column for an empty file, a wrong number of columns, a non-numeric or non-finite cell, a
  truncated last line, a duplicate or backwards time stamp;
* record every change they make (units converted, duplicates dropped, gaps, clipping) in meta.

The fast path parses a whole table with :func:`numpy.loadtxt`; only when that fails is the table
scanned line by line, to name the first bad line and column.
"""

from __future__ import annotations

import os
import stat
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace
from pathlib import Path as FilePath
from typing import Any

import numpy as np
from numpy.typing import NDArray

from footnav.core.errors import DataNotFoundError, DataQualityWarning, InvalidInputError
from footnav.core.types import (  # noqa: F401  (CLIP_*: re-exported, they were defined here)
    CLIP_FRACTION_OF_FULL_SCALE,
    CLIP_MIN_ACC_MPS2,
    CLIP_MIN_GYR_RADPS,
    CLIP_MIN_REPEATS,
    ImuData,
    detect_clipping,
)
from footnav.core.warning_log import warn

__all__ = [
    "ROTATE_180_ABOUT_X",
    "TextFile",
    "build_imu",
    "changes_of",
    "check_file",
    "max_input_bytes",
    "DEFAULT_MAX_INPUT_MB",
    "detect_clipping",
    "parse_table",
    "read_text",
    "remap_indices",
    "split_header",
]

#: Proper rotation of 180 degrees about x: (x, y, z) -> (x, -y, -z). Turns a z-down frame into a
#: z-up one without mirroring (a z flip alone would be a reflection, det = -1).
ROTATE_180_ABOUT_X = np.diag([1.0, -1.0, -1.0])


@dataclass(frozen=True)
class TextFile:
    """A text file split into lines.

    ``lines[k]`` is line ``k + 1`` of the file (without its line ending); ``ends_with_newline``
    says whether the last line was terminated, which tells a cut-off file from a complete one.
    """

    path: str
    lines: list[str]
    ends_with_newline: bool


#: Largest input file footnav reads, in MB (10^6 bytes), unless the environment variable
#: ``FOOTNAV_MAX_INPUT_MB`` says otherwise. Reading a text table takes about 5 x its size in memory
#: (the text, its lines, the parsed floats): 512 MB of text is ~2.6 GB. The largest shared
#: recording is under 10 MB; a 62-minute walk at 100 Hz in footnav CSV is ~50 MB.
DEFAULT_MAX_INPUT_MB = 512.0
MAX_INPUT_ENV = "FOOTNAV_MAX_INPUT_MB"


def max_input_bytes() -> int:
    """The input size limit in bytes: ``FOOTNAV_MAX_INPUT_MB`` (MB) or ``DEFAULT_MAX_INPUT_MB``."""
    text = os.environ.get(MAX_INPUT_ENV, "").strip()
    if not text:
        return int(DEFAULT_MAX_INPUT_MB * 1e6)
    try:
        mb = float(text)
    except ValueError:
        mb = float("nan")
    if not (mb > 0 and np.isfinite(mb)):
        raise InvalidInputError(f"{MAX_INPUT_ENV}={text!r} is not a positive number of MB", field=MAX_INPUT_ENV)
    return int(mb * 1e6)


def check_file(path: Any, *, what: str = "file") -> FilePath:
    """Return ``path`` as a Path after checking it can be read with bounded memory and time.

    Raises
    ------
    DataNotFoundError
        It does not exist.
    InvalidInputError
        A folder; not a regular file (a device such as /dev/zero reads forever, a FIFO blocks
        until a writer comes); larger than :func:`max_input_bytes` (the message says how to raise
        the limit).
    """
    p = FilePath(path)
    if not p.exists():
        raise DataNotFoundError(f"{what} {str(p)!r} does not exist")
    if p.is_dir():
        raise InvalidInputError(f"is a folder; expected a {what}", path=str(p))
    st = p.stat()
    if not stat.S_ISREG(st.st_mode):
        kind = (
            "a FIFO (named pipe)"
            if stat.S_ISFIFO(st.st_mode)
            else ("a device" if stat.S_ISCHR(st.st_mode) or stat.S_ISBLK(st.st_mode) else "not a regular file")
        )
        raise InvalidInputError(
            f"is {kind}; expected a {what} (footnav reads regular files only: a device or pipe may never end)",
            path=str(p),
        )
    limit = max_input_bytes()
    if st.st_size > limit:
        raise InvalidInputError(
            f"is {st.st_size / 1e6:.0f} MB, above footnav's input limit of {limit / 1e6:g} MB (reading takes about "
            f"5 x the file size in memory); raise it with the environment variable {MAX_INPUT_ENV}=<MB>",
            path=str(p),
        )
    return p


def read_text(path: Any, *, what: str = "file") -> TextFile:
    """Read a text file (UTF-8, optional BOM) checked by :func:`check_file`. Empty files (only
    blank lines) are an error."""
    p = check_file(path, what=what)
    limit = max_input_bytes()
    with p.open("rb") as fh:
        raw = fh.read(limit + 1)  # bounded even if the file grows after the check
    if len(raw) > limit:
        raise InvalidInputError(
            f"grew beyond footnav's input limit of {limit / 1e6:g} MB while being read; raise it with the "
            f"environment variable {MAX_INPUT_ENV}=<MB>",
            path=str(p),
        )
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        line = raw[: exc.start].count(b"\n") + 1
        raise InvalidInputError(
            f"not a UTF-8 text file ({exc.reason} at byte {exc.start})", path=str(p), line=line
        ) from None
    lines = text.splitlines()
    if not any(s.strip() for s in lines):
        raise InvalidInputError("file is empty; expected a header and data rows", path=str(p), line=1)
    return TextFile(path=str(p), lines=lines, ends_with_newline=text.endswith(("\n", "\r")))


def split_header(line: str, delimiter: str | None) -> list[str]:
    """Cells of a header line, stripped of white space and surrounding double quotes."""
    cells = line.split(delimiter) if delimiter is not None else line.split()
    return [c.strip().strip('"').strip() for c in cells]


def _cells(line: str, delimiter: str | None) -> list[str]:
    return [c.strip() for c in line.split(delimiter)] if delimiter is not None else line.split()


def parse_table(
    tf: TextFile,
    start: int,
    names: Sequence[str],
    *,
    delimiter: str | None = ",",
    stop: int | None = None,
    allow_missing: bool = False,
) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """Parse lines ``start:stop`` (0-based into ``tf.lines``) as a numeric table.

    Parameters
    ----------
    tf
        The file.
    start, stop
        Range of lines holding the data rows. Blank lines are skipped.
    names
        One name per column (used in error messages); every row must have ``len(names)`` cells.
    delimiter
        Cell separator; None splits on any run of white space.
    allow_missing
        Empty cells become NaN (motion capture drop-outs) instead of an error.

    Returns
    -------
    data
        (N, len(names)) float64.
    line_numbers
        (N,) 1-based line number of each row in the file, for error messages.

    Raises
    ------
    InvalidInputError
        No data rows, wrong number of cells (a short last line of a file that does not end with a
        newline is reported as truncated), non-numeric cell, NaN or infinite cell.
    """
    stop = len(tf.lines) if stop is None else stop
    rows = [k for k in range(start, stop) if tf.lines[k].strip()]
    if not rows:
        raise InvalidInputError(
            f"no data rows after the header; expected rows of {len(names)} columns {list(names)}",
            path=tf.path,
            line=start + 1,
        )
    line_numbers = np.asarray(rows, dtype=np.int64) + 1
    texts = [tf.lines[k] for k in rows]
    ncols = len(names)
    try:
        data = np.loadtxt(texts, delimiter=delimiter, dtype=np.float64, ndmin=2, comments=None)  # rows: not empty
    except ValueError:  # any bad cell or row: find and name it line by line
        data = None
    if data is None or data.shape[1] != ncols:
        data = _scan(tf, rows, names, delimiter, allow_missing)
    bad = ~np.isfinite(data)
    if not allow_missing:
        bad_rows = bad.any(axis=1)
        if bad_rows.any():
            i = int(np.argmax(bad_rows))
            j = int(np.argmax(bad[i]))
            raise InvalidInputError(
                f"non-finite value {_cells(tf.lines[rows[i]], delimiter)[j]!r} in column {names[j]!r}; "
                "every cell must be a finite number",
                path=tf.path,
                line=int(line_numbers[i]),
                field=names[j],
            )
    return data, line_numbers


def _scan(
    tf: TextFile, rows: list[int], names: Sequence[str], delimiter: str | None, allow_missing: bool
) -> NDArray[np.float64]:
    """Slow path: convert line by line and raise on the first bad line (named by line and column)."""
    ncols = len(names)
    out = np.empty((len(rows), ncols), dtype=np.float64)
    last_row = rows[-1]
    for r, k in enumerate(rows):
        cells = _cells(tf.lines[k], delimiter)
        if len(cells) != ncols:
            if k == last_row and k == len(tf.lines) - 1 and not tf.ends_with_newline and len(cells) < ncols:
                msg = (
                    f"truncated last line: {len(cells)} of {ncols} columns and no line ending; "
                    "the file looks cut off (incomplete copy or interrupted recording)"
                )
            else:
                msg = f"expected {ncols} columns {list(names)}, found {len(cells)}: {tf.lines[k]!r}"
            raise InvalidInputError(msg, path=tf.path, line=k + 1)
        for j, cell in enumerate(cells):
            if cell == "" and allow_missing:
                out[r, j] = np.nan
                continue
            try:
                v = float(cell)
            except ValueError:
                raise InvalidInputError(
                    f"non-numeric value {cell!r} in column {names[j]!r}; expected a number",
                    path=tf.path,
                    line=k + 1,
                    field=names[j],
                ) from None
            out[r, j] = v
    return out


def build_imu(
    t: Any,
    acc: Any,
    gyr: Any,
    mag: Any = None,
    *,
    path: str,
    fmt: str,
    line_numbers: NDArray[np.int64] | None = None,
    acc_unit: str = "m/s^2",
    gyr_unit: str = "rad/s",
    t_unit: str = "s",
    mag_unit: str = "uT",
    drop_duplicates: bool = False,
    acc_full_scale_mps2: float | None = None,
    meta: Mapping[str, Any] | None = None,
) -> tuple[ImuData, NDArray[np.bool_]]:
    """ImuData from one foot's columns, checked and with every change recorded.

    Duplicate time stamps raise (naming file, line and index of the first) unless
    ``drop_duplicates``; then :meth:`ImuData.from_arrays` drops them and this function adds to
    ``meta["duplicates_dropped"]`` the line of the first one, how many were exact copies of the
    previous row and how many conflicting (same time, different values -- warned). Backwards
    time always raises. Gaps are reported by ImuData. Clipping (:func:`detect_clipping`),
    the time base and rate, and the units are checked by :meth:`ImuData.from_arrays`, which warns
    and records its findings in meta (``"clipped"``, ``"rate_check"``, ``"acc_at_rest"``, ...).

    Returns
    -------
    imu
        The ImuData (``meta["source"]`` = ``path``, ``meta["format"]`` = ``fmt``).
    keep
        (N_rows,) bool: which input rows were kept, to drop the same rows of side arrays.
    """
    t = np.asarray(t, dtype=np.float64)
    acc = np.asarray(acc, dtype=np.float64)
    gyr = np.asarray(gyr, dtype=np.float64)
    mag = None if mag is None else np.asarray(mag, dtype=np.float64)
    meta = {"source": path, "format": fmt, **dict(meta or {})}
    # Both feet of one file share the path: name the foot in warnings.
    label = path + (f" ({meta['foot']} foot)" if meta.get("foot") in ("left", "right") else "")

    def line_of(i: int) -> int | None:
        return None if line_numbers is None else int(line_numbers[i])

    dt = np.diff(t)
    dup = np.flatnonzero(dt == 0) + 1
    back = np.flatnonzero(dt < 0) + 1
    if len(back):
        i = int(back[0])
        raise InvalidInputError(
            f"time goes backwards: t={float(t[i])!r} {t_unit} after t={float(t[i - 1])!r} {t_unit}; "
            "rows must be in time order",
            path=path,
            line=line_of(i),
            field="t",
            index=i,
        )
    keep = np.ones(len(t), dtype=bool)
    dup_info: dict[str, Any] = {}
    if len(dup):
        cols = [t[:, None], acc, gyr] + ([] if mag is None else [mag])
        rows = np.hstack(cols)
        exact = (rows[dup] == rows[dup - 1]).all(axis=1)
        if not drop_duplicates and not exact.all():
            # a repeated time with other values: which row is right is unknown; the user decides
            i = int(dup[np.argmax(~exact)])
            raise InvalidInputError(
                f"duplicate time stamp t={float(t[i])!r} {t_unit} with values different from the previous row"
                + (f" (line {line_of(i - 1)})" if line_numbers is not None else "")
                + f"; {int((~exact).sum())} such row(s) in total; pass drop_duplicates=True (footnav run: "
                "--drop-duplicates) to keep the first row of each time stamp (recorded in meta['duplicates_dropped'])",
                path=path,
                line=line_of(i),
                field="t",
                index=i,
            )
        # exact copies of the previous row (a logger writing a packet twice) carry no information:
        # they are dropped by default, with the warning and record from_arrays gives
        drop_duplicates = True
        keep[dup] = False
        dup_info = {
            "first_line": line_of(int(dup[0])),
            "exact_row_copies": int(exact.sum()),
            "conflicting": int((~exact).sum()),
        }
        if (~exact).any():
            i = int(dup[np.argmax(~exact)])
            warn(
                f"{label}: {int((~exact).sum())} dropped row(s) repeat the previous time stamp with different "
                f"values (first at index {i}"
                + (f", line {line_of(i)}" if line_numbers is not None else "")
                + "); the first row of each time stamp was kept",
                DataQualityWarning,
                stacklevel=3,
            )
    imu = ImuData.from_arrays(
        t,
        acc,
        gyr,
        mag,
        acc_unit=acc_unit,
        gyr_unit=gyr_unit,
        t_unit=t_unit,
        mag_unit=mag_unit,
        drop_duplicates=drop_duplicates,
        meta=meta,
        acc_full_scale_mps2=acc_full_scale_mps2,  # clipping is found (and warned) there
    )
    new_meta = dict(imu.meta)
    converted = {
        q: f"{u} -> {si}"
        for q, u, si in (("t", t_unit, "s"), ("acc", acc_unit, "m/s^2"), ("gyr", gyr_unit, "rad/s"))
        if u != si
    }
    if mag is not None and mag_unit not in ("uT", "a.u."):
        converted["mag"] = f"{mag_unit} -> uT"
    new_meta["units_converted"] = converted
    if dup_info:
        new_meta["duplicates_dropped"] = {**new_meta["duplicates_dropped"], **dup_info}
    return replace(imu, meta=new_meta), keep


def remap_indices(indices: NDArray[np.int64], keep: NDArray[np.bool_]) -> NDArray[np.int64]:
    """Map sample indices of the file's rows to indices after dropping rows (``keep`` False).

    An index of a dropped row maps to the kept row before it (a duplicate of it).
    """
    indices = np.asarray(indices, dtype=np.int64)
    if keep.all():
        return indices
    new = np.cumsum(keep) - 1
    return np.maximum(new[np.clip(indices, 0, len(keep) - 1)], 0)


def changes_of(foot: str, imu: ImuData) -> list[str]:
    """Human-readable list of what the reader changed or found in one foot's data."""
    out = []
    conv = imu.meta.get("units_converted") or {}
    if conv:
        out.append(f"{foot}: converted " + ", ".join(f"{k} {v}" for k, v in conv.items()))
    dd = imu.meta.get("duplicates_dropped")
    if dd:
        where = f" (first at line {dd['first_line']})" if dd.get("first_line") else ""
        out.append(f"{foot}: dropped {dd['count']} duplicate row(s){where}")
    gaps = imu.meta.get("gaps")
    if gaps:
        out.append(f"{foot}: {len(gaps)} sampling gap(s), longest {max(g[1] for g in gaps) * 1e3:.3g} ms")
    clipped = imu.meta.get("clipped")
    if clipped:
        out.append(f"{foot}: {clipped['acc']} accelerometer / {clipped['gyr']} gyroscope sample(s) clipped")
    for note in imu.meta.get("changes", ()):
        out.append(f"{foot}: {note}")
    return out
