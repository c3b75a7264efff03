"""Threshold stance detector: the foot is still where, over a short window, the angular rate is low
and the specific force is close to gravity.

The classic two-condition test of foot-mounted INS (Skog et al., IEEE TBME 2010, "MAG" and "ARE"
detectors combined; seed 001 section III-A's flat zone): with moving averages over ``window_s``,

    stance_k  <=>  mean |w| < gyr_threshold_radps   and   mean | |f| - g | < acc_tolerance_mps2

Stance runs shorter than ``min_stance_s`` are dropped (a foot does not stop for 10 ms mid-swing).
"""

from __future__ import annotations

import numpy as np
from scipy.ndimage import uniform_filter1d

from footnav.core.component import StanceDetector, require
from footnav.core.types import GRAVITY_MPS2, ImuData, StanceResult
from footnav.detectors._stance import stance_result, window_samples

__all__ = ["ThresholdDetector"]


class ThresholdDetector(StanceDetector):
    """Stance where windowed angular-rate norm and |specific force| - g are both small.

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

    def validate_params(self) -> None:
        for name in ("window_s", "gyr_threshold_radps", "acc_tolerance_mps2"):
            v = getattr(self, name)
            require(isinstance(v, (int, float)) and np.isfinite(v) and v > 0, self, name, "a positive number")
        v = self.min_stance_s
        require(isinstance(v, (int, float)) and np.isfinite(v) and v >= 0, self, "min_stance_s", "a number >= 0")

    def detect(self, imu: ImuData) -> StanceResult:
        """Stance mask, foot-flat / heel-off events (stance start / end) and the windowed gyro norm."""
        self.validate_params()
        rate = imu.rate_hz
        win = window_samples(self.window_s, rate)
        gyr_norm = uniform_filter1d(np.linalg.norm(imu.gyr, axis=1), win, mode="nearest")
        acc_dev = uniform_filter1d(np.abs(np.linalg.norm(imu.acc, axis=1) - GRAVITY_MPS2), win, mode="nearest")
        mask = (gyr_norm < self.gyr_threshold_radps) & (acc_dev < self.acc_tolerance_mps2)
        return stance_result(mask, rate, self.min_stance_s, gyr_norm, {"detector": self.describe(), "window_samples": win})
