"""Any delimited text table of one sensor: the route for files footnav has no named format for.

Format: an optional header row, then one sample per row; comment lines (``#``) and blank lines
anywhere are skipped. The delimiter is sniffed from the first non-comment line (tab, then
semicolon, then comma, else runs of white space) unless given.

Columns (``columns=``, command line ``--columns``) map groups to columns, by 0-based index, a
half-open range ``a:b`` or header names::

    t=0,acc=1:4,gyr=4:7                      # by index (t, acc x/y/z, gyr x/y/z)
    acc=AccX,AccY,AccZ,gyr=GyrX,GyrY,GyrZ    # by header name
    counter=0,acc=4:7,gyr=1:4,mag=7:10       # a packet counter column (not a time)

Groups: ``t`` (1 column), ``counter`` (1: a packet / sample number, never read as a time),
``acc``, ``gyr`` (3 each, required), ``mag`` (3, optional). Without ``columns`` they are found
from the header names (``AccX``, ``acc_x``, ``Accelerometer X (g)``, ``gx``, ``Gyroscope X``,
``time``, ``t_ms``, ``Packet number``, ``SampleIndex`` ...); a headerless table of 6 columns is
acc then gyr, of 7 t, acc, gyr.

Units: the argument (``acc_unit`` ...), else the header's unit in parentheses or brackets
(``(g)``, ``[deg/s]``, ``(ms)``), else the SI default: acc m/s^2, gyr rad/s, t s, mag uT. A unit
that was assumed is recorded in ``meta["units_assumed"]``; when the data then fail the unit
checks (median |acc| far from g, rates no gyroscope measures, a time base no IMU has) the error
says which unit was assumed and the option to give.

Time: the ``t`` column, or, without one, ``t = row / rate_hz`` (``rate_hz`` is then required:
footnav never guesses a rate). A counter column does not give the time; when its steps are not
all equal (lost packets) that is warned about and recorded in ``meta["counter_irregular"]``.
"""

from __future__ import annotations

import re
from collections.abc import Mapping, Sequence
from pathlib import Path as FilePath
from typing import Any

import numpy as np

from footnav.core.errors import DataQualityWarning, InvalidInputError
from footnav.core.types import Recording
from footnav.core.warning_log import warn
from footnav.data.io._text import TextFile, build_imu, changes_of, parse_table, read_text, split_header

__all__ = [
    "read_delimited",
    "auto_columns",
    "parse_columns",
    "sniff_delimiter",
    "header_line",
    "example_command",
    "DELIMITED_GROUPS",
    "DEFAULT_UNITS",
]

FORMAT = "delimited"
#: Group -> number of columns.
DELIMITED_GROUPS = {"t": 1, "counter": 1, "acc": 3, "gyr": 3, "mag": 3}
#: The units assumed when neither the caller nor the header says.
DEFAULT_UNITS = {"t": "s", "acc": "m/s^2", "gyr": "rad/s", "mag": "uT"}
_UNIT_ARG = {"t": "t_unit", "acc": "acc_unit", "gyr": "gyr_unit", "mag": "mag_unit"}
_UNIT_FLAG = {"t": "--t-unit", "acc": "--acc-unit", "gyr": "--gyr-unit", "mag": "mag_unit"}
#: Header unit spellings -> ImuData.from_arrays unit names, per group.
_HEADER_UNITS = {
    "t": {"s": "s", "sec": "s", "ms": "ms", "us": "us", "µs": "us", "ns": "ns"},
    "acc": {"g": "g", "m/s^2": "m/s^2", "m/s2": "m/s^2", "m/s/s": "m/s^2", "m/s²": "m/s^2", "mps2": "m/s^2"},
    "gyr": {"deg/s": "deg/s", "dps": "deg/s", "°/s": "deg/s", "rad/s": "rad/s", "rps": "rad/s"},
    "mag": {"ut": "uT", "µt": "uT", "t": "T", "g": "gauss", "gauss": "gauss", "a.u.": "a.u.", "au": "a.u."},
}
_AXIS_PREFIX = {
    "acc": ("acc", "accel", "accelerometer", "acceleration", "a"),
    "gyr": ("gyr", "gyro", "gyroscope", "angvel", "angularvelocity", "angularrate", "g", "w", "omega"),
    "mag": ("mag", "magn", "magnetometer", "magneticfield", "m"),
}
_TIME = re.compile(r"^(t|time|timestamp|timestamps|ts|sampletime|elapsedtime)(?:[ _\-.]?(s|sec|ms|us|ns))?$")
_COUNTER = {
    "packetnumber",
    "packetcounter",
    "packet",
    "packetno",
    "counter",
    "count",
    "sample",
    "samplenumber",
    "samplecounter",
    "sampleindex",
    "sampleno",
    "index",
    "idx",
    "frame",
    "framenumber",
    "n",
    "seq",
    "sequence",
    "seqno",
}
_UNIT_IN_NAME = re.compile(r"^(.*?)\s*[(\[]([^)\]]*)[)\]]\s*$")


def sniff_delimiter(line: str) -> str | None:
    """Tab, semicolon or comma, the first found in ``line``; None: runs of white space."""
    for d in ("\t", ";", ","):
        if d in line:
            return d
    return None


def _is_comment(line: str) -> bool:
    return line.lstrip().startswith("#")


def header_line(lines: Sequence[str]) -> int | None:
    """0-based index of the first line that is neither blank nor a comment."""
    return next((k for k, s in enumerate(lines) if s.strip() and not _is_comment(s)), None)


def _numeric(cells: Sequence[str]) -> bool:
    try:
        [float(c) for c in cells]
    except ValueError:
        return False
    return bool(cells)


def _classify(name: str) -> tuple[str, str | None, str | None]:
    """Header cell -> (group or "", axis or None, unit as written or None)."""
    m = _UNIT_IN_NAME.match(name.strip())
    base, unit = (m.group(1), m.group(2).strip()) if m else (name.strip(), None)
    low = base.lower().strip()
    tm = _TIME.match(low)
    if tm:
        return "t", None, unit or tm.group(2)
    flat = re.sub(r"[^0-9a-z]", "", low)
    if flat in _COUNTER:
        return "counter", None, None
    if flat and flat[-1] in "xyz":
        for group, prefixes in _AXIS_PREFIX.items():
            if flat[:-1] in prefixes:
                return group, flat[-1], unit
    return "", None, None


def auto_columns(header: Sequence[str]) -> tuple[dict[str, list[int]], dict[str, str]]:
    """Groups found from header names, and the units the header states (as written).

    Only complete groups are returned (acc, gyr, mag need x, y and z); the first column of a kind wins.
    """
    found: dict[str, dict[str | None, int]] = {}
    units: dict[str, str] = {}
    for j, name in enumerate(header):
        group, axis, unit = _classify(name)
        if not group or axis in found.get(group, {}):
            continue
        found.setdefault(group, {})[axis] = j
        if unit is not None:
            units.setdefault(group, unit)
    out: dict[str, list[int]] = {}
    for group, cols in found.items():
        if DELIMITED_GROUPS[group] == 1:
            out[group] = [cols[None]]
        elif all(a in cols for a in "xyz"):
            out[group] = [cols[a] for a in "xyz"]
    return out, {g: u for g, u in units.items() if g in out}


def _spec_items(spec: str | Mapping[str, Any]) -> list[tuple[str, list[Any]]]:
    if isinstance(spec, Mapping):
        items = []
        for group, value in spec.items():
            if isinstance(value, slice):
                value = list(range(value.start or 0, value.stop, value.step or 1))
            elif isinstance(value, str):
                value = [v.strip() for v in value.split(",")]
            elif not isinstance(value, Sequence):
                value = [value]
            items.append((str(group).strip(), list(value)))
        return items
    items = []
    for token in str(spec).split(","):
        token = token.strip()
        if not token:
            continue
        if "=" in token:
            group, _, value = token.partition("=")
            items.append((group.strip(), [value.strip()]))
        elif items:
            items[-1][1].append(token)
        else:
            raise InvalidInputError(
                f"column spec {spec!r} must start with GROUP=...: e.g. t=0,acc=1:4,gyr=4:7", field="columns"
            )
    return items


def parse_columns(
    spec: str | Mapping[str, Any], header: Sequence[str] | None, ncols: int, path: str
) -> dict[str, list[int]]:
    """``"t=0,acc=1:4,gyr=4:7"`` or ``"acc=AccX,AccY,AccZ,..."`` (or a dict) -> {group: column indices}."""
    out: dict[str, list[int]] = {}
    for group, values in _spec_items(spec):
        if group not in DELIMITED_GROUPS:
            raise InvalidInputError(
                f"unknown column group {group!r} in {spec!r}; groups: {', '.join(DELIMITED_GROUPS)}",
                field="columns",
                path=path,
            )
        idx: list[int] = []
        for v in values:
            if isinstance(v, (int, np.integer)):
                idx.append(int(v))
                continue
            text = str(v).strip()
            if re.fullmatch(r"-?\d+", text):
                idx.append(int(text))
            elif re.fullmatch(r"\d+:\d+", text):
                a, b = (int(x) for x in text.split(":"))
                idx.extend(range(a, b))
            elif header is not None and text in header:
                idx.append(list(header).index(text))
            else:
                where = (
                    f"the header's columns are {list(header)}"
                    if header is not None
                    else "the file has no header: use indices"
                )
                raise InvalidInputError(
                    f"column {text!r} of group {group!r} not found; {where}", field="columns", path=path
                )
        if len(idx) != DELIMITED_GROUPS[group]:
            raise InvalidInputError(
                f"group {group!r} needs {DELIMITED_GROUPS[group]} column(s), got {len(idx)} ({values})",
                field="columns",
                path=path,
            )
        bad = [i for i in idx if not 0 <= i < ncols]
        if bad:
            raise InvalidInputError(
                f"column index {bad[0]} of group {group!r} outside the table's {ncols} columns (0..{ncols - 1})",
                field="columns",
                path=path,
            )
        out[group] = idx
    return out


def example_command(path: str, header: Sequence[str] | None, ncols: int) -> str:
    """A one-line ``footnav run`` for a file of this header, to adapt (shown in errors)."""
    names = list(header) if header is not None else [str(j) for j in range(ncols)]
    q = lambda s: s if re.fullmatch(r"[\w.]+", s) else f'"{s}"'  # noqa: E731
    if len(names) >= 7:
        spec = f"t={names[0]},acc={','.join(names[1:4])},gyr={','.join(names[4:7])}"
        rate = ""
    else:
        spec = f"acc={','.join(names[:3])},gyr={','.join(names[3:6])}"
        rate = " --rate-hz 100"
    if header is None:
        spec = "t=0,acc=1:4,gyr=4:7" if len(names) >= 7 else "acc=0:3,gyr=3:6"
    return (
        f"footnav run --left {q(str(path))} --format delimited --columns {q(spec)}{rate} "
        "--acc-unit g --gyr-unit deg/s --out results/x"
    )


def _counter_check(counter: np.ndarray, lines: np.ndarray, path: str, column: str) -> dict[str, Any] | None:
    steps = np.diff(counter)
    if not len(steps):
        return None
    step = float(np.median(steps))
    odd = np.flatnonzero(steps != step)
    if not len(odd):
        return None
    i = int(odd[0]) + 1
    record = {
        "column": column,
        "median_step": step,
        "irregular_steps": int(len(odd)),
        "first_index": i,
        "first_line": int(lines[i]),
    }
    warn(
        f"{path}: counter column {column!r} steps by {step:g} but {len(odd)} time(s) by something else (first at "
        f"index {i}, line {int(lines[i])}: lost packets or a wrap); time = row / rate ignores them; recorded in "
        "meta['counter_irregular']",
        DataQualityWarning,
        stacklevel=4,
    )
    return record


# complexity: one branch per header and unit convention a user's file may have
def read_delimited(  # noqa: C901
    path: Any,
    *,
    columns: str | Mapping[str, Any] | None = None,
    rate_hz: float | None = None,
    acc_unit: str | None = None,
    gyr_unit: str | None = None,
    t_unit: str | None = None,
    mag_unit: str | None = None,
    delimiter: str | None = None,
    drop_duplicates: bool = False,
    acc_full_scale_mps2: float | None = None,
    _format: str = FORMAT,
    _meta: Mapping[str, Any] | None = None,
) -> Recording:
    """Read one sensor from a delimited text table (see the module docstring for the layout).

    Parameters
    ----------
    path
        The text file.
    columns
        Column mapping (``"t=0,acc=1:4,gyr=4:7"``, ``"acc=AccX,AccY,AccZ,gyr=GyrX,GyrY,GyrZ"`` or a
        dict ``{"acc": [1, 2, 3], ...}``); default: found from the header names.
    rate_hz
        Sampling rate when the table has no time column: ``t = row / rate_hz``. Refused when there
        is a time column (which rate would be right?).
    acc_unit, gyr_unit, t_unit, mag_unit
        Units of the groups (default: the header's, else m/s^2, rad/s, s, uT).
    delimiter
        Cell separator (default sniffed: tab, ``;``, ``,``, else white space); ``" "`` means white space.
    drop_duplicates, acc_full_scale_mps2
        As for the other readers.

    Returns
    -------
    Recording
        ``left`` = the sensor (SI, its own axes, ``meta["foot"]`` unknown), no truth;
        ``meta["columns"]`` the mapping used, ``meta["units_assumed"]`` the units nothing stated.

    Raises
    ------
    InvalidInputError
        No acc or gyr columns, an unknown group or column, no time and no ``rate_hz``, a bad
        cell (file, line and column named), a unit the data contradict.
    """
    tf = read_text(path)
    src = tf.path
    # comment lines become blank lines: skipped, line numbers kept
    tf = TextFile(
        path=src, lines=["" if _is_comment(s) else s for s in tf.lines], ends_with_newline=tf.ends_with_newline
    )
    first = header_line(tf.lines)
    if first is None:
        raise InvalidInputError("no data: only comment lines", path=src, line=1)
    delim = (
        (None if delimiter in (" ", "whitespace") else delimiter)
        if delimiter is not None
        else sniff_delimiter(tf.lines[first])
    )
    cells = split_header(tf.lines[first], delim)
    header = None if _numeric(cells) else cells
    start = first if header is None else first + 1
    ncols = len(cells)
    if columns is not None:
        cols = parse_columns(columns, header, ncols, src)
        stated: dict[str, str] = {}
        if header is not None:
            for group, idx in cols.items():
                m = _UNIT_IN_NAME.match(header[idx[0]].strip())
                unit = m.group(2).strip() if m else _classify(header[idx[0]])[2]
                if unit is not None and group in _HEADER_UNITS:
                    stated[group] = unit
        how = "as given"
    elif header is not None:
        cols, stated = auto_columns(header)
        how = "from the header names"
    elif ncols in (6, 7):
        cols = {"acc": [0, 1, 2], "gyr": [3, 4, 5]} if ncols == 6 else {"t": [0], "acc": [1, 2, 3], "gyr": [4, 5, 6]}
        stated, how = {}, f"no header: {ncols} columns taken as {'acc, gyr' if ncols == 6 else 't, acc, gyr'}"
    else:
        cols, stated, how = {}, {}, "no header"
    missing = [g for g in ("acc", "gyr") if g not in cols]
    if missing:
        raise InvalidInputError(
            f"cannot tell which columns hold {' and '.join(missing)} ({how}; columns: "
            f"{header if header is not None else ncols}); map them, e.g.: {example_command(src, header, ncols)}",
            path=src,
            line=first + 1,
            field="columns",
        )
    # units: argument, else the header's, else SI (recorded as assumed)
    given = {"t": t_unit, "acc": acc_unit, "gyr": gyr_unit, "mag": mag_unit}
    units: dict[str, str] = {}
    assumed: dict[str, str] = {}
    for group in ("t", "acc", "gyr", "mag"):
        head = None
        if group in stated:
            head = _HEADER_UNITS[group].get(stated[group]) or _HEADER_UNITS[group].get(stated[group].lower())
            if head is None:
                raise InvalidInputError(
                    f"unknown {group} unit {stated[group]!r} in the header; "
                    f"known: {sorted(set(_HEADER_UNITS[group].values()))}",
                    path=src,
                    line=first + 1,
                    field=group,
                )
        if given[group] is not None:
            units[group] = given[group]
            if head is not None and head != given[group]:
                warn(
                    f"{src}: the header says {group} is in {head}, {_UNIT_ARG[group]}={given[group]!r} overrides it",
                    DataQualityWarning,
                    stacklevel=2,
                )
        elif head is not None:
            units[group] = head
        else:
            units[group] = assumed[group] = DEFAULT_UNITS[group]
    if "t" not in cols:
        assumed.pop("t", None)
    if "mag" not in cols:
        assumed.pop("mag", None)
    names = header if header is not None else [f"column {j}" for j in range(ncols)]
    data, lines = parse_table(tf, start, names, delimiter=delim)
    meta: dict[str, Any] = {"foot": "unknown (one foot)", **dict(_meta or {})}
    if "t" in cols:
        if rate_hz is not None:
            raise InvalidInputError(
                f"rate_hz={rate_hz:g} given, but the file has a time column ({names[cols['t'][0]]!r}); drop rate_hz "
                "(--rate-hz), or map the time column as counter=... to use the rate",
                path=src,
                field="rate_hz",
            )
        t = data[:, cols["t"][0]]
    else:
        if rate_hz is None:
            counter = (
                f" (column {names[cols['counter'][0]]!r} is a packet counter, not a time)" if "counter" in cols else ""
            )
            raise InvalidInputError(
                f"no time column{counter}: the sampling rate is needed, and a wrong rate scales every distance; pass "
                f"it: load(path, rate_hz=100.0) (command line: --rate-hz 100)",
                path=src,
                field="rate_hz",
            )
        if not (np.isfinite(rate_hz) and rate_hz > 0):
            raise InvalidInputError(f"rate_hz={rate_hz!r} is not a finite number > 0", path=src, field="rate_hz")
        t = np.arange(len(data)) / float(rate_hz)
        units["t"] = "s"
        meta["time_source"] = f"row index / {rate_hz:g} Hz (the file has no time column)"
    if "counter" in cols:
        rec = _counter_check(data[:, cols["counter"][0]], lines, src, names[cols["counter"][0]])
        if rec:
            meta["counter_irregular"] = rec
    meta["columns"] = {g: [names[j] for j in idx] for g, idx in cols.items()}
    meta["columns_found"] = how
    if assumed:
        meta["units_assumed"] = assumed
    try:
        imu, _ = build_imu(
            t,
            data[:, cols["acc"]],
            data[:, cols["gyr"]],
            data[:, cols["mag"]] if "mag" in cols else None,
            path=src,
            fmt=_format,
            line_numbers=lines,
            acc_unit=units["acc"],
            gyr_unit=units["gyr"],
            t_unit=units["t"],
            mag_unit=units["mag"],
            drop_duplicates=drop_duplicates,
            acc_full_scale_mps2=acc_full_scale_mps2,
            meta=meta,
        )
    except InvalidInputError as exc:
        group = exc.field if exc.field in assumed else None
        if group is None:
            raise
        new = InvalidInputError("", field=exc.field, index=exc.index, path=exc.path, line=exc.line)
        new.args = (
            f"{exc} (the file does not state the {group} unit: {assumed[group]} was assumed; give "
            f"{_UNIT_ARG[group]}=... (command line: {_UNIT_FLAG[group]}))",
        )
        raise new from None
    return Recording(
        left=imu,
        name=FilePath(src).stem,
        meta={
            "format": _format,
            "source": src,
            **({"rate_hz": float(rate_hz)} if "t" not in cols else {}),
            "columns": meta["columns"],
            "units_converted": imu.meta["units_converted"],
            "changes": changes_of("foot", imu),
        },
    )
