"""Physical constants and unit factors pinned by literal values, never read from the library (issue 17).

A test that takes g from footnav on both sides cannot see g change: here the values are written out,
with their sources, and an estimator is run on a sensor at rest built from the literal value.
"""

import numpy as np
import pytest

import footnav
from footnav.core.types import ImuData, StanceResult
from footnav.estimators.ekf import EkfEstimator
from footnav.estimators.madgwick import MadgwickEstimator

#: Standard gravity, m/s^2: the conventional value of the 3rd CGPM (1901), exact by definition.
STANDARD_GRAVITY = 9.80665


def test_gravity_constant_is_standard_gravity():
    # types.GRAVITY_MPS2's comment claims the CGPM 1901 standard gravity: test the claim
    from footnav.core import types

    assert types.GRAVITY_MPS2 == STANDARD_GRAVITY
    assert footnav.GRAVITY_MPS2 == STANDARD_GRAVITY
    # and it is a plausible Earth gravity: WGS-84 normal gravity (Somigliana) at 45 deg latitude
    lat = np.radians(45.0)
    g_e, k, e2 = 9.7803253359, 0.00193185265241, 0.00669437999013
    g45 = g_e * (1 + k * np.sin(lat) ** 2) / np.sqrt(1 - e2 * np.sin(lat) ** 2)
    assert types.GRAVITY_MPS2 == pytest.approx(g45, abs=0.003)


@pytest.mark.parametrize(
    "field, unit, factor",
    [
        ("acc", "g", 9.80665),
        ("gyr", "deg/s", np.pi / 180.0),
        ("t", "ms", 1e-3),
        ("t", "us", 1e-6),
        ("mag", "gauss", 100.0),
        ("mag", "T", 1e6),
    ],
)
def test_unit_factors_are_the_defined_ones(field, unit, factor):
    n = 200
    t = np.arange(n) * 0.01
    acc = np.tile([0.0, 0.0, STANDARD_GRAVITY], (n, 1))
    gyr = np.zeros((n, 3))
    mag = np.tile([20.0, 0.0, -40.0], (n, 1))  # uT
    raw = {"t": t, "acc": acc, "gyr": gyr + 0.1, "mag": mag}
    raw[field] = raw[field] / factor
    imu = ImuData.from_arrays(raw["t"], raw["acc"], raw["gyr"], raw["mag"], **{f"{field}_unit": unit})
    expected = {"t": t, "acc": acc, "gyr": gyr + 0.1, "mag": mag}[field]
    np.testing.assert_allclose(getattr(imu, field), expected, rtol=1e-12, atol=1e-15)


def _still_sensor(n_stance=100, n_free=400, rate_hz=100.0):
    """A level sensor at rest reading exactly +g up (literal), no rotation; stance only at first."""
    n = n_stance + n_free
    t = np.arange(n) / rate_hz
    imu = ImuData.from_arrays(t, np.tile([0.0, 0.0, STANDARD_GRAVITY], (n, 1)), np.zeros((n, 3)))
    mask = np.zeros(n, bool)
    mask[:n_stance] = True
    return imu, StanceResult(mask)


@pytest.mark.parametrize("estimator", [MadgwickEstimator(), EkfEstimator(smoother="none")], ids=["madgwick", "ekf"])
def test_a_sensor_at_rest_stays_put_through_4_s_without_zupt(estimator):
    # the integration must remove exactly 9.80665 m/s^2: 9.81 instead leaves 0.00335 m/s^2, which
    # is 0.5 * 0.00335 * 4^2 = 27 mm of fall after 4 s without a velocity update
    imu, stance = _still_sensor()
    traj = estimator.estimate(imu, stance)
    assert np.abs(traj.position).max() < 1e-6
    assert np.abs(traj.velocity).max() < 1e-6
