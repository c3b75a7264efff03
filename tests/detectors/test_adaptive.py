"""The gait-adaptive stance detector against hand-built gaits, the simulator and real running."""

from __future__ import annotations

import numpy as np
import pytest

import footnav
from footnav.analysis import metrics
from footnav.core.errors import DataNotFoundError, InvalidParameterError
from footnav.core.types import GRAVITY_MPS2, ImuData, stance_intervals
from footnav.detectors.adaptive import AdaptiveDetector
from footnav.detectors.threshold import ThresholdDetector


def test_finds_one_stance_per_cycle_where_the_foot_never_stops(never_still_gait):
    imu, truth = never_still_gait(floor_radps=0.9)
    assert ThresholdDetector().detect(imu).n_stances == 2  # only the standstills at the ends
    stance = AdaptiveDetector().detect(imu)
    steps = metrics.step_detection(stance.mask, truth, tolerance_samples=20)
    assert (steps.missed, steps.false) == (0, 0)
    # stance is the stride's quiet part: every true stance sample, and the swing only where it
    # turns slower than the bound, 3 x the floor (stance_factor)
    assert stance.mask[truth & (imu.gyr[:, 1] > 0)].all()  # the standstills' edges aside
    assert not (stance.mask & (imu.gyr[:, 1] > 3.0 * 0.9 + 0.1)).any()
    assert stance.meta["swing_peaks"].size == 13
    assert stance.meta["stride_s"] == pytest.approx(0.7, abs=0.01)


def test_walking_is_detected_as_by_threshold():
    rec = footnav.simulate("straight", distance_m=20.0, seed=3, rate_hz=100.0)
    for imu in (rec.left, rec.right):
        np.testing.assert_array_equal(AdaptiveDetector().detect(imu).mask, ThresholdDetector().detect(imu).mask)


@pytest.mark.parametrize("rate_hz", [60.0, 200.0, 820.0])
def test_simulated_walk_every_step_found(rate_hz):
    rec = footnav.simulate("rectangle", width_m=12.0, height_m=6.0, seed=1, rate_hz=rate_hz)
    stance = AdaptiveDetector().detect(rec.left)
    steps = metrics.step_detection(stance.mask, rec.truth_left.stance, tolerance_samples=int(0.15 * rate_hz))
    assert (steps.missed, steps.false) == (0, 0)


def test_bad_parameters_are_refused(never_still_gait):
    with pytest.raises(InvalidParameterError, match="min_scale"):
        AdaptiveDetector(min_scale=1.5).detect(never_still_gait(0.5)[0])
    with pytest.raises(InvalidParameterError, match="stance_factor"):
        AdaptiveDetector(stance_factor=0).detect(never_still_gait(0.5)[0])


def test_is_the_default_detector():
    assert footnav.make_pipeline().detector.name == "adaptive"


# the running trials of the pyshoe VICON set, where a walking bound drifts by metres
RUNNING = ["2017-11-27-11-11-53", "2017-11-27-11-13-41", "2017-11-27-11-18-11", "2017-12-15-18-02-28"]


@pytest.mark.parametrize("trial", RUNNING)
def test_real_running_trials_within_30_cm(trial):
    from footnav.data.datasets import load_dataset

    try:
        rec = load_dataset(f"pyshoe_{trial}")
    except DataNotFoundError:
        pytest.skip("shared data not found")
    result = footnav.make_pipeline().run(rec.left)
    truth = rec.truth_left
    est = np.stack([np.interp(truth.t, result.left.t, result.left.position[:, i]) for i in range(3)], axis=1)
    # 1.1-3.8 m with the threshold detector; the dataset's best detector tuned per trial: 0.06-0.14 m
    # (its trial_error, independent of footnav). Measured 2026-11-25: 0.041, 0.102, 0.117, 0.088 m;
    # 0.3 m is 2.6x the worst and about twice the dataset's best-tuned worst (0.14 m)
    assert metrics.ate_rmse(est, truth.position, dims=2) < 0.3
    assert result.meta["stance_check"]["left"]["suspicious"] is False


def _turn_between_rests(axis: int, acc_swing_mps2: float = 0.0, rate_hz: float = 100.0) -> ImuData:
    """1 s at rest, 0.4 s turning at up to 4 rad/s about body ``axis`` (gravity is body z), 1 s at rest."""
    rest, turn = int(rate_hz), int(0.4 * rate_hz)
    hump = 4.0 * np.sin(np.pi * np.arange(turn) / turn) ** 2
    gyr = np.zeros((2 * rest + turn, 3))
    gyr[rest : rest + turn, axis] = hump
    acc = np.tile([0.0, 0.0, GRAVITY_MPS2], (len(gyr), 1))
    acc[rest : rest + turn, 2] += acc_swing_mps2 * np.sin(2.0 * np.pi * np.arange(turn) / turn)
    return ImuData(t=np.arange(len(gyr)) / rate_hz, acc=acc, gyr=gyr)


def test_a_pivot_on_the_ground_is_one_stance():
    # turning about gravity with |f| = g: the foot pivots on its heel or toe, it does not step
    pivot = AdaptiveDetector().detect(_turn_between_rests(axis=2))
    assert pivot.n_stances == 1 and len(pivot.meta["pivots_s"]) == 1
    assert pivot.meta["pivots_s"][0] == pytest.approx(1.0, abs=0.1)
    # the same turn in pitch is a step; so is a turn about gravity while the foot accelerates
    assert AdaptiveDetector().detect(_turn_between_rests(axis=1)).n_stances == 2
    assert AdaptiveDetector().detect(_turn_between_rests(axis=2, acc_swing_mps2=8.0)).n_stances == 2
    # and pivot_yaw_share=1 turns the bridging off
    assert AdaptiveDetector(pivot_yaw_share=1.0).detect(_turn_between_rests(axis=2)).n_stances == 2


@pytest.mark.parametrize("mounting", [(40.0, -25.0, 120.0), (180.0, 0.0, 0.0)])
def test_any_mounting(mounting):
    # norms and the gravity direction of each stance: nothing assumes an axis
    rec = footnav.simulate("rectangle", width_m=12.0, height_m=6.0, seed=5, mounting_rpy_deg=mounting)
    stance = AdaptiveDetector().detect(rec.left)
    steps = metrics.step_detection(stance.mask, rec.truth_left.stance, tolerance_samples=15)
    assert (steps.missed, steps.false) == (0, 0)


def _shared_names(prefix: str) -> list[str]:
    from footnav.data.datasets import data_dir, dataset_names

    try:
        root = data_dir()
    except DataNotFoundError:
        pytest.skip("shared data not found")
    return [n for n in dataset_names(root) if n.startswith(prefix)]


@pytest.mark.filterwarnings("ignore::footnav.DataQualityWarning")  # IPOL's packet loss and left-foot scale, in meta
def test_ipol_hand_checked_steps():
    from footnav.data.datasets import load_dataset

    found = detected = reference = 0
    for name in _shared_names("ipol_"):
        rec = load_dataset(name)
        for imu, truth in ((rec.left, rec.truth_left), (rec.right, rec.truth_right)):
            swings = np.column_stack((truth.events["toe_off"], truth.events["heel_strike"]))
            steps = metrics.step_detection_from_swings(
                AdaptiveDetector().detect(imu).mask, swings, truth.meta["trial_boundaries"], tolerance_samples=10
            )
            found, detected, reference = found + steps.found, detected + steps.n_detected, reference + steps.n_reference
    # dev set (subjects 1-8): threshold scores 0.970 here, missing most of subject 4's fast steps.
    # Against IPOL's hand-checked footsteps (+-10 samples): measured 2026-11-25 F1 0.993 (1594
    # found of 1600 labelled, 1611 detected); 0.98 allows 2.8x today's 0.7 % of misses and extras
    assert reference > 1500 and 2 * found / (detected + reference) >= 0.98


def test_gaitdriven_every_footprint_within_a_metre():
    from footnav.data.datasets import load_dataset

    for name in _shared_names("gaitdriven_"):
        rec = load_dataset(name)
        truth = rec.truth_left
        result = footnav.make_pipeline().run(rec.left)
        # one stance per stride: the footprints are the strides' ends
        assert result.stance_left.n_stances >= len(truth.t)
        errors = metrics.footprint_errors(result.left.position, truth.position, index=truth.events["footprint"])
        # threshold: 32 m on trial 35. The publisher's own pyshoe baseline scores 0.91 m median and
        # 2.3 m worst on these 8 trials (data README): 1 m on every trial is about its median.
        # Measured 2026-11-25: 0.18-0.63 m (trial 35 the worst), so 1 m is 1.6x the worst
        assert errors.rmse_m <= 1.0, name


def _turn_between_tilted_rests(turn_axis, tilt_after_deg: float, rate_hz: float = 100.0) -> ImuData:
    """1 s at rest level (gravity along body z), 0.4 s turning at up to 4 rad/s about the unit body
    ``turn_axis``, then 1 s at rest tilted by ``tilt_after_deg`` about body x."""
    rest, turn = int(rate_hz), int(0.4 * rate_hz)
    hump = 4.0 * np.sin(np.pi * np.arange(turn) / turn) ** 2
    gyr = np.zeros((2 * rest + turn, 3))
    gyr[rest : rest + turn] = hump[:, None] * np.asarray(turn_axis, float)[None, :]
    acc = np.tile([0.0, 0.0, GRAVITY_MPS2], (len(gyr), 1))
    tilt = np.radians(tilt_after_deg)
    acc[rest + turn :] = GRAVITY_MPS2 * np.array([0.0, np.sin(tilt), np.cos(tilt)])
    return ImuData(t=np.arange(len(gyr)) / rate_hz, acc=acc, gyr=gyr)


def test_the_pivot_test_reads_the_stance_before_the_gap():
    # mutant: adaptive-pivot-up-next. The stances differ in tilt (level, then 50 deg), so "up"
    # taken from the stance before and from the stance after disagree. Share of the squared rate
    # about "up" (hand-computed): turning about the level z, 1 before / cos^2(50) = 0.41 after;
    # turning about the tilted up, cos^2(50) = 0.41 before / 1 after. The rule (share >= 0.9 of
    # the stance *before*: the foot pivots from where it stood) bridges the first only.
    tilt = np.radians(50.0)
    about_level = AdaptiveDetector().detect(_turn_between_tilted_rests([0.0, 0.0, 1.0], 50.0))
    assert about_level.n_stances == 1 and len(about_level.meta["pivots_s"]) == 1
    about_tilted = AdaptiveDetector().detect(_turn_between_tilted_rests([0.0, np.sin(tilt), np.cos(tilt)], 50.0))
    assert about_tilted.n_stances == 2 and len(about_tilted.meta["pivots_s"]) == 0


def _windows_of(imu, size, step):
    for a in range(0, imu.n_samples - size, step):
        yield a, a + size


@pytest.mark.parametrize("pivot_yaw_share", [0.9, 0.3])
def test_online_windows_give_detect_s_mask(pivot_yaw_share):
    """The stream's form of the detector (kept per-sample quantities, one window's mask) is
    ``detect`` on that window's ImuData, bit for bit, on windows starting anywhere (the
    cumulative sums are the window's own): the online decisions are the offline rule's."""
    rec = footnav.simulate("rectangle", width_m=12.0, height_m=6.0, seed=5, rate_hz=100.0)
    det = AdaptiveDetector(pivot_yaw_share=pivot_yaw_share)
    windows = det.online_windows()
    for imu in (rec.left, rec.right):
        features = windows.features(imu.acc, imu.gyr)
        pieces = [windows.features(imu.acc[a : a + 7], imu.gyr[a : a + 7]) for a in range(0, imu.n_samples, 7)]
        for f, chunked in zip(features, zip(*pieces)):  # per sample: the same whatever the chunks
            np.testing.assert_array_equal(np.concatenate(chunked), f)
        checked = 0
        for a, b in _windows_of(imu, 1041, 313):
            want = det.detect(imu.slice(a, b))
            got = windows.mask(imu.acc[a:b], imu.gyr[a:b], *(f[a:b] for f in features), imu.slice(a, b).rate_hz)
            np.testing.assert_array_equal(got, want.mask)
            checked += want.n_stances
        assert checked > 50


def test_the_compiled_sums_are_numpy_s():
    """The pivot test sums as numpy does (its pairwise summation, einsum's order in a row), so
    the compiled rule decides as the vectorised one it replaced; a numpy that sums otherwise
    fails here, not silently."""
    from footnav.nav.windows import pairwise_sum

    rng = np.random.default_rng(4)
    x = rng.lognormal(size=40000)
    for n in [*range(1, 300), 1000, 1023, 1025, 8193, 39999]:
        assert np.add.reduceat(x[:n], [0])[0] == x[0] + pairwise_sum(x, 1, n - 1), n
    w, u = rng.normal(size=(1000, 3)), rng.normal(size=(1000, 3))
    p = w * u
    np.testing.assert_array_equal(np.einsum("ij,ij->i", w, u), (p[:, 0] + p[:, 2]) + p[:, 1])


# mutant: adaptive-ceiling-max
# adaptive-ceiling-max: a cycle's bound is capped by the LOWER of its two swing peaks. Each
# foot alternates a normal swing and a flat shuffle (swing_scale: 15 % of the pitch and lift,
# ~0.8 rad/s RMS peak against ~5 rad/s) whose slow foot-flat rolls at a few tenths of a rad/s.
# The cap from the shuffle's peak (0.3 x 0.8 rad/s, about 0.2 rad/s) keeps that roll out of the
# stance; a cap from the higher neighbour leaves the base 0.5 rad/s bound, under which the
# stance begins during the roll, 60 ms before the foot is flat (measured 2026-11-25).
# Reference: the simulator's true stance. Tolerance 30 ms at 100 Hz: half the statistic's
# 0.04 s window (a centred window reaches into the motion 20 ms before it) plus one sample;
# measured today 20 ms at every edge, seeds 0-2, both feet.
@pytest.mark.parametrize("seed", [0, 1])
def test_stances_follow_the_truth_when_neighbouring_swings_differ(seed):
    rec = footnav.simulate(
        "straight", distance_m=6.0, seed=seed, swing_scale=(1.0, 0.15), heel_off_s=0.15, foot_flat_s=0.15, swing_s=0.4
    )
    for imu, truth in ((rec.left, rec.truth_left), (rec.right, rec.truth_right)):
        stance = AdaptiveDetector().detect(imu)
        found, true = stance_intervals(stance.mask), stance_intervals(truth.stance)
        assert len(found) == len(true)  # one detected stance per true stance, none split or merged
        # the shuffles are swings of their own: every cycle was found
        assert len(stance.meta["swing_peaks"]) == len(truth.events["toe_off"])
        edge_error_s = np.abs(found - true).max() / imu.rate_hz
        assert edge_error_s <= 0.03, edge_error_s


def _pivot(acc_amp_mps2: float, rate_hz: float = 100.0) -> ImuData:
    """1 s at rest, 0.4 s turning about gravity (body z) at up to 4 rad/s while |f| - g swings
    as ``acc_amp_mps2 sin(2 pi u)`` (the foot pressing and rising), 1 s at rest."""
    rest, turn = int(rate_hz), int(0.4 * rate_hz)
    u = np.arange(turn) / turn
    gyr = np.zeros((2 * rest + turn, 3))
    gyr[rest : rest + turn, 2] = 4.0 * np.sin(np.pi * u) ** 2
    acc = np.tile([0.0, 0.0, GRAVITY_MPS2], (len(gyr), 1))
    acc[rest : rest + turn, 2] += acc_amp_mps2 * np.sin(2.0 * np.pi * u)
    return ImuData(t=np.arange(len(gyr)) / rate_hz, acc=acc, gyr=gyr)


def _gap_acc_rms(imu: ImuData) -> float:
    """RMS of |f| - g over the gap between the two stances the detector sees without bridging."""
    runs = stance_intervals(AdaptiveDetector(pivot_yaw_share=1.0).detect(imu).mask)
    assert len(runs) == 2
    gap = slice(runs[0, 1], runs[1, 0])
    return float(np.sqrt(np.mean((np.linalg.norm(imu.acc[gap], axis=1) - GRAVITY_MPS2) ** 2)))


# mutant: adaptive-pivot-acc-not-squared
# adaptive-pivot-acc-not-squared: the rule is "RMS of |f| - g below pivot_acc_mps2" (2 m/s^2),
# compared as mean square < 4. A pivot whose gap has an RMS of 1.4-2 m/s^2 (a foot turning on its
# heel at 4 rad/s feels ~1.6 m/s^2 centripetal at 0.1 m) is bridged; 2.3 m/s^2 is a step.
def test_a_pivot_with_moderate_acceleration_is_bridged_and_a_stronger_one_is_not():
    moderate, strong = _pivot(2.2), _pivot(3.0)
    assert 1.5 < _gap_acc_rms(moderate) < 1.9  # 1.71 m/s^2: between sqrt(2) and 2: where the square matters
    assert 2.1 < _gap_acc_rms(strong)  # 2.30 m/s^2
    bridged = AdaptiveDetector().detect(moderate)
    assert bridged.n_stances == 1 and len(bridged.meta["pivots_s"]) == 1
    assert AdaptiveDetector().detect(strong).n_stances == 2
