"""A complete third-party footnav plugin: one stance detector, one hook."""

from __future__ import annotations

import numpy as np

import footnav


class GyroNormDetector(footnav.StanceDetector):
    """Stance wherever the angular-rate norm is below a threshold, sample by sample.

    Parameters
    ----------
    threshold_radps : float
        Stance needs |w| below this, rad/s.
    """

    name = "example-gyro"

    def __init__(self, *, threshold_radps: float = 0.6) -> None:
        self.threshold_radps = threshold_radps

    def detect(self, imu: footnav.ImuData) -> footnav.StanceResult:
        norm = np.linalg.norm(imu.gyr, axis=1)
        return footnav.StanceResult(mask=norm < self.threshold_radps, score=norm, meta={"detector": self.describe()})


@footnav.hookimpl
def footnav_register_detectors(register):
    register(GyroNormDetector)
