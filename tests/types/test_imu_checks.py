"""footnav.core.types.imu_checks: the accelerometer-at-rest check on both sides of g, and its reading
of g from a noisy standstill (the median over the still samples, against numpy on the same data)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import footnav
from footnav.core.errors import DataQualityWarning, InvalidInputError
from footnav.core.types import GRAVITY_MPS2, ImuData


@pytest.fixture(scope="module")
def walk():
    return footnav.simulate("straight", seed=3, distance_m=12.0)


def _quiet(fn, *args, **kwargs):
    with warnings.catch_warnings():
        warnings.simplefilter("error", DataQualityWarning)
        return fn(*args, **kwargs)


@pytest.mark.parametrize("factor", [0.93, 1.07])
def test_seven_percent_off_g_is_a_warning_on_either_side(walk, factor):
    # mutant: imu-rest-warn-one-sided
    imu = walk.left
    with pytest.warns(DataQualityWarning, match=r"m/s\^2 at rest, [+-][67]\.\d % off g"):
        out = ImuData.from_arrays(imu.t, imu.acc * factor, imu.gyr)
    assert out.meta["acc_at_rest"]["off_g_fraction"] == pytest.approx(factor - 1.0, abs=0.005)


@pytest.mark.parametrize("factor", [0.7, 1.3])
def test_thirty_percent_off_g_is_an_error_on_either_side(walk, factor):
    # mutant: imu-rest-error-one-sided
    imu = walk.left
    with pytest.raises(InvalidInputError, match="at rest"):
        ImuData.from_arrays(imu.t, imu.acc * factor, imu.gyr)


@pytest.mark.parametrize("factor", [0.98, 1.02])
def test_two_percent_off_g_says_nothing(walk, factor):
    imu = walk.left
    _quiet(ImuData.from_arrays, imu.t, imu.acc * factor, imu.gyr)


def test_g_at_rest_is_read_from_the_still_samples_of_a_noisy_walk(walk):
    # mutant: imu-rest-all-samples. Noise of 0.3 m/s^2 per axis on a walk 5 % above g: the
    # reading is the median of |f| over the still samples (standstill and stances), not over the walk
    imu = walk.left
    rng = np.random.default_rng(1)
    acc = imu.acc * 1.05 + rng.normal(0.0, 0.3, imu.acc.shape)
    with pytest.warns(DataQualityWarning, match="off g"):
        out = ImuData.from_arrays(imu.t, acc, imu.gyr)
    got = out.meta["acc_at_rest"]["magnitude_mps2"]
    assert got == pytest.approx(1.05 * GRAVITY_MPS2, abs=0.06)
    assert abs(np.median(np.linalg.norm(acc, axis=1)) - got) > 0.05  # the whole walk reads otherwise
