"""The stance self-check: counts and places gait cycles without a stance, and warns."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import footnav
from footnav.errors import DataNotFoundError, DataQualityWarning
from footnav.nav.stance_check import check_stances
from footnav.types import StanceResult
from footnav.detectors.adaptive import AdaptiveDetector
from footnav.detectors.threshold import ThresholdDetector


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
