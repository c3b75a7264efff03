"""Estimator tests that kill mutants of ``tools/mutate.py`` the rest of the suite let through.

The motions are closed-form: no rotation, a force growing linearly in time, so the trapezoidal
rule integrates the velocity exactly (v = j t^2 / 2).
"""

from __future__ import annotations

import numpy as np
import pytest

from footnav.core.types import ImuData, StanceResult
from footnav.estimators.madgwick import MadgwickEstimator

G = 9.80665  # m/s^2, written out


@pytest.fixture(scope="module")
def push_and_stop():
    """1 s standing, 1 s pushed along x with a force growing at 1.5 m/s^3, then 1 s "standing"
    with the velocity the push left (0.75 m/s): the ZUPTs must take it out."""
    rate, jerk = 100.0, 1.5
    t = np.arange(301) / rate
    acc = np.tile([0.0, 0.0, G], (len(t), 1))
    push = (t > 1.0) & (t <= 2.0)
    acc[push, 0] = jerk * (t[push] - 1.0)
    acc[t > 2.0, 0] = 0.0
    stance = (t <= 1.0) | (t > 2.0)
    imu = ImuData(t=t, acc=acc, gyr=np.zeros((len(t), 3)))
    est = MadgwickEstimator(beta_radps=1e-9, heading="sensor", gyro_bias="none", use_magnetometer=False)
    return t, jerk, est.estimate(imu, StanceResult(stance))


# madgwick-velocity-rectangle: the velocity is the trapezoidal integral of the force
def test_madgwick_velocity_integrates_a_linear_force_exactly(push_and_stop):
    t, jerk, traj = push_and_stop
    k = int(np.searchsorted(t, 2.0))  # the push's last sample, before any ZUPT
    np.testing.assert_allclose(traj.velocity[: k + 1, 0], jerk * np.clip(t[: k + 1] - 1.0, 0, None) ** 2 / 2, atol=1e-9)
    np.testing.assert_allclose(traj.position[k, 0], jerk / 6, atol=1e-3)


# the ZUPTs take the left-over velocity out and the position stops moving
def test_madgwick_zupts_stop_the_foot(push_and_stop):
    t, jerk, traj = push_and_stop
    assert np.abs(traj.velocity[-1]).max() < 0.01
    late = t > 2.5
    assert np.ptp(traj.position[late, 0]) < 0.01


# madgwick-output-sign (madgwick-innovation-sign survives it, see docs/reliability.md):
# a vertical accelerometer bias (0.05 m/s^2) is learnt during a 3 s stance as the acceleration error
# state; in a 1 s "swing" of the still foot the corrected output then stays put, where the raw integral
# drifts b T^2 / 2 = 25 mm
def test_madgwick_learns_an_accelerometer_bias_at_standstill():
    rate, bias = 100.0, 0.05
    t = np.arange(401) / rate
    acc = np.tile([0.0, 0.0, G + bias], (len(t), 1))
    stance = t <= 3.0
    imu = ImuData(t=t, acc=acc, gyr=np.zeros((len(t), 3)))
    est = MadgwickEstimator(beta_radps=1e-9, heading="sensor", gyro_bias="none", use_magnetometer=False)
    traj = est.estimate(imu, StanceResult(stance))
    # measured 7.4 mm (the bias is partly learnt in 3 s): at most half the raw drift
    assert abs(traj.position[-1, 2]) < 0.0125
    assert abs(traj.velocity[-1, 2]) < 0.025  # raw: b T = 50 mm/s
