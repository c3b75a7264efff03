"""x-io Technologies Gait-Tracking CSV (xioTechnologies/Gait-Tracking): one foot, closed loops.

Format::

    Time (s),Gyroscope X (deg/s),Gyroscope Y (deg/s),Gyroscope Z (deg/s),Accelerometer X (g),...
    0,0.2509459,-0.2747676,0.2215545,-0.3716461,0.3461154,0.8569804

* Columns found by name; the unit in parentheses is read from the header and converted to SI
  (g -> m/s^2, deg/s -> rad/s; ``Magnetometer X (uT)`` columns are read when present).
* Real time stamps (~400 Hz) with gaps (reported by ImuData in ``meta["gaps"]``) and exact
  duplicate rows (dt == 0): an error naming file, line and index of the first one, unless
  ``drop_duplicates=True`` (then dropped and counted in ``meta["duplicates_dropped"]``).
* Body frame = the sensor's axes as logged.
* Truth: the walks end where they started, ``FootTruth(closed_loop=True)`` with no positions.
"""

from __future__ import annotations

import re
from pathlib import Path as FilePath
from typing import Any

import numpy as np

from footnav.core.errors import InvalidInputError
from footnav.core.types import FootTruth, Recording
from footnav.data.io._text import build_imu, changes_of, parse_table, read_text, split_header

__all__ = ["read_xio", "XIO_HEADER"]

FORMAT = "xio"
#: The header of the published files.
XIO_HEADER = (
    "Time (s)",
    "Gyroscope X (deg/s)",
    "Gyroscope Y (deg/s)",
    "Gyroscope Z (deg/s)",
    "Accelerometer X (g)",
    "Accelerometer Y (g)",
    "Accelerometer Z (g)",
)
_COLUMN = re.compile(r"^(Time|Gyroscope|Accelerometer|Magnetometer)\s*([XYZ])?\s*\(([^)]*)\)$")
#: Header unit spellings -> ImuData.from_arrays unit names.
_UNITS = {
    "s": "s",
    "ms": "ms",
    "deg/s": "deg/s",
    "dps": "deg/s",
    "°/s": "deg/s",
    "rad/s": "rad/s",
    "g": "g",
    "m/s^2": "m/s^2",
    "m/s/s": "m/s^2",
    "m/s2": "m/s^2",
    "uT": "uT",
    "µT": "uT",
    "a.u.": "a.u.",
    "gauss": "gauss",
}


def read_xio(path: Any, *, drop_duplicates: bool = False, acc_full_scale_mps2: float | None = None) -> Recording:
    """Read an x-io Gait-Tracking CSV file (one foot).

    Parameters
    ----------
    path
        The CSV file (header ``Time (s), Gyroscope X/Y/Z (deg/s), Accelerometer X/Y/Z (g)``).
    drop_duplicates
        Drop rows repeating the previous time stamp; without it the first one raises
        InvalidInputError naming file, line and sample index. The published files hold 205
        (short_walk) and 252 (long_walk) exact duplicate rows.
    acc_full_scale_mps2
        Accelerometer full scale for clipping detection, if known (not documented).

    Returns
    -------
    Recording
        ``left`` = the foot (SI units, sensor axes), ``truth_left`` = FootTruth with empty ``t``
        and ``position`` and ``closed_loop=True`` (the walk returns to its start).
    """
    tf = read_text(path)
    header = split_header(tf.lines[0], ",")
    cols: dict[tuple[str, str | None], int] = {}
    units: dict[str, str] = {}
    for j, name in enumerate(header):
        m = _COLUMN.match(name)
        if not m:
            raise InvalidInputError(
                f"unknown column {name!r}; expected x-io columns like {', '.join(XIO_HEADER)}",
                path=tf.path,
                line=1,
                field=name,
            )
        qty, axis, unit = m.group(1), m.group(2), m.group(3).strip()
        if unit not in _UNITS:
            raise InvalidInputError(f"unknown unit {unit!r} in column {name!r}", path=tf.path, line=1, field=name)
        if units.setdefault(qty, _UNITS[unit]) != _UNITS[unit]:
            raise InvalidInputError(
                f"mixed units for {qty}: {units[qty]!r} and {unit!r}", path=tf.path, line=1, field=name
            )
        cols[(qty, axis)] = j
    needed = [("Time", None)] + [(q, a) for q in ("Gyroscope", "Accelerometer") for a in "XYZ"]
    missing = [f"{q} {a}" if a else q for q, a in needed if (q, a) not in cols]
    if missing:
        raise InvalidInputError(f"missing columns {missing}; found {header}", path=tf.path, line=1)
    has_mag = all(("Magnetometer", a) in cols for a in "XYZ")
    data, lines = parse_table(tf, 1, header, delimiter=",")

    def block(q: str):
        return data[:, [cols[(q, a)] for a in "XYZ"]]

    imu, _ = build_imu(
        data[:, cols[("Time", None)]],
        block("Accelerometer"),
        block("Gyroscope"),
        block("Magnetometer") if has_mag else None,
        path=tf.path,
        fmt=FORMAT,
        line_numbers=lines,
        t_unit=units["Time"],
        acc_unit=units["Accelerometer"],
        gyr_unit=units["Gyroscope"],
        mag_unit=units.get("Magnetometer", "uT"),
        drop_duplicates=drop_duplicates,
        acc_full_scale_mps2=acc_full_scale_mps2,
        meta={"foot": "unknown (one foot)"},
    )
    truth = FootTruth(
        t=np.empty(0),
        position=np.empty((0, 3)),
        closed_loop=True,
        meta={"source": tf.path, "closed_loop_source": "publisher: the walk ends where it started"},
    )
    return Recording(
        left=imu,
        truth_left=truth,
        name=FilePath(tf.path).stem,
        meta={
            "format": FORMAT,
            "source": tf.path,
            "units_converted": imu.meta["units_converted"],
            "changes": changes_of("foot", imu),
        },
    )
