"""tools/footprint_error_decomposition.py recovers a heading drift and a length scale it was given."""

import numpy as np
import pytest
from tool_module import load_tool  # tests/tool_module.py


@pytest.fixture(scope="module")
def tool():
    return load_tool("footprint_error_decomposition")


def _walk(rng):
    """A hallway walk of 60 one-second strides of 1.3 m with U-turns, as footprints (x, y) and times."""
    heading = np.repeat([0.0, np.pi, 0.0, np.pi], 15) + rng.normal(0, 0.02, 60)
    steps = 1.3 * np.column_stack([np.cos(heading), np.sin(heading)])
    return np.vstack([[0.0, 0.0], np.cumsum(steps, axis=0)]), np.arange(61.0)


def _distort(ref, t, omega_radps, scale, theta0=0.7, offset=(3.0, -2.0)):
    """The estimate a filter with a constant yaw-rate error and a length scale would give."""
    ang = theta0 - omega_radps * (t[1:] - t[0])
    c, s = np.cos(ang), np.sin(ang)
    d = np.diff(ref, axis=0) * scale
    turned = np.column_stack([c * d[:, 0] - s * d[:, 1], s * d[:, 0] + c * d[:, 1]])
    return np.vstack([[0.0, 0.0], np.cumsum(turned, axis=0)]) + offset


def test_drift_and_scale_are_recovered(tool):
    ref, t = _walk(np.random.default_rng(1))
    omega = np.radians(5.0) / 60.0  # 5 deg/min
    est = _distort(ref, t, omega, 1 / 1.03)  # 3 % short
    fits = tool.decompose(est, ref, t)
    rmse, omega_deg_min, s_pct = fits["drift + scale"]
    assert rmse < 1e-6
    assert omega_deg_min == pytest.approx(5.0, abs=1e-4)
    assert s_pct == pytest.approx(3.0, abs=1e-4)
    # each model alone leaves what the other error costs
    assert fits["rigid"][0] > max(fits["drift"][0], fits["scale"][0]) > 0.05


def test_a_pure_scale_leaves_no_drift(tool):
    ref, t = _walk(np.random.default_rng(2))
    fits = tool.decompose(_distort(ref, t, 0.0, 1.02), ref, t)
    assert fits["scale"][0] < 1e-6
    assert fits["scale"][2] == pytest.approx(100 * (1 / 1.02 - 1), abs=1e-4)
    assert fits["drift"][0] > 0.05


def test_gyro_shift_resamples_between_samples(tool):
    import footnav

    imu = footnav.simulate("straight", seed=3, distance_m=8.0).left
    assert tool.shift_gyro(imu, 0.0) is imu
    moved = tool.shift_gyro(imu, 1.0)
    np.testing.assert_allclose(moved.gyr[:-1], imu.gyr[1:], atol=1e-12)
    half = tool.shift_gyro(imu, 0.5)
    np.testing.assert_allclose(half.gyr[:-1], 0.5 * (imu.gyr[:-1] + imu.gyr[1:]), atol=1e-12)
    np.testing.assert_array_equal(moved.acc, imu.acc)


def test_simulated_swings_close_best_unshifted(tool):
    import footnav

    imu = footnav.simulate("straight", seed=4, distance_m=20.0).left
    pipe = footnav.make_pipeline()

    def speed(foot):
        result = pipe.run(foot)
        return tool.closing_speed(pipe.estimator, foot, result.stance_left, result.left)

    at_zero = speed(imu)
    assert at_zero < 0.1
    assert speed(tool.shift_gyro(imu, 2.0)) > at_zero
