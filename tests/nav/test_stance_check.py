"""footnav.nav.stance_check: the cycle rule on a shuffle whose swing peaks differ, the counts read.

A hand-built foot at 100 Hz: narrow bumps of angular rate (the swing peaks), each with or without
an acceleration burst (a swing accelerates, a pivot on the ground does not). The expected cycles
follow from the module's rule: consecutive peaks 0.55-2.5 s apart, *both* accelerating.

The stance self-check: counts and places gait cycles without a stance, and warns.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import footnav
from footnav.core.errors import DataNotFoundError, DataQualityWarning
from footnav.core.types import GRAVITY_MPS2, ImuData, StanceResult
from footnav.detectors.adaptive import AdaptiveDetector
from footnav.detectors.threshold import ThresholdDetector
from footnav.nav.stance_check import check_stances

from .conftest import _gait

RATE = 100.0


def _foot(peaks_s, accelerating, duration_s=None, stances=()):
    """Swing-like bumps at ``peaks_s`` (Gaussian, 6 rad/s, sigma 0.06 s); those flagged in
    ``accelerating`` also carry an 8 m/s^2 burst along z (|f| - g RMS ~4 m/s^2 over the window).
    ``stances``: (start_s, stop_s) pairs."""
    duration_s = duration_s or (max(peaks_s) + 1.0)
    t = np.arange(int(duration_s * RATE)) / RATE
    gyr = np.zeros((len(t), 3))
    acc = np.zeros((len(t), 3))
    acc[:, 2] = GRAVITY_MPS2
    for tk, moving in zip(peaks_s, accelerating):
        bump = np.exp(-0.5 * ((t - tk) / 0.06) ** 2)
        gyr[:, 1] += 6.0 * bump
        if moving:
            acc[:, 2] += 8.0 * bump
    mask = np.zeros(len(t), bool)
    for a, b in stances:
        mask[int(a * RATE) : int(b * RATE)] = True
    return ImuData(t=t, acc=acc, gyr=gyr), StanceResult(mask)


def test_a_cycle_needs_both_of_its_peaks_to_swing():
    # mutant: check-cycle-either-swings. Peaks 1 s apart at 1, 2, 3, 4, 5 s; the one at 3 s is a
    # pivot (no acceleration). No stance anywhere: the cycles are (1, 2) and (4, 5) only; the
    # rule with "either" would add (2, 3) and (3, 4).
    imu, st = _foot([1.0, 2.0, 3.0, 4.0, 5.0], [True, True, False, True, True])
    check = check_stances(imu, st)
    assert check.n_cycles == 2
    np.testing.assert_allclose(check.missed_s, [1.5, 4.5], atol=0.02)
    assert check.as_meta()["gait_cycles"] == 2 and check.as_meta()["cycles_without_stance"] == 2
    assert check.n_stances == 0 and len(check.over_swing_s) == 0


def test_a_stance_in_every_cycle_is_counted_and_none_missed():
    peaks = [1.0, 2.0, 3.0, 4.0]
    stances = [(1.4, 1.7), (2.4, 2.7), (3.4, 3.7)]
    imu, st = _foot(peaks, [True] * 4, stances=stances)
    check = check_stances(imu, st)
    assert (check.n_cycles, check.n_stances) == (3, 3)
    assert len(check.missed_s) == 0 and check.ok
    assert abs(check.stride_s - 1.0) < 1e-9
    # one cycle's stance removed: that cycle (2, 3) is missed, at its middle
    imu, st = _foot(peaks, [True] * 4, stances=[stances[0], stances[2]])
    check = check_stances(imu, st)
    assert (check.n_cycles, check.n_stances) == (3, 2)
    np.testing.assert_allclose(check.missed_s, [2.5], atol=0.02)


def test_the_cycle_holds_the_samples_after_its_first_peak_up_to_its_second():
    # mutant: check-count-offset, check-count-includes-peak. Peaks at samples 100 and 200.
    imu, st = _foot([1.0, 2.0], [True, True])
    one_after = st.mask.copy()
    one_after[101] = True  # a stance of one sample right after the first peak: the cycle has it
    assert len(check_stances(imu, StanceResult(one_after)).missed_s) == 0
    at_peak = st.mask.copy()
    at_peak[95:101] = True  # a stance ending on the first peak: not inside the cycle
    check = check_stances(imu, StanceResult(at_peak))
    assert check.n_cycles == 1 and len(check.missed_s) == 1
    before_second = st.mask.copy()
    before_second[199] = True  # the last sample before the second peak is inside
    assert len(check_stances(imu, StanceResult(before_second)).missed_s) == 0


def test_stride_bounds_exclude_pauses_and_half_strides():
    # mutant: check-max-stride-boundary. Intervals 0.4 s (two humps of one stride: not a cycle),
    # 2.4 s (a slow stride, under max_stride_s = 2.5 s: a cycle), 3 s (a pause: not a cycle)
    imu, st = _foot([1.0, 1.4, 3.8, 6.8], [True] * 4, duration_s=8.0)
    check = check_stances(imu, st)
    assert check.n_cycles == 1
    np.testing.assert_allclose(check.missed_s, [2.6], atol=0.02)
    # 2.45 s and 0.6 s are strides
    imu, st = _foot([1.0, 3.45, 4.05], [True] * 3, duration_s=5.0)
    assert check_stances(imu, st).n_cycles == 2


def test_a_stance_over_an_accelerating_peak_is_caught_and_over_a_pivot_is_not():
    imu, st = _foot([1.0, 2.0, 3.0], [True, False, True], stances=[(0.9, 1.1), (1.9, 2.1)])
    check = check_stances(imu, st)
    np.testing.assert_allclose(check.over_swing_s, [1.0], atol=0.02)
    assert check.as_meta()["stances_over_swing"] == 1


def test_cycles_without_stance_are_counted_and_placed(never_still_gait):
    imu, truth = never_still_gait(floor_radps=0.9, strides=12, stride_s=0.7)
    check = check_stances(imu, ThresholdDetector().detect(imu))
    # 13 swing peaks -> 12 strides between them, none holding a stance
    assert check.n_cycles == 12 and len(check.missed_s) == 12 and check.suspicious
    # each missed cycle sits between two swing peaks 0.7 s apart, one stride after the other
    np.testing.assert_allclose(np.diff(check.missed_s), 0.7, atol=0.02)
    assert check_stances(imu, StanceResult(mask=truth)).ok


def test_a_stance_over_a_swing_is_caught(never_still_gait):
    imu, _ = never_still_gait(floor_radps=0.9)
    check = check_stances(imu, StanceResult(mask=np.ones(imu.n_samples, bool)))
    assert len(check.over_swing_s) == 13 and len(check.missed_s) == 0 and check.suspicious


def test_the_pipeline_records_and_warns(never_still_gait):
    imu, _ = never_still_gait(floor_radps=0.9)
    pipe = footnav.make_pipeline("threshold")
    with pytest.warns(DataQualityWarning, match="12 of 12 gait cycles have no stance"):
        result = pipe.run(imu)
    assert result.meta["stance_check"]["left"]["cycles_without_stance"] == 12
    assert any("gait cycles have no stance" in w for w in result.meta["warnings"])
    # the default detector finds them, and nothing is said
    with warnings.catch_warnings():
        warnings.simplefilter("error", DataQualityWarning)
        ok = footnav.make_pipeline().run(imu)
    assert ok.meta["stance_check"]["left"]["ok"]


def test_a_simulated_walk_passes_quietly():
    rec = footnav.simulate("straight", distance_m=20.0, seed=2)
    with warnings.catch_warnings():
        warnings.simplefilter("error", DataQualityWarning)
        result = footnav.make_pipeline().run(rec.left, rec.right)
    assert result.meta["stance_check"]["left"]["ok"] and result.meta["stance_check"]["right"]["ok"]
    assert result.meta["stance_check"]["left"]["gait_cycles"] >= 12


def test_a_strict_detector_on_real_running_is_named():
    from footnav.data.datasets import load_dataset

    try:
        rec = load_dataset("pyshoe_2017-11-27-11-13-41")
    except DataNotFoundError:
        pytest.skip("shared data not found")
    pipe = footnav.make_pipeline("threshold", detector_params={"gyr_threshold_radps": 0.1})
    with pytest.warns(DataQualityWarning, match="gait cycles have no stance"):
        result = pipe.run(rec.left)
    check = result.meta["stance_check"]["left"]
    # a running foot never rests below 0.3 rad/s (footnav.detectors.adaptive's docstring; the
    # pyshoe running trials), so a 0.1 rad/s bound finds no stance in any gait cycle: every cycle
    # is flagged (measured 2026-11-25: 17 of 17)
    assert check["suspicious"] and check["cycles_without_stance"] >= 10
    assert check["cycles_without_stance"] == check["gait_cycles"]
    assert len(check["cycles_without_stance_at_s"]) == check["cycles_without_stance"]


def test_adaptive_result_has_no_stance_over_swing_on_the_never_still_gait(never_still_gait):
    imu, _ = never_still_gait(floor_radps=1.2, rate_hz=100.0)
    assert check_stances(imu, AdaptiveDetector().detect(imu)).ok


# mutant: check-over-swing-unfiltered
# check-over-swing-unfiltered: gyro peaks without the swing's acceleration (turning on the spot)
# are not swings, so a stance there is not reported as a stance in a swing
def test_turning_without_swinging_is_no_stance_in_a_swing():
    from footnav.nav.stance_check import check_stances

    imu = _gait(100.0, [1.0, 2.0, 3.0, 4.0, 5.0], 6.0, acc_swing=False)
    check = check_stances(imu, StanceResult(np.ones(imu.n_samples, bool)))
    assert len(check.over_swing_s) == 0 and check.n_cycles == 0


# mutant: check-missed-time
# check-missed-time: a gait cycle without stance is reported at the midpoint of its two swing peaks
def test_missed_stances_are_reported_between_the_swing_peaks():
    from footnav.nav.stance_check import check_stances

    imu = _gait(100.0, [1.0, 2.0, 3.0, 4.0, 5.0], 6.0)
    check = check_stances(imu, StanceResult(np.zeros(imu.n_samples, bool)))
    np.testing.assert_allclose(check.missed_s, [1.5, 2.5, 3.5, 4.5], atol=0.011)


# mutant: check-suspicious-boundary
# check-suspicious-boundary: "at least max(2, 5 %) of the gait cycles"
def test_two_bad_cycles_of_ten_are_suspicious_and_one_is_not():
    from footnav.nav.stance_check import StanceCheck

    def check(missed):
        return StanceCheck(
            n_cycles=10, n_stances=10, missed_s=np.array(missed), over_swing_s=np.array([]), stride_s=1.0
        )

    assert check([1.5, 2.5]).suspicious
    assert not check([1.5]).suspicious
