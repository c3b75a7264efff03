"""simulate(stance_twist_deg=...): the shoe's twist about the leg in flat-foot stance."""

import math

import numpy as np
import pytest

from footnav import simulate
from footnav.core.errors import InvalidParameterError
from footnav.nav import quaternion as quat

TURNING = {"segments": [(3.0, 90.0), (2.0, -60.0), (2.0, 0.0)], "standstill_s": 1.0}
MOUNT = (10.0, -25.0, 40.0)


def _yaw_between(q_a: np.ndarray, q_b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Rotation q_a q_b^-1 (nav axes) as (angle about the vertical, tilt part), rad, per row."""
    inv = q_b * np.array([1.0, -1.0, -1.0, -1.0])
    d = quat.multiply(q_a, inv)
    d = d * np.sign(d[:, :1])
    return 2 * np.arctan2(d[:, 3], d[:, 0]), np.hypot(d[:, 1], d[:, 2])


def test_off_is_bit_identical_to_the_default():
    a = simulate("path", seed=2, mounting_rpy_deg=MOUNT, **TURNING)
    b = simulate("path", seed=2, mounting_rpy_deg=MOUNT, stance_twist_deg=0.0, **TURNING)
    for x, y in ((a.left, b.left), (a.right, b.right)):
        assert np.array_equal(x.gyr, y.gyr) and np.array_equal(x.acc, y.acc)
    assert np.array_equal(a.truth_left.quaternion, b.truth_left.quaternion)


@pytest.fixture(scope="module")
def twisted():
    kw = dict(noise=False, rate_hz=400.0, mounting_rpy_deg=MOUNT, **TURNING)
    return simulate("path", stance_twist_deg=3.0, **kw), simulate("path", **kw)


@pytest.mark.parametrize("foot, sign", [("left", 1.0), ("right", -1.0)])
def test_each_walking_stance_turns_the_foot_by_the_twist_and_the_swing_undoes_it(twisted, foot, sign):
    rec, plain = twisted
    truth, base = getattr(rec, "truth_" + foot), getattr(plain, "truth_" + foot)
    yaw, tilt = _yaw_between(truth.quaternion, base.quaternion)
    assert tilt.max() < 1e-9  # about the vertical only
    heel_off = truth.events["heel_off"]
    # the first heel-off leaves the initial standstill (still); every later one a twisted stance
    assert abs(yaw[heel_off[0]]) < 1e-9
    np.testing.assert_allclose(yaw[heel_off[1:]], sign * math.radians(3.0), atol=1e-9)
    # each swing lands on the planned heading; the final standstill stays still
    np.testing.assert_allclose(yaw[truth.events["foot_flat"]], 0.0, atol=1e-9)
    assert abs(yaw[-1]) < 1e-12
    # the foot turns about its sensor: stance positions and the specific force there unchanged
    st = np.asarray(truth.stance)
    np.testing.assert_array_equal(truth.position[st], base.position[st])
    np.testing.assert_allclose(getattr(rec, foot).acc[st], getattr(plain, foot).acc[st], atol=1e-12)
    assert not truth.velocity[st].any()


def test_the_gyro_carries_the_twist(twisted):
    rec, _ = twisted
    for imu, truth in ((rec.left, rec.truth_left), (rec.right, rec.truth_right)):
        # integrating the gyro (mean-rate rotation vectors) keeps to the truth's attitude, within
        # that integrator's own coning error in the swings (a gyro without the twist: 0.05 rad
        # per stance)
        q = np.empty((imu.n_samples, 4))
        q[0] = truth.quaternion[0]
        for k in range(1, imu.n_samples):
            rv = 0.5 * (imu.gyr[k - 1] + imu.gyr[k]) * (imu.t[k] - imu.t[k - 1])
            q[k] = quat.multiply(q[k - 1], quat.from_rotvec(rv))
        yaw, tilt = _yaw_between(q, truth.quaternion)
        assert np.abs(yaw).max() < 1e-4 and tilt.max() < 1e-4


def test_out_of_range_is_refused():
    for bad in (25.0, float("nan")):
        with pytest.raises(InvalidParameterError, match="stance_twist_deg"):
            simulate("straight", distance_m=4.0, stance_twist_deg=bad)
