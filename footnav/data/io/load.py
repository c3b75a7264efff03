"""``load``: read any supported recording, guessing its format from the file when not told.

Guessing looks at (in this order) whether the path is a folder (azure_fgo files; gaitmap example
files), the extension (``.mat``: variable names; ``.json``: an IPOL trial description) and the
first lines of a text file (column header). An IPOL foot file (first line ``Acquisition
frequency: ...``, name ``<stem>_lf.txt`` / ``<stem>_rf.txt`` with its other foot beside it) is
read as the two-foot IPOL trial, not as a one-sensor Xsens export. The guess is logged (``logging``
INFO on ``footnav.data.io.load``) and recorded:
``meta["format"]`` and ``meta["format_guessed"] = True``. A file matching no known format is an
InvalidInputError listing the formats.

A text table whose header names give the accelerometer and gyroscope columns (``AccX,...``,
``acc_x,...``, ``Accelerometer X (g),...``) and that no named format claims is read by the generic
``delimited`` reader (:mod:`footnav.data.io.delimited`); a file nothing recognises is refused
with a one-line ``--format delimited --columns ...`` example built from its own header.

A guess never invents a sampling rate: a headerless file of 6 numeric columns (the OpenShoe
layout, no time column) is read as OpenShoe at 820 Hz only when its name says OpenShoe
(``OpenShoeDataSet.txt``); otherwise ``load`` refuses it unless ``rate_hz`` is given. Devices,
FIFOs and files above the input size limit are refused before anything is read
(:func:`footnav.data.io._text.check_file`).
"""

from __future__ import annotations

import json
import logging
from collections.abc import Callable
from dataclasses import replace
from pathlib import Path as FilePath
from typing import Any

from footnav.core.errors import DataNotFoundError, InvalidInputError
from footnav.core.types import ImuData, Recording
from footnav.core.warning_log import recording
from footnav.data.io._text import check_file, split_header
from footnav.data.io.azure_fgo import AZURE_FGO_FILES, read_azure_fgo
from footnav.data.io.delimited import auto_columns, example_command, read_delimited, sniff_delimiter
from footnav.data.io.footnav_csv import FOOTNAV_COLUMNS, read_footnav_csv, read_footnav_folder, read_footnav_recording
from footnav.data.io.gaitdriven import GAITDRIVEN_VARIABLES, read_gaitdriven
from footnav.data.io.gaitmap import read_gaitmap
from footnav.data.io.ipol import ipol_trial_files, read_ipol
from footnav.data.io.openshoe import OPENSHOE_RATE_HZ, read_openshoe
from footnav.data.io.pyshoe import read_pyshoe
from footnav.data.io.ximu import is_ximu_cal_header, read_ximu_cal
from footnav.data.io.xio import read_xio
from footnav.data.io.xsens import read_xsens

__all__ = ["load", "guess_format", "reader_options", "READERS"]

log = logging.getLogger(__name__)

#: Format name -> reader returning a Recording. ``footnav_csv`` reads one file as the left foot
#: (:func:`read_footnav_recording`; :func:`read_footnav_csv` returns the ImuData itself).
READERS: dict[str, Callable[..., Recording]] = {
    "footnav_csv": read_footnav_recording,
    "footnav_folder": read_footnav_folder,
    "gaitmap": read_gaitmap,
    "azure_fgo": read_azure_fgo,
    "xio": read_xio,
    "openshoe": read_openshoe,
    "pyshoe": read_pyshoe,
    "xsens": read_xsens,
    "ipol": read_ipol,
    "gaitdriven": read_gaitdriven,
    "ximu_cal": read_ximu_cal,
    "delimited": read_delimited,
}

#: Lines read from the top of a text file to recognise it.
_SNIFF_LINES = 40
_GAITMAP_COMPANIONS = {"mocap_path": "mocap_sample.csv", "events_path": "stride_events_sample.csv"}


def _first_lines(path: FilePath) -> list[str]:
    lines = []
    with path.open("r", encoding="utf-8-sig", errors="replace") as fh:
        for _ in range(_SNIFF_LINES):
            line = fh.readline()
            if not line:
                break
            lines.append(line.rstrip("\r\n"))
    return lines


def _is_numeric_row(line: str, ncols: int) -> bool:
    cells = line.split(",")
    if len(cells) != ncols:
        return False
    try:
        [float(c) for c in cells]
    except ValueError:
        return False
    return True


def _is_float(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


# complexity: one branch per known file layout, tried in order
def guess_format(path: Any) -> tuple[str, str, dict[str, Any]]:  # noqa: C901
    """Guess the format of ``path``.

    Returns
    -------
    name, reason, options
        The READERS key, why it was chosen (for the log), and reader options the guess implies
        (e.g. the gaitmap companion files of a folder).

    Raises
    ------
    DataNotFoundError
        ``path`` does not exist.
    InvalidInputError
        No known format matches (the message lists them).
    """
    p = FilePath(path)
    if not p.exists():
        raise DataNotFoundError(f"{str(p)!r} does not exist")
    known = ", ".join(READERS)
    if p.is_dir():
        if (p / AZURE_FGO_FILES["left"]).exists() and (p / AZURE_FGO_FILES["right"]).exists():
            return "azure_fgo", f"folder holds {AZURE_FGO_FILES['left']} and {AZURE_FGO_FILES['right']}", {}
        if (p / "imu_sample.csv").exists():
            opts = {k: p / v for k, v in _GAITMAP_COMPANIONS.items() if (p / v).exists()}
            opts["_path"] = p / "imu_sample.csv"
            return "gaitmap", "folder holds imu_sample.csv (gaitmap example data)", opts
        if (p / "left.csv").exists():
            return "footnav_folder", "folder holds left.csv (footnav CSV, as footnav simulate writes)", {}
        raise InvalidInputError(
            f"cannot tell the format of this folder (no azure_fgo, gaitmap or footnav files); known formats: {known}; "
            "pass format=...",
            path=str(p),
        )
    check_file(p)  # a device or FIFO would block the sniffing below; a huge file is refused
    if p.suffix.lower() == ".mat":
        from scipy.io import whosmat

        try:
            names = {name for name, _, _ in whosmat(p)}
        except Exception as exc:  # corrupt or not a MATLAB file
            raise InvalidInputError(f"cannot read MATLAB file ({exc}); known formats: {known}", path=str(p)) from None
        if set(GAITDRIVEN_VARIABLES[:2]) <= names:
            return "gaitdriven", "MATLAB file with variables imu_data and timestamps (gait-driven data set)", {}
        if {"imu", "ts"} <= names:
            return "pyshoe", "MATLAB file with variables imu and ts", {}
        if names & {"ImuFootLeft", "posLeft", "posFoot"}:
            return "azure_fgo", "azure_fgo full-length MATLAB file", {"_path": p.parent, "full_length": True}
        raise InvalidInputError(
            f"MATLAB file with variables {sorted(names)} matches no known format; known formats: {known}", path=str(p)
        )
    if p.suffix.lower() == ".json":
        try:
            info = json.loads(p.read_text(encoding="utf-8"))
        except (UnicodeDecodeError, json.JSONDecodeError) as exc:
            raise InvalidInputError(f"not a JSON file ({exc}); known formats: {known}", path=str(p)) from None
        if isinstance(info, dict) and "TrialBoundaries" in info:
            return "ipol", "JSON with TrialBoundaries (IPOL trial description; reads both feet)", {}
        raise InvalidInputError(f"JSON file matches no known format; known formats: {known}", path=str(p))
    lines = _first_lines(p)
    content = [s for s in lines if s.strip()]
    if not content:
        raise InvalidInputError(f"file is empty; cannot guess its format (known formats: {known})", path=str(p), line=1)
    first = content[0].strip()
    if first.lower().startswith("acquisition frequency"):
        _, lf, rf, _ = ipol_trial_files(p)
        if p in (lf, rf) and lf.exists() and rf.exists():
            return "ipol", "IPOL foot file ('Acquisition frequency' line, _lf/_rf pair; reads both feet)", {}
        # a lone file of that layout is still an Xsens export of one sensor
    if any("PacketCounter" in s for s in content) or first.startswith("//"):
        return "xsens", "Xsens export (PacketCounter column / '//' preamble)", {}
    if first.startswith("Time (s)") and "Gyroscope" in first:
        return "xio", "x-io header 'Time (s),Gyroscope ...'", {}
    if first.startswith("time_index") and "is_zero_vel" in first:
        return "azure_fgo", "azure_fgo IMU file header (reads the whole folder)", {"_path": p.parent}
    if "left_sensor" in first or "right_sensor" in first:
        return "gaitmap", "gaitmap two-row header (left_sensor/right_sensor)", {}
    header = next((s.strip() for s in content if not s.lstrip().startswith("#")), "")
    if header.replace(" ", "").startswith("t,acc_x,acc_y,acc_z,gyr_x,gyr_y,gyr_z"):
        return "footnav_csv", "footnav CSV header 't,acc_x,...'", {}
    cells = split_header(header, sniff_delimiter(header))
    if sniff_delimiter(header) == "," and set(FOOTNAV_COLUMNS) <= set(cells):
        return "footnav_csv", "footnav CSV columns (t, acc_x, ..., gyr_z) in another order", {}
    if is_ximu_cal_header(cells):
        return "ximu_cal", "x-IMU CalInertialAndMag header 'Packet number,Gyroscope X (deg/s),...'", {}
    numeric = _is_numeric_row(first, 6)
    if not numeric and {"acc", "gyr"} <= set(auto_columns(cells)[0]):
        found = auto_columns(cells)[0]
        return (
            "delimited",
            (f"header names give acc and gyr columns ({', '.join(cells[j] for j in found['acc'] + found['gyr'])})"),
            {},
        )
    if numeric:
        # No header and no time column: the layout fits OpenShoe, but nothing in the file gives the
        # rate, and a wrong rate scales every distance (a 100 Hz file read at 820 Hz: 20 m -> 0.2 m).
        # The OpenShoe rate is taken only when the file name says OpenShoe; else load() needs rate_hz.
        if "openshoe" in p.name.lower():
            return "openshoe", f"no header, 6 numeric columns, file name says OpenShoe: {OPENSHOE_RATE_HZ:g} Hz", {}
        return "openshoe", "no header, 6 numeric comma-separated columns (OpenShoe layout)", {"_needs_rate": True}
    head = cells if not all(_is_float(c) for c in cells) else None
    raise InvalidInputError(
        f"cannot tell the format from the first line {first[:80]!r}; known formats: {known}; pass format=... "
        "(command line: --format). Any delimited table reads as format 'delimited' with its columns mapped "
        f"(docs/your-own-sensor.md), e.g.: {example_command(str(p), head, len(cells))}",
        path=str(p),
        line=1,
    )


def reader_options(format: str) -> tuple[str, ...]:
    """The keyword options the reader of ``format`` takes (e.g. ``acc_unit``, ``rate_hz``)."""
    import inspect

    if format not in READERS:
        raise InvalidInputError(f"unknown format {format!r}; known formats: {', '.join(READERS)}")
    reader = READERS[format]
    if format in ("footnav_csv", "footnav_folder"):  # options pass through to read_footnav_csv
        reader = read_footnav_csv
    params = list(inspect.signature(reader).parameters.values())[1:]  # after the path
    return tuple(
        p.name for p in params if p.kind in (p.KEYWORD_ONLY, p.POSITIONAL_OR_KEYWORD) and not p.name.startswith("_")
    )


def load(path: Any, format: str | None = None, **options: Any) -> Recording:
    """Read a recording of any supported format.

    Parameters
    ----------
    path
        A file, or a folder (azure_fgo; gaitmap example folder with ``imu_sample.csv`` and, when
        present, ``mocap_sample.csv`` and ``stride_events_sample.csv``).
    format
        One of ``READERS`` (``footnav_csv``, ``gaitmap``, ``azure_fgo``, ``xio``, ``openshoe``,
        ``pyshoe``, ``xsens``, ``ipol``, ``gaitdriven``, ``ximu_cal``, ``delimited``) to force the
        reader; None guesses from the file.
    **options
        Passed to the reader (e.g. ``drop_duplicates=True``, ``rate_hz=...``).

    Returns
    -------
    Recording
        With ``meta["format"]`` the reader used and ``meta["format_guessed"]`` whether it was
        guessed; each foot's ``meta["read_warnings"]`` holds the warnings reading gave (a
        pipeline run lists them in its ``meta["warnings"]``).

    Raises
    ------
    DataNotFoundError
        ``path`` does not exist.
    InvalidInputError
        Unknown ``format``, or a file no known format matches; the message lists the formats.
    """
    p = FilePath(path)
    if format is not None:
        if format not in READERS:
            raise InvalidInputError(f"unknown format {format!r}; known formats: {', '.join(READERS)}", path=str(p))
        if not p.exists():
            raise DataNotFoundError(f"{str(p)!r} does not exist")
        with recording() as caught:
            rec = READERS[format](p, **options)
        guessed = False
    else:
        format, reason, implied = guess_format(p)
        target = implied.pop("_path", p)
        if implied.pop("_needs_rate", False) and "rate_hz" not in options:
            raise InvalidInputError(
                "no header and no time column: 6 numeric columns fit the OpenShoe layout (acc m/s^2, gyr rad/s), "
                "but the file does not say its sampling rate, and a wrong rate scales every distance; pass it: "
                f"load(path, rate_hz=100.0) (command line: --rate-hz 100), or format='openshoe' for the OpenShoe "
                f"data set's {OPENSHOE_RATE_HZ:g} Hz; other column layouts or units: format='delimited' with "
                "columns=... (command line: --format delimited --columns acc=0:3,gyr=3:6 --rate-hz 100)",
                path=str(p),
                field="rate_hz",
            )
        log.info("footnav.load: reading %s as %r (%s)", p, format, reason)
        with recording() as caught:
            rec = READERS[format](target, **{**implied, **options})
        guessed = True
    if caught:  # said once while reading: the run's meta["warnings"] lists them too
        read = [str(w) for w in caught]
        rec = replace(rec, left=_noted(rec.left, read), right=None if rec.right is None else _noted(rec.right, read))
    return replace(rec, meta={**rec.meta, "format": format, "format_guessed": guessed})


def _noted(imu: ImuData, read: list[str]) -> ImuData:
    """``imu`` with the warnings its file gave while read, in ``meta["read_warnings"]``."""
    return replace(imu, meta={**imu.meta, "read_warnings": read})
