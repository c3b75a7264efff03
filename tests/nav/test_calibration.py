"""footnav.nav.calibration: the standstill estimators on noisy samples, the refusal on both sides.

The reference is the estimator the module's docstring states (Zhao et al. 2019, Sec. II-A):
k = g / |mean f| and b = mean w over the range, computed here with numpy on the same samples.
"""

from __future__ import annotations

import numpy as np
import pytest

from footnav.core.errors import InvalidInputError
from footnav.core.types import GRAVITY_MPS2, ImuData
from footnav.nav.calibration import calibrate_at_rest


def _still(n=20000, scale=1.02, sigma=1.5, bias=(0.01, -0.02, 0.03), seed=3, tilt=(0.3, 0.2)):
    rng = np.random.default_rng(seed)
    up = np.array([np.sin(tilt[1]), -np.sin(tilt[0]) * np.cos(tilt[1]), np.cos(tilt[0]) * np.cos(tilt[1])])
    acc = GRAVITY_MPS2 * up / scale + rng.normal(0.0, sigma, (n, 3))
    gyr = np.asarray(bias) + rng.normal(0.0, 0.05, (n, 3))
    return ImuData(t=np.arange(n) / 100.0, acc=acc, gyr=gyr)


def test_scale_from_noisy_standstill_is_the_magnitude_of_the_mean():
    # mutant: calib-mean-of-norms. With sigma = 1.5 m/s^2 the mean of |f| is biased by
    # ~3 sigma^2 / (2 g) = 0.34 m/s^2 (3.5 %); |mean f| by ~sigma^2/(2 g n) only.
    imu = _still()
    cal = calibrate_at_rest(imu)
    ref = GRAVITY_MPS2 / np.linalg.norm(imu.acc.mean(axis=0))
    assert cal.acc_scale == pytest.approx(ref, rel=1e-12)
    assert cal.acc_scale == pytest.approx(1.02, abs=0.005)  # the truth, within the noise (0.001) of 20000 samples
    biased = GRAVITY_MPS2 / np.linalg.norm(imu.acc, axis=1).mean()
    assert abs(biased - cal.acc_scale) > 0.02  # the two estimators differ here


def test_gyro_bias_is_the_mean_over_the_range_only():
    # mutant: calib-bias-whole-recording
    imu = _still(n=1000)
    gyr = imu.gyr.copy()
    gyr[500:] += 2.0  # the walk after the standstill turns
    imu = ImuData(t=imu.t, acc=imu.acc, gyr=gyr)
    cal = calibrate_at_rest(imu, 100, 400)
    np.testing.assert_allclose(cal.gyro_bias_radps, gyr[100:400].mean(axis=0), rtol=0, atol=1e-15)
    assert cal.start == 100 and cal.stop == 400
    np.testing.assert_allclose(cal.apply(imu).gyr, gyr - gyr[100:400].mean(axis=0), atol=1e-15)
    np.testing.assert_allclose(cal.apply(imu).acc, imu.acc * cal.acc_scale, atol=1e-12)


@pytest.mark.parametrize("scale", [0.85, 1.15])
def test_a_scale_too_far_from_one_is_refused_on_either_side(scale):
    # mutant: calib-one-sided (|f|/g - 1 checked without abs: only the high side refused)
    imu = _still(scale=scale, sigma=0.01)
    with pytest.raises(InvalidInputError, match="more than 10% from g"):
        calibrate_at_rest(imu)


@pytest.mark.parametrize("scale", [0.93, 1.07])
def test_a_scale_within_ten_percent_is_accepted_on_either_side(scale):
    cal = calibrate_at_rest(_still(scale=scale, sigma=0.01))
    assert cal.acc_scale == pytest.approx(scale, rel=1e-3)


def test_fewer_than_two_samples_are_refused():
    with pytest.raises(InvalidInputError, match="fewer than 2"):
        calibrate_at_rest(_still(n=10), 5, 6)
    assert calibrate_at_rest(_still(n=10, sigma=0.01), 5, 7).stop == 7
