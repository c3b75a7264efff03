"""The adaptive detector's per-cycle ceiling and pivot rule, written for two survivors of
``tools/mutate.py`` (docs/reliability.md): ``adaptive-ceiling-max`` and
``adaptive-pivot-acc-not-squared``.
"""

from __future__ import annotations

import numpy as np
import pytest

import footnav
from footnav.core.types import GRAVITY_MPS2, ImuData, stance_intervals
from footnav.detectors.adaptive import AdaptiveDetector


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
