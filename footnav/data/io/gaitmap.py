"""gaitmap example data (mad-lab-fau/gaitmap ``example_data/``): both feet, motion capture, gait events.

IMU file (``imu_sample.csv``, ``imu_sample_not_rotated.csv``, ``imu_sample_ic_stride.csv``,
``imu_sample_healthy_stair_up/down.csv``)::

    sensor,left_sensor,right_sensor,left_sensor,...      <- row 1: sensor (first cell may be empty)
    axis,acc_x,acc_x,acc_y,...                           <- row 2: axis (first cell may be empty)
    0,0.88,0.31,2.76,...                                 <- first column: sample index, or time in s

* Columns are found by (sensor, axis), so the interleaved (``imu_sample.csv``) and the grouped
  (``imu_sample_not_rotated.csv``, stair files) layouts both work.
* acc in m/s^2, gyr in **deg/s** (converted to rad/s), both feet on one clock.
* NilsPod accelerometer full scale +-16 g: samples at >= 98 % of it are reported as clipped.
* Body frame = the file's axes (``imu_sample.csv`` is gaitmap's aligned sensor frame,
  ``imu_sample_not_rotated.csv`` the raw sensor axes; both are proper rotations of each other).

Motion capture (``mocap_sample.csv``): two header rows (marker, axis), first column the frame
index at 100 Hz, markers ``L_TOE R_TOE L_FCC R_FCC L_FM5 R_FM5`` (in the file ``R_FM5`` comes before
``L_FM5``: found by name) with x, y, z in **mm** (converted to m). The mocap frame is z up as
recorded (heel ~45 mm above the floor at rest, rising in swing): no rotation is applied.

Stride events (``stride_events_sample.csv``): ``s_id, foot, start, end, ic, tc, min_vel, pre_ic``
in IMU samples.
"""

from __future__ import annotations

import csv
import io
from pathlib import Path as FilePath
from typing import Any

import numpy as np
from numpy.typing import NDArray

from footnav.core.errors import DataQualityWarning, InvalidInputError, InvalidParameterError
from footnav.core.types import GRAVITY_MPS2, FootTruth, Recording
from footnav.core.warning_log import warn
from footnav.data.io._text import TextFile, build_imu, changes_of, parse_table, read_text, remap_indices, split_header

__all__ = ["read_gaitmap", "GAITMAP_RATE_HZ", "GAITMAP_MOCAP_RATE_HZ", "GAITMAP_EVENT_NAMES"]

FORMAT = "gaitmap"
#: NilsPod sampling rate of the example recordings (the ic_stride and ms files use 102.4 Hz).
GAITMAP_RATE_HZ = 204.8
#: Motion capture frame rate of ``mocap_sample.csv``.
GAITMAP_MOCAP_RATE_HZ = 100.0
#: NilsPod accelerometer full scale (README: clips at +-16 g).
NILSPOD_ACC_FULL_SCALE_MPS2 = 16.0 * GRAVITY_MPS2
MM_TO_M = 1e-3
_SENSORS = {"left": "left_sensor", "right": "right_sensor"}
_AXES = ("acc_x", "acc_y", "acc_z", "gyr_x", "gyr_y", "gyr_z")
_MARKER_SIDE = {"left": "L", "right": "R"}
_MARKERS = ("TOE", "FCC", "FM5")
#: Stride-event columns -> footnav event names. ``ic`` (initial contact) is the heel strike,
#: ``tc`` (terminal contact) the toe off, ``min_vel`` (sample of minimum foot velocity, the
#: stride border in gaitmap) mid-stance, reported as ``mid_stance`` (not foot flat, the start of
#: the flat phase, which the file does not give). ``pre_ic`` is the ``ic`` of
#: the stride before, so it adds heel strikes (the first one of each walk) to ``ic``.
GAITMAP_EVENT_NAMES = {"ic": "heel_strike", "pre_ic": "heel_strike", "tc": "toe_off", "min_vel": "mid_stance"}
_EVENT_COLUMNS = ("foot", "start", "end", "ic", "tc", "min_vel")


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def _two_row_header(tf: TextFile, what: str) -> list[tuple[str, str]]:
    """(row 1, row 2) name pairs of a two-row header, e.g. ("left_sensor", "acc_x")."""
    if len(tf.lines) < 3:
        raise InvalidInputError(
            f"expected two header rows ({what}, axis) and data rows, found {len(tf.lines)} line(s)",
            path=tf.path,
            line=len(tf.lines),
        )
    top = split_header(tf.lines[0], ",")
    axis = split_header(tf.lines[1], ",")
    if len(top) != len(axis):
        raise InvalidInputError(
            f"header rows have {len(top)} and {len(axis)} columns; expected the same number", path=tf.path, line=2
        )
    if len(axis) > 1 and _is_number(axis[1]):
        raise InvalidInputError(
            "second line is data, not an axis header row: single-header gaitmap files (e.g. "
            "imu_sample_ms_left.csv, one foot, columns index,acc_x,...) are not supported",
            path=tf.path,
            line=2,
        )
    return list(zip(top, axis))


def _time_from_first_column(
    col0: NDArray[np.float64], rate_hz: float, time_column: str, path: str
) -> tuple[NDArray[np.float64], dict[str, Any]]:
    """Sample index -> index / rate; time in s kept (and its rate compared with ``rate_hz``)."""
    if time_column not in ("auto", "index", "seconds"):
        raise InvalidParameterError(f"time_column must be 'auto', 'index' or 'seconds', got {time_column!r}")
    if time_column == "auto":
        steps = np.diff(col0)
        is_index = bool(np.all(col0 == np.round(col0))) and len(steps) > 0 and float(np.median(steps)) == 1.0
        time_column = "index" if is_index else "seconds"
    if time_column == "index":
        return col0 / rate_hz, {"time_source": f"first column = sample index, t = index / {rate_hz:g} Hz"}
    steps = np.diff(col0)
    info: dict[str, Any] = {"time_source": "first column = time in s"}
    if len(steps):
        file_rate = 1.0 / float(np.median(steps)) if np.median(steps) > 0 else float("nan")
        info["rate_hz_from_time_column"] = file_rate
        if not np.isclose(file_rate, rate_hz, rtol=0.01):
            warn(
                f"{path}: the time column gives {file_rate:.6g} Hz but rate_hz={rate_hz:g}; the time column is used",
                DataQualityWarning,
                stacklevel=3,
            )
    return col0, info


def _read_mocap(
    path: Any, rate_hz: float, marker: str
) -> tuple[dict[str, tuple[NDArray[np.float64], NDArray[np.float64]]], dict[str, Any]]:
    tf = read_text(path, what="motion capture file")
    header = _two_row_header(tf, "marker")
    names = [f"{m}_{a}" if m else "frame" for m, a in header]
    data, _ = parse_table(tf, 2, names, delimiter=",", allow_missing=True)
    index = {h: j for j, h in enumerate(header)}
    t = data[:, 0] / rate_hz
    markers = _MARKERS if marker == "mean" else (marker,)
    out = {}
    missing = {}
    for foot, side in _MARKER_SIDE.items():
        tracks = []
        for m in markers:
            cols = [index.get((f"{side}_{m}", a)) for a in ("x", "y", "z")]
            if None in cols:
                found = sorted({h[0] for h in header if h[0]})
                raise InvalidInputError(
                    f"no columns {side}_{m} x,y,z; markers in the file: {found}",
                    path=tf.path,
                    line=1,
                    field=f"{side}_{m}",
                )
            tracks.append(data[:, cols] * MM_TO_M)
        pos = np.mean(tracks, axis=0)
        missing[foot] = int(np.isnan(pos).any(axis=1).sum())
        out[foot] = (t, pos)
    meta = {
        "source": tf.path,
        "rate_hz": rate_hz,
        "marker": "mean of " + ", ".join(_MARKERS) if marker == "mean" else marker,
        "unit_converted": "mm -> m",
        "missing_samples": missing,
    }
    return out, meta


def _read_events(path: Any) -> dict[str, dict[str, Any]]:
    tf = read_text(path, what="stride events file")
    rows = list(csv.reader(io.StringIO("\n".join(tf.lines))))
    header = [c.strip() for c in rows[0]]
    missing = [c for c in _EVENT_COLUMNS if c not in header]
    if missing:
        raise InvalidInputError(f"missing columns {missing}; found {header}", path=tf.path, line=1)
    col = {c: header.index(c) for c in header}
    numeric = [c for c in ("start", "end", "ic", "tc", "min_vel", "pre_ic") if c in col]
    per_foot: dict[str, dict[str, list]] = {f: {c: [] for c in numeric} for f in _SENSORS}
    for k, row in enumerate(rows[1:], start=2):
        if not any(c.strip() for c in row):
            continue
        if len(row) != len(header):
            raise InvalidInputError(f"expected {len(header)} columns {header}, found {len(row)}", path=tf.path, line=k)
        foot = row[col["foot"]].strip()
        if foot not in per_foot:
            raise InvalidInputError(f"foot {foot!r}; expected 'left' or 'right'", path=tf.path, line=k, field="foot")
        for c in numeric:
            cell = row[col[c]].strip()
            try:
                v = float(cell) if cell else np.nan
            except ValueError:
                raise InvalidInputError(
                    f"non-numeric value {cell!r} in column {c!r}", path=tf.path, line=k, field=c
                ) from None
            if np.isfinite(v) and v != round(v):
                raise InvalidInputError(f"event {c}={v!r} is not a whole sample index", path=tf.path, line=k, field=c)
            per_foot[foot][c].append(v)
    out = {}
    for foot, cols in per_foot.items():
        arr = {c: np.asarray(v, dtype=np.float64) for c, v in cols.items()}
        events: dict[str, set] = {}
        n_missing = 0
        for c, name in GAITMAP_EVENT_NAMES.items():
            if c not in arr:
                continue
            vals = arr[c]
            n_missing += int(np.isnan(vals).sum())
            events.setdefault(name, set()).update(int(v) for v in vals[np.isfinite(vals)])
        out[foot] = {
            "events": {k: np.array(sorted(v), dtype=np.int64) for k, v in events.items()},
            "strides": np.column_stack([arr["start"], arr["end"]]),
            "missing_events": n_missing,
            "source": tf.path,
        }
    return out


def read_gaitmap(
    imu_path: Any,
    mocap_path: Any = None,
    events_path: Any = None,
    *,
    rate_hz: float = GAITMAP_RATE_HZ,
    mocap_rate_hz: float = GAITMAP_MOCAP_RATE_HZ,
    marker: str = "FCC",
    time_column: str = "auto",
    gyr_unit: str = "deg/s",
    drop_duplicates: bool = False,
    acc_full_scale_mps2: float | None = NILSPOD_ACC_FULL_SCALE_MPS2,
) -> Recording:
    """Read a gaitmap example recording: both feet, optionally motion capture and stride events.

    Parameters
    ----------
    imu_path
        IMU file with two header rows (sensor, axis); see the module docstring.
    mocap_path
        ``mocap_sample.csv`` (optional): foot position truth for both feet.
    events_path
        ``stride_events_sample.csv`` (optional): gait events for both feet.
    rate_hz
        IMU sampling rate (204.8 Hz; 102.4 Hz for ``imu_sample_ic_stride.csv`` -- the file does not
        say, so pass it), used when the first column is a sample index.
    mocap_rate_hz
        Motion capture frame rate (100 Hz).
    marker
        Marker giving each foot's truth position: ``"FCC"`` (heel, default), ``"TOE"``,
        ``"FM5"`` (5th metatarsal head) or ``"mean"`` (mean of the three). The IMU sits on the
        lateral side of the shoe, not at a marker: expect a lever-arm offset of a few cm.
    time_column
        ``"auto"`` (integer values with step 1 -> sample index, else seconds), ``"index"`` or
        ``"seconds"``.
    gyr_unit
        Gyroscope unit of the file (deg/s), converted to rad/s.
    drop_duplicates
        Drop rows repeating the previous time stamp (recorded); without it they raise.
    acc_full_scale_mps2
        Accelerometer full scale for clipping detection (NilsPod: 16 g).

    Returns
    -------
    Recording
        ``left``/``right`` ImuData in SI units and the file's sensor axes. With mocap or events,
        ``truth_left``/``truth_right`` are FootTruth with ``frame="mocap"`` (z up, m) at the
        mocap times and ``events`` (``heel_strike`` = ``ic`` and ``pre_ic``, ``toe_off`` = ``tc``,
        ``mid_stance`` = ``min_vel``) as IMU sample indices; the stride borders
        (``start``, ``end``) are in ``truth.meta["strides"]``.

    Notes
    -----
    Time alignment: the mocap frames are put on the IMU clock as ``t = frame / mocap_rate_hz``,
    assuming both systems start together (the published files are synchronised: 3,870 mocap
    frames = 38.70 s, 7,928 IMU samples = 38.71 s; heel strikes of the event file fall on heel
    marker minima under this assumption).
    """
    tf = read_text(imu_path, what="IMU file")
    header = _two_row_header(tf, "sensor")
    names = ["index/time"] + [f"{s}.{a}" for s, a in header[1:]]
    data, lines = parse_table(tf, 2, names, delimiter=",")
    t, time_info = _time_from_first_column(data[:, 0], rate_hz, time_column, tf.path)
    index = {h: j for j, h in enumerate(header)}
    feet: dict[str, Any] = {}
    keeps: dict[str, Any] = {}
    for foot, sensor in _SENSORS.items():
        cols = [index.get((sensor, a)) for a in _AXES]
        if all(c is None for c in cols):
            continue
        if None in cols:
            miss = [a for a, c in zip(_AXES, cols) if c is None]
            raise InvalidInputError(f"{sensor} lacks columns {miss}", path=tf.path, line=2, field=sensor)
        imu, keep = build_imu(
            t,
            data[:, cols[:3]],
            data[:, cols[3:]],
            path=tf.path,
            fmt=FORMAT,
            line_numbers=lines,
            acc_unit="m/s^2",
            gyr_unit=gyr_unit,
            drop_duplicates=drop_duplicates,
            acc_full_scale_mps2=acc_full_scale_mps2,
            meta={"foot": foot, "sensor_column": sensor, **time_info},
        )
        feet[foot] = imu
        keeps[foot] = keep
    if not feet:
        raise InvalidInputError(
            f"no left_sensor/right_sensor columns {list(_AXES)} in the header; found {sorted({h[0] for h in header})}",
            path=tf.path,
            line=1,
        )
    if "left" not in feet:
        raise InvalidInputError(
            "no left_sensor columns; a one-foot recording must be the left foot", path=tf.path, line=1
        )

    files = {"imu": tf.path}
    mocap = mocap_meta = events = None
    if mocap_path is not None:
        if marker not in _MARKERS + ("mean",):
            raise InvalidParameterError(f"marker must be one of {_MARKERS + ('mean',)}, got {marker!r}")
        mocap, mocap_meta = _read_mocap(mocap_path, mocap_rate_hz, marker)
        files["mocap"] = mocap_meta["source"]
    if events_path is not None:
        events = _read_events(events_path)
        files["events"] = events[next(iter(events))]["source"]

    truths: dict[str, FootTruth | None] = {"left": None, "right": None}
    for foot in feet:
        if mocap is None and events is None:
            continue
        t_ref, pos = mocap[foot] if mocap is not None else (np.empty(0), np.empty((0, 3)))
        ev = {} if events is None else {k: remap_indices(v, keeps[foot]) for k, v in events[foot]["events"].items()}
        meta: dict[str, Any] = {
            "time_alignment": "mocap frame / mocap_rate_hz on the IMU clock, assuming both start together"
        }
        if mocap is not None:
            meta.update(
                position_source=f"motion capture marker {_MARKER_SIDE[foot]}_{mocap_meta['marker']}"
                if marker != "mean"
                else f"motion capture, {mocap_meta['marker']} markers of the {foot} foot",
                frame_note="mocap frame, z up as recorded (no rotation applied)",
                lever_arm_note="IMU on the lateral shoe, not at the marker: offset of a few cm",
                missing_samples=mocap_meta["missing_samples"][foot],
                mocap=mocap_meta,
            )
        if events is not None:
            meta.update(
                events_source="gaitmap stride events (mocap-derived), " + events[foot]["source"],
                event_mapping={"ic": "heel_strike", "pre_ic": "heel_strike", "tc": "toe_off", "min_vel": "mid_stance"},
                strides=remap_indices(events[foot]["strides"].astype(np.int64), keeps[foot]),
                missing_events=events[foot]["missing_events"],
            )
        truths[foot] = FootTruth(t=t_ref, position=pos, events=ev, frame="mocap", meta=meta)

    changes = [c for foot, imu in feet.items() for c in changes_of(foot, imu)]
    return Recording(
        left=feet["left"],
        right=feet.get("right"),
        truth_left=truths["left"],
        truth_right=truths["right"],
        name=FilePath(tf.path).stem,
        meta={
            "format": FORMAT,
            "source": tf.path,
            "files": files,
            "rate_hz": rate_hz,
            **time_info,
            "units_converted": {
                **feet["left"].meta["units_converted"],
                **({"mocap": "mm -> m"} if mocap is not None else {}),
            },
            "changes": changes,
        },
    )
