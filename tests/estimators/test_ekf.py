import numpy as np
import pytest

import footnav
from footnav import InvalidInputError, StanceResult
from footnav.core import metrics
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
        assert _final_error_after_alignment(traj, truth) <= 0.01 * dist
        assert metrics.ate_rmse(traj.position, truth.position, dims=2) <= 0.01 * dist


@pytest.mark.parametrize("direction", ["ccw", "cw"])
def test_rectangle_105_by_68_error_within_one_percent(direction):
    rec = footnav.simulate("rectangle", seed=3, rate_hz=100.0, width_m=105.0, height_m=68.0, direction=direction)
    res = _run(rec)
    for traj, truth in ((res.left, rec.truth_left), (res.right, rec.truth_right)):
        dist = metrics.travelled_distance(truth.position, dims=2)
        assert dist > 340.0
        loop = metrics.loop_closure_error(traj.position, dims=2)
        assert loop.error_m <= 0.01 * dist  # the walk returns to its start: heading-free check
        assert metrics.ate_rmse(traj.position, truth.position, dims=2) <= 0.01 * dist


def test_noise_free_walk_is_reproduced_closely_at_100_and_400_hz():
    errors = []
    for rate in (100.0, 400.0):
        rec = footnav.simulate("straight", seed=0, rate_hz=rate, distance_m=30.0, noise=False)
        traj = EkfEstimator().estimate(rec.left, StanceResult(rec.truth_left.stance))
        errors.append(metrics.ate_rmse(traj.position, rec.truth_left.position, dims=3))
    assert max(errors) < 0.03  # 0.1 % of 30 m
    # noise densities make the filter rate-independent: no order-of-magnitude change with rate
    assert errors[1] < 2 * errors[0] + 0.005


def test_first_step_points_along_x():
    rec = footnav.simulate("path", seed=0, segments=[(20.0, 0.0)], noise=False)
    traj = EkfEstimator().estimate(rec.left, StanceResult(rec.truth_left.stance))
    fp = traj.footprints
    d = fp[1] - fp[0]
    assert abs(np.arctan2(d[1], d[0])) < 1e-6
    assert traj.position[-1, 0] == pytest.approx(20.0, abs=0.5)
    sensor = EkfEstimator(heading="sensor").estimate(rec.left, StanceResult(rec.truth_left.stance))
    np.testing.assert_allclose(np.linalg.norm(sensor.position[:, :2], axis=1), np.linalg.norm(traj.position[:, :2], axis=1), atol=1e-9)


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


def test_azure_fgo_accuracy_regression(shared_data):
    """Real two-foot recording: 2-D RMSE must stay near what the closing note of the spine reports."""
    from footnav.core.evaluation import evaluate
    from footnav.core.io import read_azure_fgo

    rec = read_azure_fgo(shared_data / "azure_fgo")
    report = evaluate(footnav.make_pipeline(), rec)
    # measured 0.280 m left, 0.074 m right; gaitmap RtsKalman reference: 0.36 m left, 0.76 m right
    assert report.value("ate_2d", "left") < 0.33
    assert report.value("ate_2d", "right") < 0.15
