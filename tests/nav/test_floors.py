"""footnav.nav.floors on hand-made strides: the stance height (a median of an even count), floors
counted down as well as up, a landing of exactly LANDING_STRIDES, a flight turning back, and the
holder's totals on both signs. Expected values worked out from the module's rules."""

from __future__ import annotations

import numpy as np
import pytest

from footnav.nav.floors import LANDING_STRIDES, LEVEL_RISE_MAX_M, FloorHolder, floor_changes, stance_heights


def test_stance_height_is_the_median_of_its_samples():
    # mutant: floors-upper-median. An even count's median is the mean of the middle two
    z = np.array([0.0, 1.0, 0.1, 0.3, 5.0, 3.0, 1.0, 2.0, 9.0])
    steps = np.array([[0, 4], [5, 8]])  # samples 0..3 (even) and 5..7 (odd)
    np.testing.assert_allclose(stance_heights(z, steps), [0.2, 2.0], atol=1e-15)


def test_a_descent_changes_the_floor_down():
    # mutant: floors-floor-one-sided. 9 stair strides of -0.34 m: -3.06 m, one storey down
    rise = np.full(9, -0.34)
    level, flights = floor_changes(rise, np.abs(rise) >= LEVEL_RISE_MAX_M)
    assert flights[0]["floors"] == -1 and level[-1] == -1 and level[0] == 0


def test_a_landing_of_landing_strides_joins_the_two_half_flights():
    # mutant: floors-landing-boundary. 5 strides up 0.34 m, 4 level, 5 up: one flight of 3.4 m
    rise = np.array([0.34] * 5 + [0.0] * LANDING_STRIDES + [0.34] * 5)
    level, flights = floor_changes(rise, np.abs(rise) >= LEVEL_RISE_MAX_M)
    assert len(flights) == 1 and flights[0]["rise_m"] == pytest.approx(3.4) and flights[0]["floors"] == 1
    assert flights[0]["first_stride"] == 0 and flights[0]["last_stride"] == 13 and level[-1] == 1
    # one level stride more and the halves (1.7 m each, under 1.8 m) are no floor
    rise = np.array([0.34] * 5 + [0.0] * (LANDING_STRIDES + 1) + [0.34] * 5)
    level, flights = floor_changes(rise, np.abs(rise) >= LEVEL_RISE_MAX_M)
    assert [f["floors"] for f in flights] == [0, 0] and level[-1] == 0


def test_a_flight_that_turns_back_is_two_flights():
    # mutant: floors-flight-sign-kept. 9 strides up 0.34 m then 9 down: up one floor and back
    rise = np.array([0.34] * 9 + [-0.34] * 9)
    level, flights = floor_changes(rise, np.abs(rise) >= LEVEL_RISE_MAX_M)
    assert [f["floors"] for f in flights] == [1, -1]
    assert level[9] == 1 and level[-1] == 0


def test_the_holders_totals_on_both_signs():
    # mutant: floors-stair-one-sided, floors-descent-sign. Stances 10 samples each, 0.4 m apart in
    # x, at heights 0, 0.01, 0.35, 0.7, 0.36, 0.02: rises +0.01 (level), +0.34, +0.35 (stairs up),
    # -0.34, -0.34 (stairs down)
    heights = [0.0, 0.01, 0.35, 0.7, 0.36, 0.02]
    t, p, s = [], [], []
    k = 0
    for i, h in enumerate(heights):
        for j in range(15):
            stance = j < 10
            t.append(k * 0.01)
            p.append([0.4 * i + (0.4 * (j - 9) / 6 if not stance else 0.0), 0.0, h])
            s.append(stance)
            k += 1
    n = len(t)
    holder = FloorHolder()
    holder.push(np.array(t), np.array(p), np.zeros((n, 3)), np.tile([1.0, 0, 0, 0], (n, 1)), np.array(s))
    holder.flush()
    fl = holder.floors()
    np.testing.assert_allclose(fl.rise_m, [0.01, 0.34, 0.35, -0.34, -0.34], atol=1e-12)
    assert list(fl.stair) == [False, True, True, True, True]
    assert fl.climb_m == pytest.approx(0.69) and fl.descent_m == pytest.approx(0.68)
    assert fl.removed_m == pytest.approx(0.01)


def test_stance_heights_are_each_stances_median_all_at_once_or_one_at_a_time():
    # one lexsort over every stance: numpy's median of each, bit for bit (a stream gives one at a time)
    rng = np.random.default_rng(5)
    z = rng.normal(size=2000)
    bounds = np.sort(rng.choice(np.arange(1, 2000), size=40, replace=False))
    steps = bounds.reshape(-1, 2)  # 20 stances of 1 to ~200 samples, even and odd counts
    together = stance_heights(z, steps)
    alone = np.concatenate([stance_heights(z, steps[i : i + 1]) for i in range(len(steps))])
    np.testing.assert_array_equal(together, alone)
    np.testing.assert_array_equal(together, [np.median(z[a:b]) for a, b in steps])
