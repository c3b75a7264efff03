import numpy as np
import pytest

import footnav
from footnav.core import metrics
from footnav.detectors.threshold import ThresholdDetector
from footnav.testing import DetectorContract


class TestThresholdContract(DetectorContract):
    component = ThresholdDetector


@pytest.mark.parametrize("scenario, rate", [("straight", 100.0), ("rectangle", 100.0), ("straight", 400.0)])
def test_finds_every_step_of_a_simulated_walk(scenario, rate):
    opts = {"distance_m": 30.0} if scenario == "straight" else {"width_m": 20.0, "height_m": 10.0}
    rec = footnav.simulate(scenario, seed=2, rate_hz=rate, **opts)
    det = ThresholdDetector()
    for imu, truth in ((rec.left, rec.truth_left), (rec.right, rec.truth_right)):
        stance = det.detect(imu)
        steps = metrics.step_detection(stance.mask, truth.stance, tolerance_samples=int(0.15 * rate))
        assert steps.missed == 0 and steps.false == 0
        assert metrics.sample_scores(stance.mask, truth.stance).f1 >= 0.85


def test_events_bound_each_stance():
    rec = footnav.simulate("straight", seed=0, distance_m=10.0)
    stance = ThresholdDetector().detect(rec.left)
    runs = stance.intervals
    np.testing.assert_array_equal(stance.events["foot_flat"], runs[:, 0])
    np.testing.assert_array_equal(stance.events["heel_off"], runs[:, 1] - 1)
    assert stance.score.shape == stance.mask.shape


def test_min_stance_removes_short_runs():
    t = np.arange(300) / 100.0
    gyr = np.full((300, 3), 3.0)
    gyr[100:103] = 0.0  # a 30 ms pause mid-swing is no stance
    gyr[200:260] = 0.0
    acc = np.tile([0.0, 0.0, footnav.GRAVITY_MPS2], (300, 1))
    imu = footnav.ImuData(t, acc, gyr)
    mask = ThresholdDetector(window_s=0.01, min_stance_s=0.1).detect(imu).mask
    assert not mask[100:103].any()
    assert mask[205:255].all()
