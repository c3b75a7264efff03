from functools import cache

import numpy as np
import pytest

import footnav
from footnav.analysis import metrics
from footnav.core.errors import InvalidParameterError
from footnav.detectors.glrt import GlrtDetector, glrt_statistic
from footnav.testing import DetectorContract

G = footnav.GRAVITY_MPS2


class TestGlrtAnyContract(DetectorContract):
    component = GlrtDetector
    params = {"combine": "any"}


def test_registry_name():
    assert GlrtDetector.name == "glrt"


@cache
def _walk(scenario: str, rate: float, seed: int = 2):
    opts = {"distance_m": 30.0} if scenario == "straight" else {"width_m": 20.0, "height_m": 10.0}
    return footnav.simulate(scenario, seed=seed, rate_hz=rate, **opts)


def _imu(acc, gyr, rate=100.0):
    acc, gyr = np.asarray(acc, float), np.asarray(gyr, float)
    return footnav.ImuData(np.arange(len(acc)) / rate, acc, gyr)


# -- the statistic ---------------------------------------------------------------------------
def test_statistic_by_hand():
    # One window of W = 3 samples.
    #   f = (g-1, 0, 0), (g, 1, 0), (g+1, -1, 0)  -> f_mean = (g, 0, 0), so g u = (g, 0, 0)
    #   f - g u = (-1, 0, 0), (0, 1, 0), (1, -1, 0)  -> squared norms 1, 1, 2: sum 4 (m/s^2)^2
    #   w = (0.1, 0, 0), (0, 0.2, 0), (0, 0, 0)      -> squared norms 0.01, 0.04, 0: sum 0.05 (rad/s)^2
    #   sigma_a = 0.5 m/s^2, sigma_g = 0.1 rad/s:
    #   T = (1/3) (4 / 0.25 + 0.05 / 0.01) = (1/3) (16 + 5) = 7
    acc = [[G - 1, 0, 0], [G, 1, 0], [G + 1, -1, 0]]
    gyr = [[0.1, 0, 0], [0, 0.2, 0], [0, 0, 0]]
    np.testing.assert_allclose(glrt_statistic(np.array(acc), np.array(gyr), 3, 0.5, 0.1), [7.0], rtol=1e-12)
    # through the detector (0.03 s at 100 Hz = 3 samples): every sample's score is that window's T
    det = GlrtDetector(window_s=0.03, sigma_acc_mps2=0.5, sigma_gyr_radps=0.1, gamma=7.5, min_stance_s=0.0)
    stance = det.detect(_imu(acc, gyr))
    np.testing.assert_allclose(stance.score, [7.0, 7.0, 7.0], rtol=1e-12)
    assert stance.mask.all()  # 7 < 7.5
    assert not det.clone(gamma=6.5).detect(_imu(acc, gyr)).mask.any()  # 7 > 6.5


def test_statistic_matches_openshoe_loop():
    """OpenShoe's GLRT.m, one window at a time, with each window's own gravity direction."""
    rng = np.random.default_rng(0)
    acc = rng.normal(size=(60, 3)) + [1.0, -2.0, 9.0]
    gyr = rng.normal(scale=0.5, size=(60, 3))
    sa, sg = 0.01, 0.1 * np.pi / 180
    for win in (1, 3, 8, 15):
        loop = []
        for k in range(60 - win + 1):
            f, w = acc[k : k + win], gyr[k : k + win]
            u = f.mean(axis=0) / np.linalg.norm(f.mean(axis=0))
            loop.append(np.sum((f - G * u) ** 2) / sa**2 / win + np.sum(w**2) / sg**2 / win)
        np.testing.assert_allclose(glrt_statistic(acc, gyr, win, sa, sg), loop, rtol=1e-9)


def test_gravity_direction_is_each_windows_own():
    # 1.5 s still and flat, 1 s of motion, 1.5 s still with the foot tilted 60 deg about y
    rate, rng = 100.0, np.random.default_rng(4)
    t = np.arange(100) / rate
    tilt = np.deg2rad(60.0)
    acc = np.concatenate(
        [
            np.tile([0.0, 0.0, G], (150, 1)),
            np.stack([4 * np.sin(9 * t), np.zeros(100), G + 4 * np.cos(9 * t)], axis=1),
            np.tile([G * np.sin(tilt), 0.0, G * np.cos(tilt)], (150, 1)),
        ]
    ) + rng.normal(scale=0.01, size=(400, 3))
    gyr = np.concatenate([np.zeros((150, 3)), np.tile([0.0, 5.0, 0.0], (100, 1)), np.zeros((150, 3))])
    gyr = gyr + rng.normal(scale=0.003, size=(400, 3))
    stance = GlrtDetector().detect(_imu(acc, gyr, rate))
    w = stance.meta["window_samples"]
    assert stance.mask[: 150 - w].all() and stance.mask[250 + w :].all()  # both still periods
    assert not stance.mask[150 + w : 250 - w].any()
    # the centred window leaves a stance edge W//2 samples inside the still period
    np.testing.assert_array_equal(stance.intervals, [[0, 150 - w // 2], [250 + w // 2, 400]])
    # with one gravity direction for the whole recording the tilted period would not be still:
    # its specific force is ~30 deg off the average direction, ~5 m/s^2 -> T ~ 2.5e5 > gamma
    u = acc.mean(axis=0) / np.linalg.norm(acc.mean(axis=0))
    t_global = np.sum((acc[260:390] - G * u) ** 2, axis=1) / GlrtDetector().sigma_acc_mps2 ** 2
    assert np.all(t_global > GlrtDetector().gamma)


# -- simulated walks -------------------------------------------------------------------------
@pytest.mark.parametrize("scenario", ["straight", "rectangle"])
@pytest.mark.parametrize("rate", [100.0, 400.0])
def test_finds_every_step_of_a_simulated_walk(scenario, rate):
    rec = _walk(scenario, rate)
    det = GlrtDetector()
    for imu, truth in ((rec.left, rec.truth_left), (rec.right, rec.truth_right)):
        stance = det.detect(imu)
        steps = metrics.step_detection(stance.mask, truth.stance, tolerance_samples=int(0.15 * rate))
        assert steps.missed == 0 and steps.false == 0
        assert metrics.sample_scores(stance.mask, truth.stance).f1 >= 0.95
        np.testing.assert_array_equal(stance.events["foot_flat"], stance.intervals[:, 0])
        np.testing.assert_array_equal(stance.events["heel_off"], stance.intervals[:, 1] - 1)


@pytest.mark.parametrize("rate", [60.0, 820.0])
def test_defaults_work_at_the_ends_of_the_rate_range(rate):
    rec = _walk("straight", rate)
    stance = GlrtDetector().detect(rec.left)
    steps = metrics.step_detection(stance.mask, rec.truth_left.stance, tolerance_samples=int(0.15 * rate))
    assert steps.missed == 0 and steps.false == 0
    assert metrics.sample_scores(stance.mask, rec.truth_left.stance).f1 >= 0.95


@pytest.mark.parametrize("combine", ["center", "any", "all"])
def test_same_stance_at_100_and_400_hz(combine):
    # the simulator's truth is the same walk at both rates; the window is in seconds and T a
    # per-sample mean, so the stance edges agree in time to within two 100 Hz samples
    det = GlrtDetector(combine=combine)
    slow = det.detect(_walk("straight", 100.0, seed=1).left).intervals / 100.0
    fast = det.detect(_walk("straight", 400.0, seed=1).left).intervals / 400.0
    assert slow.shape == fast.shape and len(slow) > 20
    assert np.abs(slow - fast).max() <= 2 / 100.0


def test_any_contains_center_contains_all():
    imu = _walk("rectangle", 100.0).left
    masks = {c: GlrtDetector(combine=c).detect(imu).mask for c in ("any", "center", "all")}
    assert not (masks["all"] & ~masks["center"]).any()
    assert not (masks["center"] & ~masks["any"]).any()
    assert masks["any"].sum() > masks["center"].sum() > masks["all"].sum()
    # W = 5 at 100 Hz: each stance edge moves by W//2 = 2 samples between the rules
    n_stances = GlrtDetector().detect(imu).n_stances
    assert masks["any"].sum() - masks["all"].sum() == pytest.approx(8 * n_stances, rel=0.1)


# -- awkward recordings ----------------------------------------------------------------------
def test_no_standstill_gives_no_stance():
    t = np.arange(400) / 100.0
    gyr = np.stack([3.0 * np.cos(4 * t), 3.0 * np.sin(4 * t), np.ones(400)], axis=1)
    acc = np.stack([3.0 * np.sin(7 * t), np.zeros(400), G + 3.0 * np.cos(7 * t)], axis=1)
    stance = GlrtDetector().detect(_imu(acc, gyr))
    assert not stance.mask.any() and len(stance.events["foot_flat"]) == 0
    assert np.all(stance.score > GlrtDetector().gamma)


def test_all_standstill_is_one_stance():
    rng = np.random.default_rng(5)
    acc = np.tile([0.0, 0.0, G], (400, 1)) + rng.normal(scale=0.01, size=(400, 3))
    stance = GlrtDetector().detect(_imu(acc, rng.normal(scale=0.003, size=(400, 3))))
    np.testing.assert_array_equal(stance.intervals, [[0, 400]])
    np.testing.assert_array_equal(stance.events["heel_off"], [399])


def test_short_recordings():
    two_s = _walk("straight", 100.0).left.slice(150, 350)
    stance = GlrtDetector().detect(two_s)
    assert stance.mask.shape == (200,) and stance.mask.any() and not stance.mask.all()
    tiny = GlrtDetector().detect(_imu(np.tile([0.0, 0.0, G], (2, 1)), np.zeros((2, 3))))
    assert tiny.meta["window_samples"] == 2 and tiny.score.shape == (2,)


@pytest.mark.parametrize(
    "param, value",
    [
        ("gamma", 0.0),
        ("sigma_acc_mps2", -0.01),
        ("sigma_gyr_radps", float("inf")),
        ("window_s", None),
        ("combine", "majority"),
        ("min_swing_s", -1.0),
    ],
)
def test_invalid_parameters_are_named(param, value):
    rng = np.random.default_rng(6)
    imu = _imu(np.tile([0.0, 0.0, G], (50, 1)), rng.normal(scale=0.01, size=(50, 3)))
    with pytest.raises(InvalidParameterError, match=f"{param}="):
        GlrtDetector(**{param: value}).detect(imu)
