import numpy as np
import pytest

import footnav
from footnav.core import metrics
from footnav.core.types import GRAVITY_MPS2
from footnav.detectors.glrt import GlrtDetector, glrt_statistic
from footnav.testing import DetectorContract


class TestGlrtContract(DetectorContract):
    component = GlrtDetector


def test_statistic_hand_case():
    # one window of W = 2 samples: f = [0, 0, g + 1], [0, 0, g - 1]; w = [0.1, 0, 0], [0, 0.2, 0]
    # f_mean = [0, 0, g] -> u = [0, 0, 1]; residuals [0, 0, 1], [0, 0, -1] -> acc sum 2
    # gyro sum 0.01 + 0.04 = 0.05; T = (2 / sa^2 + 0.05 / sg^2) / 2 with sa = 1, sg = 0.5 -> 1.1
    acc = np.array([[0.0, 0.0, GRAVITY_MPS2 + 1.0], [0.0, 0.0, GRAVITY_MPS2 - 1.0]])
    gyr = np.array([[0.1, 0.0, 0.0], [0.0, 0.2, 0.0]])
    t = glrt_statistic(acc, gyr, 2, 1.0, 0.5)
    # the centred window of sample 1 is samples 0..1; sample 0's window is clipped to 0..1 too
    assert t[1] == pytest.approx(1.1)


def test_gravity_direction_comes_from_each_window():
    # two still periods at different tilts, separated by motion: both are stance
    rate, n = 100.0, 600
    t = np.arange(n) / rate
    acc = np.empty((n, 3))
    tilt = np.radians(30.0)
    acc[:200] = [0.0, 0.0, GRAVITY_MPS2]
    acc[400:] = [GRAVITY_MPS2 * np.sin(tilt), 0.0, GRAVITY_MPS2 * np.cos(tilt)]
    acc[200:400] = [5.0, 0.0, 15.0]
    gyr = np.zeros((n, 3))
    gyr[200:400] = [0.0, 4.0, 0.0]
    mask = GlrtDetector().detect(footnav.ImuData(t, acc, gyr)).mask
    assert mask[10:190].all() and mask[410:590].all()
    assert not mask[210:390].any()


@pytest.mark.parametrize("scenario, opts", [("straight", {"distance_m": 30.0}), ("rectangle", {"width_m": 20.0, "height_m": 10.0})])
@pytest.mark.parametrize("rate", [100.0, 400.0])
def test_every_simulated_step_and_f1(scenario, opts, rate):
    rec = footnav.simulate(scenario, seed=2, rate_hz=rate, **opts)
    det = GlrtDetector()
    for imu, truth in ((rec.left, rec.truth_left), (rec.right, rec.truth_right)):
        stance = det.detect(imu)
        steps = metrics.step_detection(stance.mask, truth.stance, tolerance_samples=0.15 * rate)
        assert steps.n_missed == 0 and steps.n_false == 0
        assert metrics.sample_scores(stance.mask, truth.stance).f1 >= 0.95


def test_rate_independence():
    lo = footnav.simulate("straight", seed=1, rate_hz=100.0, distance_m=15.0)
    hi = footnav.simulate("straight", seed=1, rate_hz=400.0, distance_m=15.0)
    a = GlrtDetector().detect(lo.left).intervals / 100.0
    b = GlrtDetector().detect(hi.left).intervals / 400.0
    assert a.shape == b.shape
    np.testing.assert_allclose(a, b, atol=0.03)  # stance edges agree within 3 samples at 100 Hz


def test_any_contains_center_contains_all():
    rec = footnav.simulate("straight", seed=0, distance_m=10.0)
    masks = {c: GlrtDetector(combine=c, min_stance_s=0.0).detect(rec.left).mask for c in ("any", "center", "all")}
    assert (masks["all"] <= masks["center"]).all() and (masks["center"] <= masks["any"]).all()
    assert masks["any"].sum() > masks["center"].sum() > masks["all"].sum()


def test_degenerate_recordings():
    rate = 100.0
    t = np.arange(200) / rate
    still = footnav.ImuData(t, np.tile([0.0, 0.0, GRAVITY_MPS2], (200, 1)), np.zeros((200, 3)))
    res = GlrtDetector().detect(still)
    assert res.mask.all() and res.n_stances == 1  # all standstill: one stance
    moving = footnav.ImuData(t, np.tile([3.0, 0.0, 15.0], (200, 1)), np.tile([0.0, 5.0, 0.0], (200, 1)))
    res = GlrtDetector().detect(moving)
    assert not res.mask.any() and res.n_stances == 0 and len(res.events["foot_flat"]) == 0


def test_bad_parameter():
    rec = footnav.simulate("straight", distance_m=5.0)
    with pytest.raises(footnav.InvalidParameterError, match="combine"):
        GlrtDetector(combine="most").detect(rec.left)
