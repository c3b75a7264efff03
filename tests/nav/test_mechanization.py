"""The strapdown mechanization (footnav/nav/mechanization.py) on closed-form motions."""

from __future__ import annotations

import numpy as np

from footnav.nav.mechanization import strapdown

from .conftest import G, _imu


# mutant: mech-bias-sign
# mech-bias-sign: a still sensor that reads only its gyro bias keeps its attitude once the bias
# is subtracted
def test_strapdown_subtracts_the_gyro_bias():
    n, rate = 201, 100.0
    t = np.arange(n) / rate
    bias = np.array([0.01, -0.02, 0.03])
    acc = np.tile([0.0, 0.0, G], (n, 1))
    q, v, p = strapdown(_imu(t, acc, np.tile(bias, (n, 1))), np.array([1.0, 0, 0, 0]), gyro_bias_radps=bias)
    np.testing.assert_allclose(q[-1], [1.0, 0, 0, 0], atol=1e-12)
    np.testing.assert_allclose(p[-1], 0.0, atol=1e-12)


# mutant: mech-loop-swapped-samples
# mech-loop-swapped-samples: without rotation, a force growing linearly in time (jerk j along x)
# gives v = j t^2 / 2 exactly under the trapezoidal / Simpson rule, p = j t^3 / 6 to O(dt^2)
def test_strapdown_integrates_a_linear_force_exactly():
    n, rate, jerk = 201, 100.0, 1.5
    t = np.arange(n) / rate
    acc = np.zeros((n, 3))
    acc[:, 0] = jerk * t
    acc[:, 2] = G
    q, v, p = strapdown(_imu(t, acc, np.zeros((n, 3))), np.array([1.0, 0, 0, 0]))
    np.testing.assert_allclose(v[:, 0], jerk * t**2 / 2, atol=1e-9)
    np.testing.assert_allclose(v[:, 1:], 0.0, atol=1e-9)
    # trapezoid on v = j t^2 / 2: error j T dt^2 / 12 = 2.5e-5 m at T = 2 s
    np.testing.assert_allclose(p[:, 0], jerk * t**3 / 6, atol=3e-5)
