"""The threshold family of stance detectors: the foot is still where a windowed statistic of the
specific force or the angular rate is small (Skog et al., "Zero-velocity detection -- an
algorithm evaluation", IEEE TBME 2010, eq. 10-12; seed 001 section III-A's flat zone).

Each statistic is a centred moving average over ``window_s`` seconds (so the window scales with the
rate and the thresholds do not), and stance runs shorter than ``min_stance_s`` are dropped (a foot
does not stop for 10 ms mid-swing):

========================  =====================================================================
``acc-magnitude`` (MAG)   mean | |f| - g |           < ``acc_tolerance_mps2``
``acc-variance`` (MV)     sqrt(mean ||f - f_mean||^2) < ``acc_std_threshold_mps2``
``ared`` (ARE)            sqrt(mean ||w||^2)          < ``gyr_rms_threshold_radps``
``threshold`` (combined)  mean |w| < ``gyr_threshold_radps`` and MAG < ``acc_tolerance_mps2``
========================  =====================================================================
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from footnav.core.component import StanceDetector, require
from footnav.core.types import GRAVITY_MPS2, ImuData, StanceResult
from footnav.detectors._stance import centred_mean, stance_result, window_samples

__all__ = ["ThresholdDetector", "AccMagnitudeDetector", "AccVarianceDetector", "AredDetector"]


class _WindowedThreshold(StanceDetector):
    """Shared action of the family: compute the statistic, threshold it, post-process."""

    def validate_params(self) -> None:
        for name, value in self.get_params().items():
            if name == "min_stance_s":
                require(isinstance(value, (int, float)) and np.isfinite(value) and value >= 0, self, name, "a number >= 0")
            else:
                require(isinstance(value, (int, float)) and np.isfinite(value) and value > 0, self, name, "a positive number")

    def _stance(self, imu: ImuData, win: int) -> tuple[NDArray[np.bool_], NDArray[np.float64]]:
        """(stance mask before post-processing, per-sample statistic)."""
        raise NotImplementedError

    def detect(self, imu: ImuData) -> StanceResult:
        """Stance mask, foot-flat / heel-off events (stance start / end) and the statistic as score."""
        self.validate_params()
        rate = imu.rate_hz
        win = window_samples(self.window_s, rate)
        mask, score = self._stance(imu, win)
        return stance_result(mask, rate, self.min_stance_s, score, {"detector": self.describe(), "window_samples": win})


def _acc_deviation(imu: ImuData, win: int) -> NDArray[np.float64]:
    return centred_mean(np.abs(np.linalg.norm(imu.acc, axis=1) - GRAVITY_MPS2), win)


class ThresholdDetector(_WindowedThreshold):
    """Stance where the windowed angular-rate norm and | |f| - g | are both small (combined test).

    Parameters
    ----------
    window_s : float
        Length of the centred moving-average window, s.
    gyr_threshold_radps : float
        Stance needs the windowed mean of |w| below this, rad/s.
    acc_tolerance_mps2 : float
        Stance needs the windowed mean of ||f| - g| below this, m/s^2.
    min_stance_s : float
        Stance runs shorter than this are discarded, s.

    Examples
    --------
    >>> det = ThresholdDetector(gyr_threshold_radps=0.6)
    >>> stance = det.detect(imu)  # doctest: +SKIP
    >>> stance.mask, stance.events["foot_flat"]  # doctest: +SKIP
    """

    name = "threshold"

    def __init__(
        self,
        *,
        window_s: float = 0.1,
        gyr_threshold_radps: float = 0.8,
        acc_tolerance_mps2: float = 1.5,
        min_stance_s: float = 0.05,
    ) -> None:
        self.window_s = window_s
        self.gyr_threshold_radps = gyr_threshold_radps
        self.acc_tolerance_mps2 = acc_tolerance_mps2
        self.min_stance_s = min_stance_s

    def _stance(self, imu, win):
        gyr_norm = centred_mean(np.linalg.norm(imu.gyr, axis=1), win)
        mask = (gyr_norm < self.gyr_threshold_radps) & (_acc_deviation(imu, win) < self.acc_tolerance_mps2)
        return mask, gyr_norm


class AccMagnitudeDetector(_WindowedThreshold):
    """Stance where the specific-force magnitude stays near g (Skog 2010 "MAG", eq. 11).

    Parameters
    ----------
    window_s : float
        Length of the centred moving-average window, s.
    acc_tolerance_mps2 : float
        Stance needs the windowed mean of ||f| - g| below this, m/s^2.
    min_stance_s : float
        Stance runs shorter than this are discarded, s.
    """

    name = "acc-magnitude"

    def __init__(self, *, window_s: float = 0.05, acc_tolerance_mps2: float = 0.5, min_stance_s: float = 0.1) -> None:
        self.window_s = window_s
        self.acc_tolerance_mps2 = acc_tolerance_mps2
        self.min_stance_s = min_stance_s

    def _stance(self, imu, win):
        dev = _acc_deviation(imu, win)
        return dev < self.acc_tolerance_mps2, dev


class AccVarianceDetector(_WindowedThreshold):
    """Stance where the specific force barely varies over the window (Skog 2010 "MV", eq. 10).

    Parameters
    ----------
    window_s : float
        Length of the centred moving window, s.
    acc_std_threshold_mps2 : float
        Stance needs sqrt(mean ||f - f_mean||^2) over the window below this, m/s^2.
    min_stance_s : float
        Stance runs shorter than this are discarded, s.
    """

    name = "acc-variance"

    def __init__(self, *, window_s: float = 0.05, acc_std_threshold_mps2: float = 0.5, min_stance_s: float = 0.1) -> None:
        self.window_s = window_s
        self.acc_std_threshold_mps2 = acc_std_threshold_mps2
        self.min_stance_s = min_stance_s

    def _stance(self, imu, win):
        f_mean = centred_mean(imu.acc, win)
        f2_mean = centred_mean(np.einsum("ij,ij->i", imu.acc, imu.acc), win)
        # mean ||f - f_mean||^2 = mean ||f||^2 - ||f_mean||^2
        std = np.sqrt(np.maximum(f2_mean - np.einsum("ij,ij->i", f_mean, f_mean), 0.0))
        return std < self.acc_std_threshold_mps2, std


class AredDetector(_WindowedThreshold):
    """Stance where the angular-rate energy is small (Skog 2010 "ARE", eq. 12).

    Parameters
    ----------
    window_s : float
        Length of the centred moving window, s.
    gyr_rms_threshold_radps : float
        Stance needs sqrt(mean ||w||^2) over the window below this, rad/s.
    min_stance_s : float
        Stance runs shorter than this are discarded, s.
    """

    name = "ared"

    def __init__(self, *, window_s: float = 0.05, gyr_rms_threshold_radps: float = 0.6, min_stance_s: float = 0.05) -> None:
        self.window_s = window_s
        self.gyr_rms_threshold_radps = gyr_rms_threshold_radps
        self.min_stance_s = min_stance_s

    def _stance(self, imu, win):
        rms = np.sqrt(centred_mean(np.einsum("ij,ij->i", imu.gyr, imu.gyr), win))
        return rms < self.gyr_rms_threshold_radps, rms
