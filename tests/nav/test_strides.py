"""footnav.nav.strides: which strides are standstill ones, each reason alone, on hand-built
10 Hz masks (the expected strides worked out from the module's two rules)."""

from __future__ import annotations

import numpy as np

from footnav.nav import quaternion as quat
from footnav.nav.strides import stride_parameters
from footnav.types import FootTrajectory


def _strides(stances, n):
    t = np.arange(n) * 0.1
    mask = np.zeros(n, bool)
    for a, b in stances:
        mask[a:b] = True
    pos = np.zeros((n, 3))
    pos[:, 0] = np.cumsum(~mask) * 0.1
    traj = FootTrajectory(t=t, position=pos, velocity=np.zeros((n, 3)), quaternion=quat.from_yaw(np.zeros(n)),
                          position_std=np.zeros((n, 3)), steps=np.empty((0, 2)))
    return stride_parameters(traj, mask)


def test_a_stride_long_in_duration_alone_is_a_standstill_one():
    # mutant: strides-standstill-and. Stances of 0.5 s every 1.2 s; the swing between the 4th and
    # 5th lasts 3 s (a stance the detector missed): that stride (mid 3 -> mid 4) lasts 3.7 s, more
    # than 2 x the median 1.2 s, though no stance is long
    starts = [0, 12, 24, 36, 78, 90, 102]
    s = _strides([(a, a + 5) for a in starts], 110)
    assert len(s) == 6
    assert list(np.flatnonzero(s["standstill"])) == [3]


def test_a_long_stance_alone_makes_both_its_strides_standstill_ones():
    # mutant: strides-standstill-mean, strides-standstill-k0-side. Stances of 0.5 s; the 4th is
    # 1.0 s (2 x the median 0.5 s > 1.5 x), its strides are ~1.45 s (< 2 x 1.2 s); the mean stance
    # (0.57 s) x 1.5 = 0.86 s would still flag it, so a 0.8 s stance tells the mean from the median
    starts = [0, 12, 24, 36, 53, 65, 77]
    lengths = [5, 5, 5, 10, 5, 5, 5]
    s = _strides([(a, a + w) for a, w in zip(starts, lengths)], 85)
    assert list(np.flatnonzero(s["standstill"])) == [2, 3]
    lengths = [5, 5, 5, 8, 5, 5, 5, 5, 5, 5, 14, 14, 14]  # 0.8 s: > 1.5 x median 0.5 = 0.75 s
    starts = list(np.cumsum([0] + [w + 7 for w in lengths[:-1]]))
    s = _strides([(a, a + w) for a, w in zip(starts, lengths)], starts[-1] + 14)
    # median stance 0.5 s: stance 3 (0.8 s) and the three 1.4 s ones are long; the mean (0.73 s)
    # x 1.5 = 1.1 s would leave stance 3 out
    flagged = set(np.flatnonzero(s["standstill"]))
    assert {2, 3} <= flagged and {9, 10, 11} <= flagged and not {0, 1, 4, 5, 6, 7} & flagged


def test_a_stride_from_a_two_sample_stance_after_a_long_one_is_not_a_standstill_one():
    # mutant: strides-standstill-k0-side. Stances of 5 samples every 12; the 4th lasts 10 (long),
    # the 5th only 2, so its mid-stance is its first sample. The stride from the 5th stance to
    # the 6th touches no long stance: only the two strides touching the 4th are standstill ones
    starts = [0, 12, 24, 36, 53, 62, 74, 86]
    lengths = [5, 5, 5, 10, 2, 5, 5, 5]
    s = _strides([(a, a + w) for a, w in zip(starts, lengths)], 95)
    assert s["start_index"][4] == 53
    assert list(np.flatnonzero(s["standstill"])) == [2, 3]
