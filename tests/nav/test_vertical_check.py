"""footnav.nav.vertical_check: each condition of ``suspicious`` alone, both signs of a trend.

The walks are hand-built (flat stances joined by straight swings); every expected figure is
worked out from the stride list: trend = sum of the level strides' rises, rate = 100 trend / walked.
"""

from __future__ import annotations

import numpy as np
import pytest

from footnav.nav.floors import LEVEL_RISE_MAX_M
from footnav.nav.vertical_check import check_vertical
from footnav.types import FootTrajectory


def _walk(rises, stride_m=1.5, stance_n=10, swing_n=10):
    n = stance_n * (len(rises) + 1) + swing_n * len(rises)
    pos = np.zeros((n, 3))
    steps, k, h, x = [], 0, 0.0, 0.0
    for i in range(len(rises) + 1):
        steps.append((k, k + stance_n))
        pos[k : k + stance_n] = [x, 0.0, h]
        k += stance_n
        if i < len(rises):
            u = np.arange(1, swing_n + 1)[:, None] / (swing_n + 1)
            pos[k : k + swing_n] = [x, 0.0, h] + u * [stride_m, 0.0, rises[i]]
            h, x, k = h + rises[i], x + stride_m, k + swing_n
    return FootTrajectory(t=np.arange(n) / 100.0, position=pos, velocity=np.zeros((n, 3)),
                          quaternion=np.tile([1.0, 0, 0, 0], (n, 1)), position_std=np.zeros((n, 3)), steps=np.array(steps))


def test_a_steady_sinking_is_as_suspicious_as_a_steady_climb():
    # mutant: vcheck-rate-one-sided, vcheck-trend-one-sided. 20 strides of 1.5 m sinking 3 cm:
    # trend -0.6 m over 30 m, -2 m per 100 m, every stride alike
    check = check_vertical(_walk([-0.03] * 20))
    assert (check.level_strides, check.stair_strides) == (20, 0)
    assert check.trend_m == pytest.approx(-0.6) and check.walked_m == pytest.approx(30.0)
    assert check.rate_m_per_100m == pytest.approx(-2.0) and check.steady_fraction == 1.0
    assert check.suspicious
    assert "sinks 2.00 m per 100 m" in check.message("left", "ekf")


def test_too_few_level_strides_alone_say_nothing():
    # mutant: vcheck-and-or (7 level strides; every other condition holds)
    check = check_vertical(_walk([0.05] * 7))
    assert check.level_strides == 7 and abs(check.rate_m_per_100m) > 0.5 and check.trend_m >= 0.25
    assert not check.suspicious
    assert check_vertical(_walk([0.05] * 8)).suspicious


def test_a_small_rate_over_a_long_walk_alone_says_nothing():
    # 200 strides of 1.5 m rising 2 mm: trend 0.4 m (>= 0.25) but 0.13 m per 100 m (< 0.5)
    check = check_vertical(_walk([0.002] * 200))
    assert check.trend_m == pytest.approx(0.4) and check.rate_m_per_100m == pytest.approx(0.4 / 3.0)
    assert not check.suspicious


def test_a_small_trend_over_a_short_walk_alone_says_nothing():
    # 10 strides of 1.5 m rising 2 cm: 1.33 m per 100 m but 0.2 m in all (< 0.25)
    check = check_vertical(_walk([0.02] * 10))
    assert check.rate_m_per_100m == pytest.approx(0.2 / 15 * 100) and check.trend_m == pytest.approx(0.2)
    assert not check.suspicious
    assert check_vertical(_walk([0.026] * 10)).suspicious  # 0.26 m


def test_an_unsteady_trend_alone_says_nothing():
    # 10 strides up 12 cm and 10 down 6 cm... level strides must stay under LEVEL_RISE_MAX_M
    up, down = 0.9 * LEVEL_RISE_MAX_M, -0.5 * LEVEL_RISE_MAX_M
    check = check_vertical(_walk([up, down] * 10))
    assert check.steady_fraction == pytest.approx(0.5) and check.level_strides == 20
    assert abs(check.trend_m) >= 0.25 or abs(check.rate_m_per_100m) >= 0.5
    assert not check.suspicious


def test_a_big_drop_is_a_stair_not_a_level_stride():
    # mutant: vcheck-level-one-sided (a stride falling more than LEVEL_RISE_MAX_M is a stair down)
    check = check_vertical(_walk([-2.0 * LEVEL_RISE_MAX_M] * 5 + [0.0] * 5))
    assert (check.level_strides, check.stair_strides) == (5, 5)
    assert check.trend_m == 0.0 and not check.suspicious
