import numpy as np
import pytest

import footnav
from footnav import InvalidInputError, StanceResult
from footnav.analysis import metrics
from footnav.estimators.ekf import EkfEstimator
from footnav.testing import EstimatorContract


class TestEkfContract(EstimatorContract):
    component = EkfEstimator


def _run(rec, **est):
    pipe = footnav.make_pipeline("threshold", "ekf", "independent", estimator_params=est)
    return pipe.run(rec.left, rec.right)


def _final_error_after_alignment(traj, truth):
    aligned, _, _ = metrics.rigid_align(traj.position, truth.position, dims=2)
    return float(np.linalg.norm(aligned[-1, :2] - truth.position[-1, :2]))


@pytest.mark.parametrize("seed", [0, 1])
def test_straight_100m_error_within_one_percent(seed):
    rec = footnav.simulate("straight", seed=seed, rate_hz=100.0, distance_m=100.0)
    res = _run(rec)
    for traj, truth in ((res.left, rec.truth_left), (res.right, rec.truth_right)):
        dist = metrics.travelled_distance(truth.position, dims=2)
        assert dist == pytest.approx(100.0, rel=0.05)
        # the specification: 1 % of the distance
        final, ate = _final_error_after_alignment(traj, truth), metrics.ate_rmse(traj.position, truth.position, dims=2)
        assert final <= 0.01 * dist
        assert ate <= 0.01 * dist
        # regression bounds: measured final 0.04-0.14 %, ATE 0.023-0.078 % over seeds 0-4 (both feet)
        assert final <= 0.0025 * dist
        assert ate <= 0.0015 * dist
        # vertical, on level ground: today the feet end 0.05-0.42 m low (a downward drift of about
        # 1 mm per step at 100 Hz from the mechanization, under investigation); tighten when fixed
        assert abs(traj.position[-1, 2] - traj.position[0, 2]) <= 0.8


@pytest.mark.parametrize("direction", ["ccw", "cw"])
def test_rectangle_105_by_68_error_within_one_percent(direction):
    rec = footnav.simulate("rectangle", seed=3, rate_hz=100.0, width_m=105.0, height_m=68.0, direction=direction)
    res = _run(rec)
    for traj, truth in ((res.left, rec.truth_left), (res.right, rec.truth_right)):
        dist = metrics.travelled_distance(truth.position, dims=2)
        assert dist > 340.0
        loop = metrics.loop_closure_error(traj.position, dims=2)
        ate = metrics.ate_rmse(traj.position, truth.position, dims=2)
        assert loop.error_m <= 0.01 * dist  # the walk returns to its start: heading-free check
        assert ate <= 0.01 * dist
        # regression bound: ATE measured 0.046-0.166 % (seed 3), 0.04-0.22 % over seeds 3-5; the
        # loop error (0.21-0.43 %, 0.11-0.63 % over seeds 3-5) has the 1 % specification at ~2x
        assert ate <= 0.004 * dist
        # vertical: back at its start height, the loop ends 0.88-0.96 m low today (seed 3; the
        # mechanization's downward drift, under investigation); tighten when fixed
        assert abs(traj.position[-1, 2] - traj.position[0, 2]) <= 1.5


def test_noise_free_walk_is_reproduced_closely_at_100_and_400_hz():
    errors = []
    for rate in (100.0, 400.0):
        rec = footnav.simulate("straight", seed=0, rate_hz=rate, distance_m=30.0, noise=False)
        traj = EkfEstimator().estimate(rec.left, StanceResult(rec.truth_left.stance))
        errors.append(metrics.ate_rmse(traj.position, rec.truth_left.position, dims=2))
        # vertical: measured z at the end -0.052 m at 100 Hz, -0.0032 m at 400 Hz (the
        # mechanization's downward drift, about 1.2 mm per step at 100 Hz, under investigation)
        assert abs(traj.position[-1, 2] - rec.truth_left.position[-1, 2]) <= {100.0: 0.1, 400.0: 0.01}[rate]
    assert max(errors) < 0.03  # the specification: 0.1 % of 30 m
    # regression: measured 2-D ATE 0.5 mm at 100 Hz, 0.1 mm at 400 Hz
    assert errors[0] < 0.0015
    # no worse at the higher rate (the discretisation error shrinks with dt)
    assert errors[1] < errors[0]


def test_first_step_points_along_x():
    rec = footnav.simulate("path", seed=0, segments=[(20.0, 0.0)], noise=False)
    traj = EkfEstimator().estimate(rec.left, StanceResult(rec.truth_left.stance))
    fp = traj.footprints
    d = fp[1] - fp[0]
    assert abs(np.arctan2(d[1], d[0])) < 1e-6
    assert traj.position[-1, 0] == pytest.approx(20.0, abs=0.5)
    sensor = EkfEstimator(heading="sensor").estimate(rec.left, StanceResult(rec.truth_left.stance))
    np.testing.assert_allclose(
        np.linalg.norm(sensor.position[:, :2], axis=1), np.linalg.norm(traj.position[:, :2], axis=1), atol=1e-9
    )


def test_stance_mask_of_wrong_length_is_rejected():
    rec = footnav.simulate("straight", distance_m=5.0)
    with pytest.raises(InvalidInputError, match="stance mask has 10 samples"):
        EkfEstimator().estimate(rec.left, StanceResult(np.ones(10, dtype=bool)))


def test_no_stance_is_rejected_with_advice():
    rec = footnav.simulate("straight", distance_m=5.0)
    with pytest.raises(InvalidInputError, match="no stance phase"):
        EkfEstimator().estimate(rec.left, StanceResult(np.zeros(rec.left.n_samples, dtype=bool)))


def test_invalid_parameter_value():
    rec = footnav.simulate("straight", distance_m=5.0)
    with pytest.raises(footnav.InvalidParameterError, match="zupt_std_mps=0"):
        EkfEstimator(zupt_std_mps=0).estimate(rec.left, StanceResult(rec.truth_left.stance))


def test_smoother_cache_only_trades_memory_for_time():
    # 0 MB: every segment re-run from its checkpoint; the default keeps them all; same numbers
    rec = footnav.simulate("straight", seed=2, distance_m=60.0)
    stance = StanceResult(rec.truth_left.stance)
    kept = EkfEstimator().estimate(rec.left, stance)
    rerun = EkfEstimator(smoother_cache_mb=0).estimate(rec.left, stance)
    for a, b in ((kept.position, rerun.position), (kept.quaternion, rerun.quaternion), (kept.velocity, rerun.velocity)):
        np.testing.assert_array_equal(a, b)
    with pytest.raises(footnav.InvalidParameterError, match="smoother_cache_mb"):
        EkfEstimator(smoother_cache_mb=-1.0).estimate(rec.left, stance)


def test_azure_fgo_accuracy_regression(shared_data):
    """Real two-foot recording: 2-D RMSE must stay near what the closing note of the spine reports."""
    from footnav.analysis.evaluation import evaluate
    from footnav.data.io import read_azure_fgo

    rec = read_azure_fgo(shared_data / "azure_fgo")
    report = evaluate(footnav.make_pipeline(), rec)
    # measured 0.241 m left, 0.052 m right (2026-11-25; 0.280 / 0.074 m before). Independent
    # reference (data README): gaitmap 2.6 RtsKalman with defaults, 0.36 m left, 0.76 m right;
    # the left bound stays below it (1.4x measured), the right one is 2.9x measured
    assert report.value("ate_2d", "left") < 0.33
    assert report.value("ate_2d", "right") < 0.15


# -- issue 5 acceptance on the simulator ----------------------------------------------------------
LONG_WALK = {"bias_states": True, "zaru_std_radps": 0.005}


@pytest.mark.parametrize("rate", [100.0, 400.0])
def test_rectangle_346m_return_error_within_half_percent_with_bias_states(rate):
    rec = footnav.simulate("rectangle", seed=1, rate_hz=rate, width_m=105.0, height_m=68.0)
    stance = footnav.make_detector("threshold").detect(rec.left)
    traj = EkfEstimator(**LONG_WALK).estimate(rec.left, stance)
    dist = metrics.travelled_distance(rec.truth_left.position, dims=2)
    assert dist > 340.0
    # measured 0.118 % at 100 Hz, 0.111 % at 400 Hz (the 9-state filter: 0.61 % and 1.33 %: the
    # gyro bias left after the 2 s initial standstill turns the heading by 3-7 deg over the walk)
    loop = metrics.loop_closure_error(traj.position, dims=2).error_m
    assert loop <= 0.005 * dist
    assert loop <= 0.003 * dist  # regression: 2.5x the measured value


@pytest.mark.parametrize("bias_states", [False, True])
def test_uncertainty_does_not_depend_on_the_sampling_rate(bias_states):
    stds = []
    for rate in (100.0, 400.0):
        rec = footnav.simulate("rectangle", seed=0, rate_hz=rate, width_m=20.0, height_m=10.0)
        traj = EkfEstimator(bias_states=bias_states).estimate(rec.left, StanceResult(rec.truth_left.stance))
        stds.append(traj.position_std[-1, :2])
    # noise densities scaled with dt: the same walk ends with the same uncertainty (measured
    # 0.6-1.8 % apart)
    np.testing.assert_allclose(stds[1], stds[0], rtol=0.05)


def test_bias_states_converge_to_the_simulated_biases_within_two_sigma():
    # at 400 Hz: at 100 Hz the trapezoidal mechanisation's error in the fast swing (noise-free:
    # 0.02 m/s^2 of apparent accelerometer bias) is itself absorbed into the bias states
    rec = footnav.simulate("rectangle", seed=0, rate_hz=400.0, width_m=105.0, height_m=68.0)
    traj = EkfEstimator(**LONG_WALK).estimate(rec.left, footnav.make_detector("threshold").detect(rec.left))
    truth = rec.truth_left.meta["biases"]
    for name, true in (("acc_bias_mps2", truth["acc_mps2"][-1]), ("gyr_bias_radps", truth["gyr_radps"][-1])):
        std = np.array(traj.meta[name.replace("_mps2", "_std_mps2").replace("_radps", "_std_radps")])
        assert np.all(np.abs(np.array(traj.meta[name]) - true) <= 2 * std), name
    # the gyro bias is well observed (zero angular rate in stance): 0.25 mrad/s, not the prior's 2
    assert max(traj.meta["gyr_bias_std_radps"]) < 5e-4


@pytest.mark.parametrize("bias_states", [False, True])
@pytest.mark.parametrize("seed", [2, 3])
@pytest.mark.parametrize(
    "scenario, opts", [("straight", {"distance_m": 30.0}), ("rectangle", {"width_m": 20.0, "height_m": 10.0})]
)
def test_smoothing_never_worsens_the_forward_filter(scenario, opts, seed, bias_states):
    # 400 Hz: at 100 Hz the simulator's own discretisation error dominates (its gait profiles are
    # C2, so the jerk jumps at each phase change and the integration error, 0.02 m/s per swing
    # noise-free, arrives at the heel strike, where no smoother can place it)
    rec = footnav.simulate(scenario, seed=seed, rate_hz=400.0, **opts)
    stance = StanceResult(rec.truth_left.stance)
    kw = LONG_WALK if bias_states else {}
    fwd, step, whole = (
        EkfEstimator(smoother=s, heading="sensor", **kw).estimate(rec.left, stance) for s in ("none", "step", "whole")
    )
    truth = rec.truth_left

    def speed_rmse(traj):
        return float(
            np.sqrt(np.mean((np.linalg.norm(traj.velocity, axis=1) - np.linalg.norm(truth.velocity, axis=1)) ** 2))
        )

    for smoothed in (step, whole):
        assert speed_rmse(smoothed) <= speed_rmse(fwd)  # measured 15-65 % lower
    # the whole-walk RTS smoother is the optimal one for its model: its positions are no worse
    # either. With bias states and the standstill's gyro prior (honest: the initial bias errors
    # of seeds 2-7 have an RMS of 1.08e-4 rad/s against a prior of 1.07e-4) the simulator's
    # discretisation error, outside the model, leaves both at 1-3 mm on this walk, the
    # smoother up to 0.9 mm behind (seed 2)
    slack = 1e-3 if bias_states else 0.0
    assert (
        metrics.ate_rmse(whole.position, truth.position, dims=2)
        <= metrics.ate_rmse(fwd.position, truth.position, dims=2) + slack
    )


def test_covariance_stays_symmetric_positive_definite_over_a_60_minute_walk():
    # eleven laps of a 153 x 63 m rectangle, about 60 minutes
    segments = [(150.0, 90.0), (60.0, 90.0), (150.0, 90.0), (60.0, 90.0)] * 11
    rec = footnav.simulate("path", seed=11, segments=segments)
    assert rec.left.duration_s > 55 * 60
    est = EkfEstimator(smoother="step", **LONG_WALK)
    filt = est.start([rec.left], [StanceResult(rec.truth_left.stance)])
    filt.step_stops = True  # a checkpoint at every step end: the covariance seen step by step
    filt.run_until()
    worst_asym, worst_eig = 0.0, np.inf
    for cp in filt.checkpoints[1:]:  # the first holds the exactly known start position (variance 0)
        cov = cp.state.cov
        worst_asym = max(worst_asym, float(np.abs(cov - cov.T).max()))
        worst_eig = min(worst_eig, float(np.linalg.eigvalsh(cov).min()))
    assert len(filt.checkpoints) > 2000  # a checkpoint per step: the check covers the whole walk
    assert worst_asym == 0.0  # the update writes both triangles from one value
    assert worst_eig > 0.0
    _, _, pos, pcov = filt.outputs(0)
    assert np.isfinite(pos).all() and (pcov[1:, [0, 2, 3]] > 0).all()


def test_closed_loop_constraint_closes_the_loop_and_improves_the_whole_trajectory():
    rec = footnav.simulate("rectangle", seed=1, width_m=105.0, height_m=68.0)
    stance = footnav.make_detector("threshold").detect(rec.left)
    free = EkfEstimator(smoother="whole").estimate(rec.left, stance)
    closed = EkfEstimator(smoother="whole", closed_loop=True).estimate(rec.left, stance)
    assert metrics.loop_closure_error(free.position, dims=2).error_m > 1.0  # measured 2.07 m
    assert metrics.loop_closure_error(closed.position, dims=2).error_m < 0.01  # measured 0.1 mm
    ate_free = metrics.ate_rmse(free.position, rec.truth_left.position, dims=2)
    ate_closed = metrics.ate_rmse(closed.position, rec.truth_left.position, dims=2)
    assert ate_closed < 0.5 * ate_free  # measured 0.588 -> 0.160 m: the smoother spreads it back
    assert closed.meta["closed_loop"]["std_m"] == 0.01


def test_closed_loop_needs_the_whole_walk_smoother():
    rec = footnav.simulate("straight", distance_m=5.0)
    with pytest.raises(footnav.InvalidParameterError, match="smoother='whole'"):
        EkfEstimator(closed_loop=True, smoother="step").estimate(rec.left, StanceResult(rec.truth_left.stance))
    with pytest.raises(footnav.InvalidParameterError, match="bias_states=True"):
        EkfEstimator(zaru_std_radps=0.01).estimate(rec.left, StanceResult(rec.truth_left.stance))


@pytest.mark.filterwarnings("ignore::footnav.DataQualityWarning")  # the x-io files' duplicates and gaps
@pytest.mark.parametrize("name", ["xio_short", "xio_long"])
def test_closed_loop_constraint_on_the_xio_loops(shared_data, name):
    from footnav.analysis.evaluation import evaluate
    from footnav.data.datasets import load_dataset

    rec = load_dataset(name, shared_data)
    free = evaluate(footnav.make_pipeline(), rec).value("loop_closure_2d", "left")
    pipe = footnav.make_pipeline("threshold", "ekf", "independent", estimator_params={"closed_loop": True})
    closed = evaluate(pipe, rec).value("loop_closure_2d", "left")
    # measured 2026-11-25: short 0.076 -> 0.0022 m, long 0.213 -> 0.0014 m. Free: the publisher's
    # own end-to-start errors (0.082 / 0.421 m, data README), an independent figure. Closed: 5 mm,
    # 2.3x the worst measured (was 10 mm, 4.5x)
    assert free < {"xio_short": 0.09, "xio_long": 0.42}[name]
    assert closed < 0.005
