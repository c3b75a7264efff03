"""Detector tests that kill mutants of ``tools/mutate.py`` the rest of the suite let through.

Expected values are counted by hand from the rules in the docstrings.
"""

from __future__ import annotations

import numpy as np

from footnav.core.types import stance_intervals
from footnav.detectors.threshold import stance_result


def _runs(mask):
    return stance_intervals(np.asarray(mask)).tolist()


# thr-min-stance-boundary: a stance of exactly min_stance_s (5 samples at 100 Hz) is kept, one of
# 4 samples is dropped
def test_a_stance_of_exactly_the_minimum_is_kept():
    mask = np.zeros(100, bool)
    mask[10:15] = True  # 5 samples
    mask[60:64] = True  # 4 samples
    out = stance_result(mask, 100.0, 0.05, 0.0, np.zeros(100), {})
    assert _runs(out.mask) == [[10, 15]]


# thr-min-swing-boundary: a gap of exactly min_swing_s (20 samples at 100 Hz) is a swing, one of
# 19 samples is bridged
def test_a_swing_of_exactly_the_minimum_is_kept():
    mask = np.zeros(200, bool)
    mask[0:30] = True
    mask[50:80] = True  # gap 30..50: 20 samples
    mask[99:130] = True  # gap 80..99: 19 samples
    out = stance_result(mask, 100.0, 0.0, 0.2, np.zeros(200), {})
    assert _runs(out.mask) == [[0, 30], [50, 130]]


# dual-gait-first-peak (written for it; it does not kill it, see docs/reliability.md): every heel
# strike of the simulator's truth is found, the first landing's too, within 2 samples
def test_dual_gait_finds_every_heel_strike_including_the_first():
    import footnav
    from footnav.detectors.dual_gait import DualGaitDetector

    rec = footnav.simulate("straight", seed=1, distance_m=8.0)
    left, right = DualGaitDetector().detect_pair(rec.left, rec.right)
    for found, truth in ((left, rec.truth_left), (right, rec.truth_right)):
        hs, ref = found.events["heel_strike"], truth.events["heel_strike"]
        assert len(hs) == len(ref)
        np.testing.assert_allclose(hs, ref, atol=2)


# hmm-model-samples: the HMM's model-rate grid runs from the recording's first sample to its last,
# both included: 2.0 s at 100 Hz is 201 model samples (0, 0.01, ..., 2.0 s after the start), and
# the recording's last sample maps to the last model sample, not to one 10 ms before it
def test_hmm_model_grid_covers_the_whole_recording():
    from footnav.core.types import ImuData
    from footnav.detectors.hmm.features import model_grid

    t = 0.5 + np.arange(401) / 200.0  # 200 Hz, exactly 2.0 s
    gyr = np.column_stack([t, 2 * t, -t])  # linear: interpolation is exact
    imu = ImuData(t=t, acc=np.tile([0.0, 0.0, 9.80665], (401, 1)), gyr=gyr)
    grid = model_grid(imu, "gyr", 100.0)
    assert len(grid.t_model) == 201
    assert grid.t_model[0] == 0.5 and abs(grid.t_model[-1] - 2.5) < 1e-12
    # sample k at 200 Hz is nearest to model sample round(k / 2)
    assert grid.nearest[-1] == 200 and grid.nearest[-2] == 200 and grid.nearest[-3] == 199
    # the low-pass filter (anti-alias at the model rate) leaves the linear ramp's ends slightly off;
    # the last model sample's feature is the recording's end, within the filter's edge effect
    assert abs(grid.features[-1, 0] - 2.5) < 0.05
