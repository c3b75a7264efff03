"""Checks of single samples and their time stamps, shared by a recording (:class:`~footnav.core.types.ImuData`,
:mod:`footnav.core.types.imu_checks`) and an online stream's chunks (:mod:`footnav.pipeline.online_checks`):
time order, sampling gaps, and values no foot-mounted IMU reads. The errors name the sample by its
index in the recording (or the foot's stream), with the same words on both paths."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from footnav.core.errors import InvalidInputError
from footnav.core.types._derived import row_norms
from footnav.core.types.units import GRAVITY_MPS2

__all__ = [
    "ACC_MAX_MPS2",
    "ACC_MEDIAN_BOUNDS_MPS2",
    "GAP_FACTOR",
    "GYR_MAX_RADPS",
    "GYR_PEAK_MAX_RADPS",
    "check_extremes",
    "check_same_rows",
    "check_time_order",
    "find_gaps",
    "gap_message",
]

#: A foot-mounted IMU reads about 1 g of specific force over a recording (the foot stands still
#: much of the time); a median |f| outside these bounds (m/s^2) is not a foot in m/s^2.
ACC_MEDIAN_BOUNDS_MPS2 = (2.5, 30.0)
#: The largest MEMS gyroscope full scale is +-4000 deg/s (70 rad/s). An angular rate held above
#: this (rad/s) for ``PEAK_HOLD_S`` is deg/s read as rad/s. A held peak, not a percentile: on a
#: mostly still recording the few swings are far fewer than 1 % of the samples.
GYR_PEAK_MAX_RADPS = 70.0
#: No foot-mounted IMU reads a specific force above this (m/s^2, 100 g: the largest
#: accelerometer ranges on shoes are +-16 g to +-200 g high-g parts, and a heel strike peaks at
#: 5-30 g) nor an angular rate above ``GYR_MAX_RADPS`` (100 rad/s = 5730 deg/s, beyond the largest
#: MEMS range of 4000 deg/s). A sample beyond either is a corrupt record or a wrong unit:
#: InvalidInputError naming its index (one such sample integrates into a 1e29 m walk).
ACC_MAX_MPS2 = 100.0 * GRAVITY_MPS2
GYR_MAX_RADPS = 100.0

#: A sampling interval longer than GAP_FACTOR x the median interval is reported as a gap. One lost
#: sample makes an interval of about 2 x the median, which time-stamp rounding puts on either side
#: of 2.0; logger jitter without loss stays below ~1.75 x (pyshoe VICON trials: 8.6 ms at 5 ms).
GAP_FACTOR = 1.9


def check_same_rows(n: int, arrays: dict[str, NDArray | None], path: str | None = None) -> None:
    """Refuse arrays (by field name; None skipped) whose row count is not ``n``, the samples of ``t``."""
    for name, arr in arrays.items():
        if arr is not None and len(arr) != n:
            raise InvalidInputError(
                f"has {len(arr)} samples but t has {n}; every array needs one row per sample", field=name, path=path
            )


def check_time_order(
    t: NDArray[np.float64], *, path: str | None = None, offset: int = 0, previous: float | None = None
) -> NDArray[np.float64]:
    """Refuse time stamps that do not increase strictly; returns the intervals (s).

    ``offset`` is the stream index of ``t[0]`` and ``previous`` the time of the sample before it
    (a stream's chunk), so the error names the sample as the whole recording would. With
    ``previous`` the first interval is ``t[0] - previous``.

    Raises
    ------
    InvalidInputError
        ``field="t"``, ``index`` the first sample whose time equals (a duplicate row: drop
        duplicates explicitly) or precedes the one before it.
    """
    full = t if previous is None else np.concatenate(([previous], t))
    dt = np.diff(full)
    first = offset - (0 if previous is None else 1)  # stream index of full[0]
    if not (dt > 0).all():
        j = int(np.argmax(~(dt > 0)))
        i = first + j + 1
        if dt[j] == 0:
            message = (
                f"duplicate time stamp t={full[j + 1]!r} s (same as sample {i - 1}); "
                "drop duplicate rows explicitly (drop_duplicates=True)"
            )
        else:
            message = (
                f"time goes backwards: t[{i}]={full[j + 1]!r} s < t[{i - 1}]={full[j]!r} s; "
                "t must be strictly increasing"
            )
        raise InvalidInputError(message, field="t", index=i, path=path)
    return dt


def find_gaps(dt: NDArray[np.float64], median_dt: float, first_index: int = 1) -> list[tuple[int, float]]:
    """``(index, interval_s)`` of every interval longer than ``GAP_FACTOR`` x ``median_dt``,
    ``index`` the first sample after the gap; ``dt[0]`` ends at sample ``first_index``."""
    idx = np.flatnonzero(dt > GAP_FACTOR * median_dt)
    return [(int(first_index + i), float(dt[i])) for i in idx]


def gap_message(label: str, gaps: list[tuple[int, float]], median_dt: float) -> str:
    """The warning of sampling gaps (:func:`find_gaps`), the same offline and online."""
    return (
        f"{label}: {len(gaps)} sampling gap(s) longer than {GAP_FACTOR:g} x the median interval "
        f"{median_dt * 1e3:.3g} ms (first at index {gaps[0][0]}, {gaps[0][1] * 1e3:.3g} ms); listed in meta['gaps']"
    )


def _acc_median_error(f: float, path: str | None) -> InvalidInputError:
    lo_a = ACC_MEDIAN_BOUNDS_MPS2[0]
    hint = (
        "the data look like g: read them with acc_unit='g'"
        if 0.5 <= f < lo_a
        else ("is the accelerometer in another unit, or is its column mapping wrong?")
    )
    return InvalidInputError(
        f"implausible specific force: median |acc| = {f:.3g} m/s^2, but a foot-mounted IMU reads gravity "
        f"({GRAVITY_MPS2:g} m/s^2) whenever the foot stands still; {hint}",
        field="acc",
        path=path,
    )


def _first_held_start(x: NDArray[np.float64], threshold: float, hold: int) -> int | None:
    """Index of the first sample of the first run of at least ``hold`` values above ``threshold``."""
    above = (x > threshold).astype(np.int64)
    if len(above) < hold:
        return None
    full = np.flatnonzero(np.convolve(above, np.ones(hold, dtype=np.int64), "valid") == hold)
    return int(full[0]) if len(full) else None


def _gyr_unit_error(index: int, path: str | None) -> InvalidInputError:
    # worded by the first held run, not the recording's peak: a stream judging its first chunks
    # says the same as the offline check of the whole recording
    return InvalidInputError(
        f"implausible angular rate: |gyr| held above {GYR_PEAK_MAX_RADPS:g} rad/s from this sample on, beyond any "
        "MEMS gyroscope's range (4000 deg/s); the data look like deg/s: read them with gyr_unit='deg/s'",
        field="gyr",
        index=index,
        path=path,
    )


def check_extremes(
    acc: NDArray[np.float64],
    gyr: NDArray[np.float64],
    *,
    path: str | None = None,
    offset: int = 0,
    hold: int = 3,
    settled: int | None = None,
    acc_median: float | None = None,
    acc_norm: NDArray[np.float64] | None = None,
    gyr_norm: NDArray[np.float64] | None = None,
) -> None:
    """Refuse samples no foot-mounted IMU reads.

    In order: |gyr| held above ``GYR_PEAK_MAX_RADPS`` for ``hold`` samples (deg/s read as rad/s:
    the unit check's error, at the run's first sample); a sample with |gyr| above
    ``GYR_MAX_RADPS`` or |acc| above ``ACC_MAX_MPS2`` (a corrupt record, at that sample) -- unless
    the median |acc| (``acc_median``, else these samples') is not gravity: then the accelerometer
    is in another unit (the unit check's error). ``offset`` is the stream index of the first row;
    only rows before ``settled`` are judged as single samples (a stream's last rows wait for the
    samples after them, which may make them part of a held run).

    Raises
    ------
    InvalidInputError
        ``field`` ``"acc"`` or ``"gyr"``, ``index`` the sample.
    """
    if len(acc) == 0:
        return
    settled = len(acc) if settled is None else settled
    gyr_norm = row_norms(gyr) if gyr_norm is None else gyr_norm
    if gyr_norm.max() > GYR_PEAK_MAX_RADPS:
        start = _first_held_start(gyr_norm, GYR_PEAK_MAX_RADPS, hold)
        if start is not None:
            raise _gyr_unit_error(offset + start, path)
        if settled and gyr_norm[:settled].max() > GYR_MAX_RADPS:
            raise _corrupt("gyr", gyr_norm[:settled], GYR_MAX_RADPS, offset, path)
    acc_norm = row_norms(acc) if acc_norm is None else acc_norm
    if acc_norm.max() > ACC_MAX_MPS2:
        f = float(np.median(acc_norm)) if acc_median is None else acc_median
        if not ACC_MEDIAN_BOUNDS_MPS2[0] <= f <= ACC_MEDIAN_BOUNDS_MPS2[1]:
            raise _acc_median_error(f, path)
        raise _corrupt("acc", acc_norm, ACC_MAX_MPS2, offset, path)


def _corrupt(field: str, norm: NDArray[np.float64], bound: float, offset: int, path: str | None) -> InvalidInputError:
    """The error of the first sample whose magnitude ``norm`` exceeds ``bound`` (SI): a corrupt record."""
    i = int(np.argmax(norm > bound))
    if field == "acc":
        value, limit = f"{norm[i]:.3g} m/s^2 ({norm[i] / GRAVITY_MPS2:.3g} g)", f"{bound / GRAVITY_MPS2:g} g"
    else:
        value, limit = f"{norm[i]:.3g} rad/s ({np.degrees(norm[i]):.3g} deg/s)", f"{bound:g} rad/s"
    return InvalidInputError(
        f"|{field}| = {value}, beyond what a foot-mounted IMU reads (bound {limit}): a corrupt record; remove or "
        "repair it",
        field=field,
        index=offset + i,
        path=path,
    )
