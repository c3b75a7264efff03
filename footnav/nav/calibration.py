"""Sensor calibration from a standstill: gyro bias and accelerometer scale factor.

Zhao et al. (2019), Sec. II-A: the sensor is kept still (about 8 s in their experiments) and two
truths are known there: (1) the angular rate is zero about every axis, (2) the magnitude of the
specific force equals gravity. (1) gives the gyro bias, (2) the accelerometer's scale factor::

    b_gyr = mean(w)                       (rad/s, body frame)
    k_acc = g / |mean(f)|                 (dimensionless; corrected f = k_acc f)

One scale for all three axes: a standstill in one attitude cannot tell the axes' scales apart
(only the magnitude of f is known). ``|mean(f)|`` rather than ``mean(|f|)``: white noise of
standard deviation sigma raises the mean magnitude by about sigma^2 / (2 g) and leaves the
magnitude of the mean unbiased. An accelerometer *bias* along gravity is read as a scale error
too (bias b reads as k = g / (g + b)); the standstill cannot separate them, nor can the paper's.

The pipeline's data flow (DESIGN.md) has a "sync + calibrate" stage before the detector; until it
exists, :class:`~footnav.fusion.step_vector.StepVectorFusion` applies this calibration itself
(``calibration="standstill"``).

References
----------
.. [1] H. Zhao, Z. Wang, S. Qiu, Y. Shen, L. Zhang, K. Tang and G. Fortino, "Heading drift
   reduction for foot-mounted inertial navigation system via multi-sensor fusion and dual-gait
   analysis", IEEE Sensors J., 2019, doi:10.1109/JSEN.2018.2866802.

Examples
--------
>>> rec = footnav.simulate("straight", distance_m=10.0)  # doctest: +SKIP
>>> cal = calibrate_at_rest(rec.left, 0, 150)  # the first 1.5 s are still  # doctest: +SKIP
>>> left = cal.apply(rec.left)  # doctest: +SKIP
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import NDArray

from footnav.core.errors import InvalidInputError
from footnav.core.types import GRAVITY_MPS2, ImuData

__all__ = ["StandstillCalibration", "calibrate_at_rest"]

#: A scale factor this far from 1 is not a MEMS accelerometer's error (datasheets give under 1 %):
#: the range was not still, or the units are wrong. calibrate_at_rest refuses it.
MAX_SCALE_ERROR = 0.1


@dataclass(frozen=True)
class StandstillCalibration:
    """What a standstill says about a sensor (Zhao et al. (2019), Sec. II-A).

    Parameters
    ----------
    acc_scale
        Factor the specific force is multiplied by, dimensionless (g / |mean f|).
    gyro_bias_radps
        Gyro bias in rad/s, body frame, (3,); subtracted from the angular rate.
    start, stop
        The standstill's sample range.
    acc_norm_mps2
        |mean f| over the standstill, m/s^2.
    """

    acc_scale: float
    gyro_bias_radps: NDArray[np.float64]
    start: int
    stop: int
    acc_norm_mps2: float

    def apply(self, imu: ImuData, *, gyro_bias: bool = True) -> ImuData:
        """``imu`` with ``f <- acc_scale f`` and (with ``gyro_bias``) ``w <- w - gyro_bias_radps``.

        The returned data's ``meta["calibration"]`` records what was applied.
        """
        gyr = imu.gyr - self.gyro_bias_radps if gyro_bias else imu.gyr
        meta = {**imu.meta, "calibration": self.as_meta(gyro_bias=gyro_bias)}
        return replace(imu, acc=imu.acc * self.acc_scale, gyr=gyr, meta=meta)

    def as_meta(self, *, gyro_bias: bool = True) -> dict:
        """Plain-Python record (for result meta and JSON)."""
        return {
            "method": "standstill (Zhao et al. 2019, Sec. II-A)",
            "samples": [self.start, self.stop],
            "acc_scale": float(self.acc_scale),
            "acc_norm_mps2": float(self.acc_norm_mps2),
            "gyro_bias_radps": [float(b) for b in self.gyro_bias_radps] if gyro_bias else None,
        }


def calibrate_at_rest(imu: ImuData, start: int = 0, stop: int | None = None) -> StandstillCalibration:
    """Gyro bias and accelerometer scale from the still samples ``start:stop`` (module docstring).

    Parameters
    ----------
    imu
        The recording.
    start, stop
        The standstill's sample range (``stop`` None: to the end).

    Returns
    -------
    StandstillCalibration

    Raises
    ------
    InvalidInputError
        Field ``acc``: the range holds fewer than 2 samples, or |mean f| is more than
        ``MAX_SCALE_ERROR`` from g (the range was not a standstill, or the data are not in m/s^2).

    Notes
    -----
    Zhao et al. (2019), Sec. II-A: ``b_gyr = mean(w)``, ``k_acc = g / |mean(f)|``.
    """
    n = len(imu.t)
    stop = n if stop is None else min(int(stop), n)
    start = max(int(start), 0)
    if stop - start < 2:
        raise InvalidInputError(f"standstill range {start}:{stop} holds fewer than 2 samples", field="acc", index=start)
    f_norm = float(np.linalg.norm(imu.acc[start:stop].mean(axis=0)))
    if not abs(f_norm / GRAVITY_MPS2 - 1.0) <= MAX_SCALE_ERROR:
        raise InvalidInputError(
            f"|mean specific force| over samples {start}:{stop} is {f_norm:.4g} m/s^2, more than "
            f"{MAX_SCALE_ERROR:.0%} from g = {GRAVITY_MPS2} m/s^2: not a standstill, or not in m/s^2",
            field="acc",
            index=start,
        )
    return StandstillCalibration(
        acc_scale=GRAVITY_MPS2 / f_norm,  # k_acc = g / |mean f|
        gyro_bias_radps=imu.gyr[start:stop].mean(axis=0),  # b_gyr = mean w
        start=start,
        stop=stop,
        acc_norm_mps2=f_norm,
    )
