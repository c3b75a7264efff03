"""Madgwick + 9-state error KF (seed 003): the attitude against ahrs, the trajectory against truth."""

import numpy as np
import pytest

import footnav
from footnav import StanceResult
from footnav.core import metrics
from footnav.estimators.madgwick import MadgwickEstimator, madgwick_imu_step, madgwick_marg_step
from footnav.testing import EstimatorContract


class TestMadgwickContract(EstimatorContract):
    component = MadgwickEstimator


@pytest.fixture(scope="module")
def walk():
    return footnav.simulate("rectangle", seed=2, width_m=10.0, height_m=5.0)


def test_imu_update_matches_ahrs_step_by_step(walk):
    ahrs = pytest.importorskip("ahrs")
    ref = ahrs.filters.Madgwick(gain=0.05, frequency=100.0)
    q_ours = np.array([1.0, 0.0, 0.0, 0.0])
    q_ref = q_ours.copy()
    imu = walk.left
    for k in range(1, 1500):
        dt = imu.t[k] - imu.t[k - 1]
        madgwick_imu_step(q_ours, *imu.gyr[k], *imu.acc[k], 0.05, dt)
        q_ref = ref.updateIMU(q_ref, imu.gyr[k], imu.acc[k], dt=dt)
    np.testing.assert_allclose(q_ours, q_ref, atol=1e-10)


def test_marg_update_matches_ahrs_step_by_step(walk):
    ahrs = pytest.importorskip("ahrs")
    ref = ahrs.filters.Madgwick(gain=0.05, frequency=100.0)
    imu = walk.left
    # a field of 50 uT dipping 60 deg, seen in the sensor frame through the true attitude
    field_n = 50.0 * np.array([np.cos(np.radians(60)), 0.0, -np.sin(np.radians(60))])
    mag = footnav.core.quaternion.rotate(footnav.core.quaternion.conjugate(walk.truth_left.quaternion), field_n)
    q_ours = np.array([1.0, 0.0, 0.0, 0.0])
    q_ref = q_ours.copy()
    for k in range(1, 1500):
        dt = imu.t[k] - imu.t[k - 1]
        madgwick_marg_step(q_ours, *imu.gyr[k], *imu.acc[k], *mag[k], 0.05, dt)
        q_ref = ref.updateMARG(q_ref, imu.gyr[k], imu.acc[k], mag[k], dt=dt)
    np.testing.assert_allclose(q_ours, q_ref, atol=1e-9)


def test_marg_finds_magnetic_north_from_a_wrong_start():
    rec = footnav.simulate("straight", seed=0, distance_m=10.0, noise=False)
    truth = rec.truth_left
    field_n = 50.0 * np.array([np.cos(np.radians(60)), 0.0, -np.sin(np.radians(60))])  # north = nav +x
    mag = footnav.core.quaternion.rotate(footnav.core.quaternion.conjugate(truth.quaternion), field_n)
    q = footnav.core.quaternion.from_yaw(1.0)  # start 57 deg off
    for k in range(1, 600):  # the 2 s standstill and the first steps
        madgwick_marg_step(q, *rec.left.gyr[k], *rec.left.acc[k], *mag[k], 0.5, 0.01)
    yaw_err = footnav.core.quaternion.yaw(footnav.core.quaternion.multiply(q, footnav.core.quaternion.conjugate(truth.quaternion[599])))
    assert abs(yaw_err) < 0.02


@pytest.mark.parametrize("scenario, opts", [("straight", {"distance_m": 50.0}), ("rectangle", {"width_m": 20.0, "height_m": 10.0})])
def test_trajectory_matches_truth_at_100_and_400_hz(scenario, opts):
    errors = []
    for rate in (100.0, 400.0):
        rec = footnav.simulate(scenario, seed=0, rate_hz=rate, **opts)
        traj = MadgwickEstimator().estimate(rec.left, StanceResult(rec.truth_left.stance))
        dist = metrics.travelled_distance(rec.truth_left.position, dims=2)
        ate = metrics.ate_rmse(traj.position, rec.truth_left.position, dims=2)
        errors.append(ate / dist)
        # measured 0.016-0.056 % of the distance (the ekf: 0.010-0.029 %)
        assert ate < 0.001 * dist
        assert traj.meta["orientation"] == "madgwick-imu"


def test_noise_densities_keep_the_uncertainty_rate_independent():
    stds = []
    for rate in (100.0, 400.0):
        rec = footnav.simulate("straight", seed=1, rate_hz=rate, distance_m=20.0)
        stds.append(MadgwickEstimator().estimate(rec.left, StanceResult(rec.truth_left.stance)).position_std[-1])
    np.testing.assert_allclose(stds[1], stds[0], rtol=0.1)


def test_real_data_azure_fgo(shared_data):
    from footnav.core.datasets import load_dataset
    from footnav.core.evaluation import evaluate

    rep = evaluate(footnav.make_pipeline("threshold", "madgwick"), load_dataset("azure_fgo", shared_data))
    # measured 0.167 / 0.059 m; gaitmap RtsKalman 0.36 / 0.76 m
    assert rep.value("ate_2d", "left") < 0.25 and rep.value("ate_2d", "right") < 0.12
