"""Initial alignment from a standstill: roll and pitch from gravity, gyro bias from the mean rate.

With the foot still, the accelerometer measures f^b = C_b^n' [0, 0, g]; for C_b^n = Rz(yaw)
Ry(pitch) Rx(roll) that gives roll = atan2(f_y, f_z) and pitch = atan2(-f_x, sqrt(f_y^2 + f_z^2))
(Groves, *Principles of GNSS, Inertial, and Multisensor Integrated Navigation*, 2nd ed., eq. 5.101).
Heading is unobservable without a magnetometer and is set to zero. The mean angular rate of the
standstill is the gyro bias (Zhao et al. (2019), section II-A, "initial calibration").

A detected stance is not always a true standstill: a foot about to lift, or shifting weight,
already turns at a few hundredths of a rad/s, and averaging those samples puts motion into the
bias. Only the samples whose angular-rate norm is below ``still_gyr_max_radps`` are used.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from footnav.core.errors import DataQualityWarning, InvalidInputError
from footnav.core.warning_log import warn
from footnav.nav import quaternion as quat

__all__ = ["Alignment", "align_at_rest", "align_first_stance"]


@dataclass(frozen=True)
class Alignment:
    """Result of :func:`align_at_rest`: attitude [w, x, y, z] body -> nav (yaw 0), gyro bias (rad/s),
    the sample range and how many of its samples were still enough to be used."""

    quaternion: NDArray[np.float64]
    gyro_bias_radps: NDArray[np.float64]
    start: int
    stop: int
    n_used: int


#: Fewest still samples an alignment accepts.
MIN_STILL_SAMPLES = 10


def align_at_rest(
    acc: NDArray[np.float64],
    gyr: NDArray[np.float64],
    start: int = 0,
    stop: int | None = None,
    *,
    still_gyr_max_radps: float = np.inf,
) -> Alignment:
    """Level the sensor and estimate the gyro bias from the still samples of ``start:stop``.

    Parameters
    ----------
    acc
        Specific force in m/s^2, body frame, (N, 3).
    gyr
        Angular rate in rad/s, body frame, (N, 3).
    start, stop
        The standstill's sample range.
    still_gyr_max_radps
        Only samples with |w| below this (rad/s) are used; when fewer than ``MIN_STILL_SAMPLES``
        are, the whole range is.
    """
    stop = len(acc) if stop is None else stop
    if stop <= start:
        raise InvalidInputError(f"empty standstill range {start}:{stop}", field="acc", index=start)
    still = np.linalg.norm(gyr[start:stop], axis=1) < still_gyr_max_radps
    if still.sum() < MIN_STILL_SAMPLES:
        still[:] = True
    f = np.mean(acc[start:stop][still], axis=0)
    roll = np.arctan2(f[1], f[2])
    pitch = np.arctan2(-f[0], np.hypot(f[1], f[2]))
    return Alignment(
        quaternion=quat.from_euler(roll, pitch, 0.0),
        gyro_bias_radps=np.mean(gyr[start:stop][still], axis=0),
        start=int(start),
        stop=int(stop),
        n_used=int(still.sum()),
    )


def bridged_gaps(gaps, start: int) -> list[tuple[int, float]]:
    """The sampling gaps (``meta["gaps"]``: ``(index, interval_s)``) an estimate starting at sample
    ``start`` integrates across."""
    return [(int(i), float(dt)) for i, dt in gaps if i > start]


def bridged_gaps_message(source: str | None, gaps: list[tuple[int, float]]) -> str:
    """The warning of :func:`bridged_gaps` (the offline estimate's and the online stream's)."""
    # the strapdown step spans a gap as one interval: right in stance, a guess in swing
    longest = max(gaps, key=lambda g: g[1])
    return (
        f"{source or 'ImuData'}: the filter integrates across {len(gaps)} sampling gap(s) "
        f"(longest {longest[1] * 1e3:.3g} ms before index {longest[0]}); positions after a gap in a swing "
        "are less certain; listed in the trajectory's meta['gaps_bridged']"
    )


def align_first_stance(imu, stance, *, still_gyr_max_radps: float, stacklevel: int = 3) -> tuple[int, Alignment, dict]:
    """Check a stance mask against its recording and align at its first stance phase.

    What every per-foot estimator does first: the mask must have one value per sample and at
    least one stance; a recording that does not start at standstill starts its estimate at the
    first stance (DataQualityWarning, ``meta["estimate_start_index"]``); sampling gaps the
    integration will cross are listed (DataQualityWarning, ``meta["gaps_bridged"]``).

    Returns
    -------
    start, alignment, meta
        Index of the first stance sample, :class:`Alignment` there, and what to record.

    Raises
    ------
    InvalidInputError
        The mask's length differs from the recording's, or it has no stance (field
        ``stance.mask``).
    """
    source = imu.meta.get("source")
    if len(stance.mask) != imu.n_samples:
        raise InvalidInputError(
            f"stance mask has {len(stance.mask)} samples but the IMU data has {imu.n_samples}",
            field="stance.mask",
            path=source,
        )
    steps = stance.intervals
    if len(steps) == 0:
        raise InvalidInputError(
            "no stance phase detected, so the filter cannot be aligned or aided; "
            "check the detector's thresholds against this recording",
            field="stance.mask",
            path=source,
        )
    meta: dict = {}
    s0, e0 = int(steps[0, 0]), int(steps[0, 1])
    if s0 > 0:
        meta["estimate_start_index"] = s0
        warn(
            f"{source or 'ImuData'}: recording does not start at standstill; the estimate "
            f"starts at the first stance phase (index {s0}) and holds that state before it",
            DataQualityWarning,
            stacklevel=stacklevel,
        )
    align = align_at_rest(imu.acc, imu.gyr, s0, e0, still_gyr_max_radps=still_gyr_max_radps)
    meta["alignment_samples"] = [s0, e0, align.n_used]
    gaps = bridged_gaps(imu.meta.get("gaps", ()), s0)
    if gaps:
        meta["gaps_bridged"] = gaps
        warn(bridged_gaps_message(source, gaps), DataQualityWarning, stacklevel=stacklevel)
    return s0, align, meta
