"""footnav.data.io.pyshoe: which way up the sensor is, read from the samples at rest only (still
*and* |acc| within 1 m/s^2 of g, on both sides), on crafted samples."""

from __future__ import annotations

import numpy as np

from footnav.core.types import GRAVITY_MPS2
from footnav.data.io.pyshoe import _gravity_z_sign


def test_the_sign_comes_from_the_rest_samples_only():
    # mutant: pyshoe-rest-one-sided, pyshoe-rest-or. 30 rest samples upside down (z = -g), then
    # 200 still samples far below g (z = +2: a foot lifted, |f| - g = -7.8) and 200 turning ones
    # reading +g: neither kind is rest, and both would turn the mean's sign
    rest = np.tile([0.0, 0.0, -GRAVITY_MPS2], (30, 1))
    light = np.tile([0.0, 0.0, 2.0], (200, 1))
    turning = np.tile([0.0, 0.0, GRAVITY_MPS2], (200, 1))
    acc = np.vstack([rest, light, turning])
    gyr = np.vstack([np.zeros((430 - 200, 3)), np.tile([0.0, 5.0, 0.0], (200, 1))])
    sign, how = _gravity_z_sign(acc, gyr)
    assert sign == -1.0 and "over 30 rest samples" in how


def test_too_few_rest_samples_fall_back_to_the_whole_trial():
    acc = np.vstack([np.tile([0.0, 0.0, -GRAVITY_MPS2], (10, 1)), np.tile([0.0, 0.0, 3.0], (50, 1))])
    sign, how = _gravity_z_sign(acc, np.zeros((60, 3)))
    assert sign == 1.0 and "whole trial" in how
