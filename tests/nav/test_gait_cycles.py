"""The swing peaks of footnav/nav/gait_cycles.py on hand-built gyro signals."""

from __future__ import annotations

import numpy as np
import pytest

from .conftest import _gait


# mutant: gait-stride-mean, gait-no-max-stride
# gait-stride-mean, gait-no-max-stride: the stride time is the median of the peak intervals
# shorter than max_stride_s (a pause is not a stride)
def test_stride_time_is_the_median_of_intervals_without_pauses():
    from footnav.nav.gait_cycles import swing_peaks

    centres = [1.0, 2.0, 3.0, 4.0, 5.3, 9.3, 13.3]  # intervals 1, 1, 1, 1.3, then two 4 s pauses
    peaks = swing_peaks(_gait(100.0, centres, 14.5).gyr, 100.0)
    np.testing.assert_allclose(peaks.index / 100.0, centres, atol=0.011)
    assert peaks.stride_s == pytest.approx(1.0, abs=0.011)


# mutant: gait-distance-min
# gait-distance-min: once the stride time is known, peaks closer than stride_fraction of it are
# one swing (the larger kept); a second bump 0.4 s after a swing in one of six strides is dropped
def test_a_second_bump_within_a_stride_is_not_a_swing():
    from footnav.nav.gait_cycles import swing_peaks

    centres = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0]
    imu = _gait(100.0, centres, 7.0, extra=[(3.4, 6.0, 0.2)])
    peaks = swing_peaks(imu.gyr, 100.0)
    np.testing.assert_allclose(peaks.index / 100.0, centres, atol=0.011)
