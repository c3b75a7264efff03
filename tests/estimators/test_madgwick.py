"""Madgwick + 9-state error KF (seed 003): the attitude against ahrs, the trajectory against truth."""

import warnings
from dataclasses import replace

import numpy as np
import pytest

import footnav
from footnav import InvalidInputError, InvalidParameterError, StanceResult
from footnav.analysis import metrics
from footnav.core.errors import DataQualityWarning
from footnav.core.types import ImuData
from footnav.estimators.madgwick import MadgwickEstimator, madgwick_imu_step, madgwick_marg_step
from footnav.nav import quaternion as quat
from footnav.testing import EstimatorContract

#: Earth field for the MARG tests: 50 uT dipping 60 deg, magnetic north along nav +x.
FIELD_NORTH_UT = 50.0 * np.array([np.cos(np.radians(60)), 0.0, -np.sin(np.radians(60))])


class TestMadgwickContract(EstimatorContract):
    component = MadgwickEstimator


@pytest.fixture(scope="module")
def walk():
    return footnav.simulate("rectangle", seed=2, width_m=10.0, height_m=5.0)


def _with_mag(rec, north_yaw_rad=0.0):
    """The left foot's recording with the field of magnetic north at ``north_yaw_rad`` from nav +x."""
    field_n = quat.rotate(quat.from_yaw(north_yaw_rad), FIELD_NORTH_UT)
    return replace(rec.left, mag=quat.rotate(quat.conjugate(rec.truth_left.quaternion), field_n))


def _ahrs_run(imu, start, q_start, beta, mag=None):
    """ahrs's Madgwick (Python, independent code) from ``q_start`` at sample ``start``: (N - start, 4)."""
    ahrs = pytest.importorskip("ahrs")
    ref = ahrs.filters.Madgwick(gain=beta, frequency=imu.rate_hz)  # gain = beta in rad/s, q = [w, x, y, z]
    out = np.empty((imu.n_samples - start, 4))
    out[0] = q = np.array(q_start, dtype=float)
    for k in range(start + 1, imu.n_samples):
        dt = imu.t[k] - imu.t[k - 1]
        if mag is None:
            q = ref.updateIMU(q, imu.gyr[k], imu.acc[k], dt=dt)
        else:
            q = ref.updateMARG(q, imu.gyr[k], imu.acc[k], mag[k], dt=dt)
        out[k - start] = q
    return out


# -- the orientation filter ------------------------------------------------------------------------
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
    mag = _with_mag(walk).mag
    q_ours = np.array([1.0, 0.0, 0.0, 0.0])
    q_ref = q_ours.copy()
    for k in range(1, 1500):
        dt = imu.t[k] - imu.t[k - 1]
        madgwick_marg_step(q_ours, *imu.gyr[k], *imu.acc[k], *mag[k], 0.05, dt)
        q_ref = ref.updateMARG(q_ref, imu.gyr[k], imu.acc[k], mag[k], dt=dt)
    np.testing.assert_allclose(q_ours, q_ref, atol=1e-9)


def test_marg_finds_magnetic_north_from_a_wrong_start():
    rec = footnav.simulate("straight", seed=0, distance_m=10.0, noise=False)
    mag = _with_mag(rec).mag
    q = quat.from_yaw(1.0)  # start 57 deg off
    for k in range(1, 600):  # the 2 s standstill and the first steps
        madgwick_marg_step(q, *rec.left.gyr[k], *rec.left.acc[k], *mag[k], 0.5, 0.01)
    yaw_err = quat.yaw(quat.multiply(q, quat.conjugate(rec.truth_left.quaternion[599])))
    assert abs(yaw_err) < 0.02


def _mid_walk(rec, first=280, stop=1200):
    """The left foot's samples first:stop, starting in a swing: the recording does not start at
    standstill (first stance at 320)."""
    mask = rec.truth_left.stance[first:stop]
    assert not mask[0]
    return rec.left.slice(first, stop), StanceResult(mask)


def test_estimator_attitude_is_ahrs_madgwick_from_the_first_standstill(walk):
    imu, stance = _mid_walk(walk)
    s0 = int(stance.intervals[0, 0])
    with pytest.warns(DataQualityWarning, match="does not start at standstill"):
        traj = MadgwickEstimator(beta_radps=0.05, gyro_bias="none", heading="sensor").estimate(imu, stance)
    assert traj.meta["estimate_start_index"] == s0 and traj.meta["orientation"] == "madgwick-imu"
    # the start: levelled at the standstill (roll, pitch of the truth), yaw 0 in the sensor's frame
    start_err = quat.as_rotvec(quat.multiply(quat.conjugate(walk.truth_left.quaternion[280 + s0]), traj.quaternion[s0]))
    assert np.linalg.norm(start_err[:2]) < 2e-3 and quat.yaw(traj.quaternion[s0]) == pytest.approx(0.0, abs=1e-12)
    np.testing.assert_allclose(traj.quaternion[:s0], np.tile(traj.quaternion[s0], (s0, 1)))
    np.testing.assert_allclose(traj.quaternion[s0:], _ahrs_run(imu, s0, traj.quaternion[s0], 0.05), atol=1e-9)


def test_estimator_marg_starts_at_magnetic_north_and_is_ahrs_madgwick(walk):
    north = 1.0  # rad from the walk's (and the sensor's initial) heading
    imu = _with_mag(walk, north).slice(0, 1200)
    traj = MadgwickEstimator(beta_radps=0.05, gyro_bias="none", heading="sensor").estimate(
        imu, StanceResult(walk.truth_left.stance[:1200])
    )
    assert traj.meta["orientation"] == "madgwick-marg"
    # nav x = magnetic north: the truth turned by -north about z
    expected = quat.multiply(quat.from_yaw(-north), walk.truth_left.quaternion[0])
    assert np.linalg.norm(quat.as_rotvec(quat.multiply(quat.conjugate(expected), traj.quaternion[0]))) < 3e-3
    np.testing.assert_allclose(traj.quaternion, _ahrs_run(imu, 0, traj.quaternion[0], 0.05, imu.mag), atol=1e-9)


# -- trajectories against the simulator's truth -----------------------------------------------------
def _errors(traj, truth):
    """ATE (2-D, aligned), final-position error after the same alignment, in m; distance in m."""
    dist = metrics.travelled_distance(truth.position, dims=2)
    aligned, _, _ = metrics.rigid_align(traj.position, truth.position, dims=2)
    final = float(np.linalg.norm(aligned[-1, :2] - truth.position[-1, :2]))
    return metrics.ate_rmse(traj.position, truth.position, dims=2), final, dist


@pytest.mark.parametrize(
    "scenario, opts", [("straight", {"distance_m": 50.0}), ("rectangle", {"width_m": 20.0, "height_m": 10.0})]
)
def test_trajectory_matches_truth_at_100_and_400_hz(scenario, opts):
    runs = []
    for rate in (100.0, 400.0):
        rec = footnav.simulate(scenario, seed=0, rate_hz=rate, **opts)
        traj = MadgwickEstimator().estimate(rec.left, StanceResult(rec.truth_left.stance))
        assert traj.meta["orientation"] == "madgwick-imu"
        ate, final, dist = _errors(traj, rec.truth_left)
        # measured (seeds 0-3): ATE 0.02-0.07 % of the distance at 100 Hz, 0.01-0.03 % at 400 Hz
        # (ekf: 0.02-0.05 %); final error 0.02-0.12 %
        assert ate < 0.001 * dist
        assert final < 0.0025 * dist
        if scenario == "rectangle":  # back at the start: a heading-free check
            assert metrics.loop_closure_error(traj.position, dims=2).error_m < 0.002 * dist
        runs.append(traj)
    lo, hi = runs
    # the same walk at either rate: end point, path length and end uncertainty agree (measured:
    # end points 0.3 % of the distance apart, lengths 0.12 %, std 4 %). The errors themselves are
    # millimetres; at 100 Hz Madgwick's first-order quaternion step adds ~2x (noise-free: 24 vs 7 mm).
    assert np.linalg.norm(lo.position[-1, :2] - hi.position[-1, :2]) < 0.01 * dist
    assert lo.path_length_m == pytest.approx(hi.path_length_m, rel=0.01)
    np.testing.assert_allclose(hi.position_std[-1], lo.position_std[-1], rtol=0.1)


def test_marg_trajectory_matches_truth_when_north_is_not_the_sensor_heading(walk):
    truth = walk.truth_left
    stance = StanceResult(truth.stance)
    imu_only = MadgwickEstimator(use_magnetometer=False).estimate(walk.left, stance)
    for north in (1.0, 2.5):
        imu = _with_mag(walk, north)
        traj = MadgwickEstimator().estimate(imu, stance)
        assert traj.meta["magnetic_heading_rad"] == pytest.approx(-north, abs=0.01)
        ate, final, dist = _errors(traj, truth)
        # measured 0.04 % (IMU only: 0.03 %); started at the sensor's heading instead: 3-4 %
        assert ate < 0.001 * dist
        # no worse than without the magnetometer beyond the start's heading (measured 1.7-2.2x
        # the IMU-only 6.9 mm)
        assert ate < 3 * _errors(imu_only, truth)[0]
        # heading="sensor": nav x is magnetic north, so the truth turned by -north, no alignment
        sensor = MadgwickEstimator(heading="sensor").estimate(imu, stance)
        expected = quat.rotate(quat.from_yaw(-north), truth.position - truth.position[0])
        assert np.max(np.linalg.norm(sensor.position[:, :2] - expected[:, :2], axis=1)) < 0.005 * dist


def test_magnetometer_off_or_absent_gives_the_imu_filter(walk):
    stance = StanceResult(walk.truth_left.stance)
    plain = MadgwickEstimator().estimate(walk.left, stance)
    off = MadgwickEstimator(use_magnetometer=False).estimate(_with_mag(walk, 1.0), stance)
    assert off.meta["orientation"] == "madgwick-imu"
    np.testing.assert_array_equal(off.position, plain.position)


def test_position_std_grows_in_swing_and_keeps_its_size_under_the_heading_turn(walk):
    stance = StanceResult(walk.truth_left.stance)
    traj = MadgwickEstimator().estimate(walk.left, stance)
    sensor = MadgwickEstimator(heading="sensor").estimate(walk.left, stance)
    a, b = stance.intervals[3, 1], stance.intervals[4, 0]  # a swing
    assert np.all(traj.position_std[b, :2] > traj.position_std[a, :2])
    # a rotation about z keeps the horizontal variance (xx + yy) and the vertical one
    np.testing.assert_allclose(
        (traj.position_std[:, :2] ** 2).sum(1), (sensor.position_std[:, :2] ** 2).sum(1), rtol=1e-9
    )
    np.testing.assert_allclose(traj.position_std[:, 2], sensor.position_std[:, 2])


# -- bad input ---------------------------------------------------------------------------------------
def test_stance_mask_of_wrong_length_is_rejected(walk):
    with pytest.raises(InvalidInputError, match="stance mask has 10 samples") as err:
        MadgwickEstimator().estimate(walk.left, StanceResult(np.ones(10, dtype=bool)))
    assert "stance.mask" in str(err.value)


def test_no_stance_is_rejected_with_advice(walk):
    with pytest.raises(InvalidInputError, match="no stance phase"):
        MadgwickEstimator().estimate(walk.left, StanceResult(np.zeros(walk.left.n_samples, dtype=bool)))


@pytest.mark.parametrize(
    "params, match",
    [
        ({"zupt_std_mps": 0}, "zupt_std_mps=0"),
        ({"beta_radps": -0.1}, "beta_radps=-0.1"),
        ({"use_magnetometer": "yes"}, "use_magnetometer='yes'"),
        ({"heading": "north"}, "heading='north'"),
    ],
)
def test_invalid_parameter_value(walk, params, match):
    with pytest.raises(InvalidParameterError, match=match):
        MadgwickEstimator(**params).estimate(walk.left, StanceResult(walk.truth_left.stance))


def test_parameters_document_their_units():
    info = {p.name: p for p in MadgwickEstimator.parameter_info()}
    assert info["beta_radps"].unit == "rad/s" and info["acc_noise_mps2_sqrthz"].unit == "m/s^2/sqrt(Hz)"
    assert all(p.description for p in info.values())


# -- real data ---------------------------------------------------------------------------------------
@pytest.mark.parametrize("name, bounds", [("azure_fgo", (0.25, 0.12)), ("gaitmap", (0.26, 0.25))])
def test_real_data_accuracy(shared_data, name, bounds):
    from footnav.analysis.evaluation import evaluate
    from footnav.data.datasets import load_dataset

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DataQualityWarning)
        rep = evaluate(footnav.make_pipeline("threshold", "madgwick"), load_dataset(name, shared_data))
    # measured 2-D ATE azure_fgo 0.167 / 0.059 m, gaitmap 0.194 / 0.184 m (ekf: 0.241 / 0.052 m,
    # 0.198 / 0.194 m; gaitmap's RtsKalman on azure_fgo 0.36 / 0.76 m), re-measured 2026-11-25.
    # azure_fgo: below that independent reference (data README), 1.5x / 2.0x measured; gaitmap:
    # regression bounds at 1.3x measured (the example publishes no trajectory error)
    assert rep.value("ate_2d", "left") < bounds[0] and rep.value("ate_2d", "right") < bounds[1]


# Closed-form motions (from the mutant-derived tests, tools/mutate.py): no rotation, a force growing
# linearly in time, so the trapezoidal rule integrates the velocity exactly (v = j t^2 / 2).


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


# mutant: madgwick-velocity-rectangle
# madgwick-velocity-rectangle: the velocity is the trapezoidal integral of the force
def test_madgwick_velocity_integrates_a_linear_force_exactly(push_and_stop):
    t, jerk, traj = push_and_stop
    k = int(np.searchsorted(t, 2.0))  # the push's last sample, before any ZUPT
    np.testing.assert_allclose(traj.velocity[: k + 1, 0], jerk * np.clip(t[: k + 1] - 1.0, 0, None) ** 2 / 2, atol=1e-9)
    np.testing.assert_allclose(traj.position[k, 0], jerk / 6, atol=1e-3)


# mutant: none named (the second check of madgwick-velocity-rectangle's motion)
# the ZUPTs take the left-over velocity out and the position stops moving
def test_madgwick_zupts_stop_the_foot(push_and_stop):
    t, jerk, traj = push_and_stop
    assert np.abs(traj.velocity[-1]).max() < 0.01
    late = t > 2.5
    assert np.ptp(traj.position[late, 0]) < 0.01


# mutant: madgwick-output-sign
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
