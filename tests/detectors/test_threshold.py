from functools import cache

import numpy as np
import pytest

import footnav
from footnav.analysis import metrics
from footnav.core.errors import FootnavError, InvalidParameterError
from footnav.core.types import stance_intervals
from footnav.detectors.threshold import (
    AccMagnitudeDetector,
    AccVarianceDetector,
    AredDetector,
    ThresholdDetector,
    stance_result,
    window_samples,
    window_sums,
    windows_to_samples,
)

G = footnav.GRAVITY_MPS2
FAMILY = [ThresholdDetector, AccMagnitudeDetector, AccVarianceDetector, AredDetector]


def test_registry_names():
    assert [d.name for d in FAMILY] == ["threshold", "acc-magnitude", "acc-variance", "ared"]


# -- simulated walks -------------------------------------------------------------------------
@cache
def _walk(scenario: str, rate: float):
    opts = {"distance_m": 30.0} if scenario == "straight" else {"width_m": 20.0, "height_m": 10.0}
    return footnav.simulate(scenario, seed=2, rate_hz=rate, **opts)


@pytest.mark.parametrize("detector", FAMILY, ids=lambda d: d.name)
@pytest.mark.parametrize("scenario", ["straight", "rectangle"])
@pytest.mark.parametrize("rate", [100.0, 400.0])
def test_finds_every_step_of_a_simulated_walk(detector, scenario, rate):
    rec = _walk(scenario, rate)
    det = detector()
    for imu, truth in ((rec.left, rec.truth_left), (rec.right, rec.truth_right)):
        stance = det.detect(imu)
        steps = metrics.step_detection(stance.mask, truth.stance, tolerance_samples=int(0.15 * rate))
        assert steps.missed == 0 and steps.false == 0
        assert metrics.sample_scores(stance.mask, truth.stance).f1 >= 0.95


@pytest.mark.parametrize("detector", FAMILY, ids=lambda d: d.name)
@pytest.mark.parametrize("rate", [60.0, 820.0])
def test_defaults_work_at_the_ends_of_the_rate_range(detector, rate):
    rec = _walk("straight", rate)
    stance = detector().detect(rec.left)
    steps = metrics.step_detection(stance.mask, rec.truth_left.stance, tolerance_samples=int(0.15 * rate))
    assert steps.missed == 0 and steps.false == 0
    assert metrics.sample_scores(stance.mask, rec.truth_left.stance).f1 >= 0.95


@pytest.mark.parametrize("detector", FAMILY, ids=lambda d: d.name)
def test_events_bound_each_stance(detector):
    rec = _walk("straight", 100.0)
    stance = detector().detect(rec.left)
    runs = stance.intervals
    assert len(runs) > 10
    np.testing.assert_array_equal(stance.events["foot_flat"], runs[:, 0])
    np.testing.assert_array_equal(stance.events["heel_off"], runs[:, 1] - 1)
    assert stance.score.shape == stance.mask.shape
    assert stance.meta["window_samples"] == window_samples(detector().window_s, 100.0, rec.left.n_samples)


# -- statistics ------------------------------------------------------------------------------
def _imu(acc, gyr, rate=100.0):
    acc, gyr = np.asarray(acc, float), np.asarray(gyr, float)
    return footnav.ImuData(np.arange(len(acc)) / rate, acc, gyr)


def test_window_samples_is_odd_and_scales_with_rate():
    # 0.04 s: 2.4, 4, 8.19, 16, 32.8 samples -> the nearest odd number (ties upward)
    assert [window_samples(0.04, r, 10_000) for r in (60.0, 100.0, 204.8, 400.0, 820.0)] == [3, 5, 9, 17, 33]
    # a rate from the median interval is inexact: 400 samples at t = k / 100 give 99.99999999999991 Hz
    rate = 1 / np.median(np.diff(np.arange(400) / 100.0))
    assert rate != 100.0 and window_samples(0.04, rate, 400) == 5
    assert window_samples(0.001, 100.0, 50) == 1
    assert window_samples(1.0, 100.0, 7) == 7  # never longer than the recording


def test_window_sums_match_a_direct_sum():
    x = np.random.default_rng(0).normal(size=(50, 3))
    for win in (1, 4, 7, 50):
        direct = np.array([x[k : k + win].sum(axis=0) for k in range(50 - win + 1)])
        np.testing.assert_allclose(window_sums(x, win), direct, atol=1e-12)


def test_statistics_by_hand():
    # 3 samples, one 3-sample window: |w| = 0.3, 0.4, 0 rad/s -> RMS sqrt((0.09 + 0.16 + 0)/3) = sqrt(1/12)
    gyr = [[0.3, 0, 0], [0, 0.4, 0], [0, 0, 0]]
    # |f| - g = -1, 0, +2 m/s^2 -> RMS sqrt(5/3); f - f_mean along z: -4/3, -1/3, +5/3 -> RMS sqrt(42/27)
    acc = [[0, 0, G - 1], [0, 0, G], [0, 0, G + 2]]
    imu = _imu(acc, gyr)
    np.testing.assert_allclose(AredDetector(window_s=0.03).detect(imu).score, np.sqrt(1 / 12))
    np.testing.assert_allclose(AccMagnitudeDetector(window_s=0.03).detect(imu).score, np.sqrt(5 / 3))
    np.testing.assert_allclose(AccVarianceDetector(window_s=0.03).detect(imu).score, np.sqrt(42 / 27))
    # the combined score is the larger of the two ratios to their bounds: sqrt(1/12)/0.5 vs sqrt(5/3)/1.5
    combined = ThresholdDetector(window_s=0.03).detect(imu).score
    np.testing.assert_allclose(combined, max(np.sqrt(1 / 12) / 0.5, np.sqrt(5 / 3) / 1.5))


def test_variance_ignores_orientation_and_accelerometer_offset():
    rng = np.random.default_rng(1)
    acc = rng.normal(scale=0.05, size=(200, 3)) + [3.0, -2.0, 9.0]  # tilted, |f| = 9.7, not g
    std = AccVarianceDetector().detect(_imu(acc, np.zeros((200, 3)))).score
    assert np.all(std < 0.15)


# -- windows -> samples ----------------------------------------------------------------------
def test_combine_rules_on_a_small_example():
    # 10 samples, W = 3: windows k cover k..k+2 (8 windows); windows 2..4 are still (samples 2..6)
    still = np.zeros(8, dtype=bool)
    still[2:5] = True
    centre = windows_to_samples(still, 3, 10, "center")  # sample s uses window s-1 (clipped)
    any_ = windows_to_samples(still, 3, 10, "any")
    all_ = windows_to_samples(still, 3, 10, "all")
    np.testing.assert_array_equal(np.flatnonzero(centre), [3, 4, 5])
    np.testing.assert_array_equal(np.flatnonzero(any_), [2, 3, 4, 5, 6])
    np.testing.assert_array_equal(np.flatnonzero(all_), [4])


def test_combine_rules_nest_and_handle_the_ends():
    rng = np.random.default_rng(2)
    for win in (1, 2, 3, 8, 9):
        still = rng.random(40 - win + 1) < 0.6
        masks = {c: windows_to_samples(still, win, 40, c) for c in ("all", "center", "any")}
        assert not (masks["all"] & ~masks["center"]).any()
        assert not (masks["center"] & ~masks["any"]).any()
        # direct definition: the windows holding sample s are max(0, s-W+1) .. min(s, N-W)
        for s in range(40):
            held = still[max(0, s - win + 1) : min(s, 40 - win) + 1]
            assert masks["any"][s] == held.any() and masks["all"][s] == held.all()


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


def test_min_swing_bridges_a_short_gap_within_a_stance():
    mask = np.zeros(400, dtype=bool)
    mask[50:120] = True
    mask[125:200] = True  # 50 ms of rocking inside one stance
    mask[300:380] = True  # a real swing of 1 s before the next stance
    res = stance_result(mask, 100.0, 0.05, 0.2, np.zeros(400), {})
    np.testing.assert_array_equal(res.intervals, [[50, 200], [300, 380]])
    np.testing.assert_array_equal(res.events["foot_flat"], [50, 300])
    np.testing.assert_array_equal(res.events["heel_off"], [199, 379])
    # a blip shorter than min_stance_s is dropped before bridging: it cannot extend a stance
    blip = np.zeros(400, dtype=bool)
    blip[50:120] = True
    blip[130:133] = True
    np.testing.assert_array_equal(stance_result(blip, 100.0, 0.05, 0.2, np.zeros(400), {}).intervals, [[50, 120]])


# -- awkward recordings ----------------------------------------------------------------------
def _no_standstill(n=400, rate=100.0):
    # the foot never stops: it turns at 3 rad/s and accelerates by 3 m/s^2 throughout
    t = np.arange(n) / rate
    gyr = np.stack([3.0 * np.cos(4 * t), 3.0 * np.sin(4 * t), np.ones(n)], axis=1)
    acc = np.stack([3.0 * np.sin(7 * t), np.zeros(n), G + 3.0 * np.cos(7 * t)], axis=1)
    return footnav.ImuData(t, acc, gyr)


def _standstill(n=400, rate=100.0):
    rng = np.random.default_rng(3)
    acc = np.tile([0.0, 0.0, G], (n, 1)) + rng.normal(scale=0.01, size=(n, 3))
    gyr = rng.normal(scale=0.003, size=(n, 3))
    return footnav.ImuData(np.arange(n) / rate, acc, gyr)


@pytest.mark.parametrize("detector", FAMILY, ids=lambda d: d.name)
def test_no_standstill_gives_no_stance(detector):
    stance = detector().detect(_no_standstill())
    assert not stance.mask.any()
    assert len(stance.events["foot_flat"]) == 0 and len(stance.events["heel_off"]) == 0


@pytest.mark.parametrize("detector", FAMILY, ids=lambda d: d.name)
def test_all_standstill_is_one_stance(detector):
    stance = detector().detect(_standstill())
    assert stance.mask.all()
    np.testing.assert_array_equal(stance.intervals, [[0, 400]])
    np.testing.assert_array_equal(stance.events["foot_flat"], [0])
    np.testing.assert_array_equal(stance.events["heel_off"], [399])


@pytest.mark.parametrize("detector", FAMILY, ids=lambda d: d.name)
def test_short_recordings(detector):
    rec = _walk("straight", 100.0)
    two_s = rec.left.slice(150, 350)  # 2 s: standstill end, first step, part of the next
    stance = detector().detect(two_s)
    assert stance.mask.shape == (200,) and stance.mask.any() and not stance.mask.all()
    # shorter than the window: one window over the whole recording, no crash
    tiny = detector().detect(_standstill(n=3))
    assert tiny.mask.shape == (3,) and tiny.meta["window_samples"] <= 3


def test_a_walk_without_standstill_is_refused_by_the_pipeline_with_a_footnav_error():
    imu = _no_standstill()
    with pytest.raises(FootnavError, match="no stance"):
        footnav.make_pipeline(ThresholdDetector()).run(imu)


@pytest.mark.parametrize(
    "detector, param, value",
    [
        (ThresholdDetector, "window_s", 0.0),
        (ThresholdDetector, "gyr_threshold_radps", -1.0),
        (ThresholdDetector, "acc_tolerance_mps2", True),
        (AccMagnitudeDetector, "acc_tolerance_mps2", float("nan")),
        (AccVarianceDetector, "acc_std_threshold_mps2", "0.4"),
        (AredDetector, "combine", "middle"),
        (AredDetector, "min_stance_s", -0.1),
        (ThresholdDetector, "min_swing_s", None),
    ],
)
def test_invalid_parameters_are_named(detector, param, value):
    with pytest.raises(InvalidParameterError, match=f"{param}="):
        detector(**{param: value}).detect(_standstill())


def _runs(mask):
    return stance_intervals(np.asarray(mask)).tolist()


# mutant: thr-min-stance-boundary
# thr-min-stance-boundary: a stance of exactly min_stance_s (5 samples at 100 Hz) is kept, one of
# 4 samples is dropped
def test_a_stance_of_exactly_the_minimum_is_kept():
    mask = np.zeros(100, bool)
    mask[10:15] = True  # 5 samples
    mask[60:64] = True  # 4 samples
    out = stance_result(mask, 100.0, 0.05, 0.0, np.zeros(100), {})
    assert _runs(out.mask) == [[10, 15]]


# mutant: thr-min-swing-boundary
# thr-min-swing-boundary: a gap of exactly min_swing_s (20 samples at 100 Hz) is a swing, one of
# 19 samples is bridged
def test_a_swing_of_exactly_the_minimum_is_kept():
    mask = np.zeros(200, bool)
    mask[0:30] = True
    mask[50:80] = True  # gap 30..50: 20 samples
    mask[99:130] = True  # gap 80..99: 19 samples
    out = stance_result(mask, 100.0, 0.0, 0.2, np.zeros(200), {})
    assert _runs(out.mask) == [[0, 30], [50, 130]]
