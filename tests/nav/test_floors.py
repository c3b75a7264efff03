"""footnav.nav.floors on hand-made strides: the stance height (a median of an even count), floors
counted down as well as up, a landing of exactly LANDING_STRIDES, a flight turning back, and the
holder's totals on both signs. Expected values worked out from the module's rules.

footnav.nav.floors on hand-built walks: level strides held, stairs kept, floors counted.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from footnav.core.types import FootTrajectory
from footnav.nav.floors import (
    FLOOR_MIN_RISE_M,
    LANDING_STRIDES,
    LEVEL_RISE_MAX_M,
    FloorHolder,
    floor_changes,
    hold_floors,
    stance_heights,
    stance_swing_rises,
    swing_offsets,
    swing_rises,
)


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


RATE_HZ = 100.0


def _walk(rises, stance_n=40, swing_n=60):
    """A foot whose stances are flat and whose swings climb linearly in time by ``rises`` (m),
    moving forward at 1 m/s: its FootTrajectory."""
    n_strides = len(rises)
    n = stance_n * (n_strides + 1) + swing_n * n_strides
    t = np.arange(n) / RATE_HZ
    z, vz = np.zeros(n), np.zeros(n)
    steps, k, h = [], 0, 0.0
    for i in range(n_strides + 1):
        steps.append((k, k + stance_n))
        z[k : k + stance_n] = h
        k += stance_n
        if i < n_strides:
            # from the last stance sample to the first of the next: linear in time
            z[k : k + swing_n] = h + rises[i] * np.arange(1, swing_n + 1) / (swing_n + 1)
            vz[k : k + swing_n] = rises[i] / ((swing_n + 1) / RATE_HZ)  # its slope, m/s
            h, k = h + rises[i], k + swing_n
    pos = np.zeros((n, 3))
    pos[:, 0] = t
    pos[:, 2] = z
    vel = np.zeros((n, 3))
    vel[:, 0] = 1.0
    vel[:, 2] = vz
    q = np.tile([1.0, 0.0, 0.0, 0.0], (n, 1))
    return FootTrajectory(
        t=t, position=pos, velocity=vel, quaternion=q, position_std=np.zeros((n, 3)), steps=np.array(steps)
    )


def _vertical(traj):
    return traj.meta["vertical"]


def test_level_strides_are_held_at_the_first_stance_height_and_the_drift_reported():
    rises = [0.02, 0.03, -0.01, 0.025]
    walk = _walk(rises)
    held = hold_floors(walk)
    v = _vertical(held)
    assert v["level_strides"] == 4 and v["stair_strides"] == 0
    assert v["removed_m"] == pytest.approx(sum(rises))
    assert v["removed_m_per_100m"] == pytest.approx(100 * sum(rises) / (held.footprints[-1, 0] - held.footprints[0, 0]))
    assert v["climb_m"] == 0.0 and v["descent_m"] == 0.0 and v["floors_changed"] == 0
    # a swing's climb is linear in time from the last stance sample to the next stance's first,
    # as the correction is: the whole walk is flat, sample by sample, and so is its velocity
    assert np.allclose(held.position[:, 2], 0.0, atol=1e-12)
    assert np.allclose(held.velocity[:, 2], 0.0, atol=1e-9)
    assert np.array_equal(held.position[:, :2], walk.position[:, :2])  # the plane untouched
    assert np.allclose(walk.position[-1, 2], sum(rises))  # a new trajectory: the input as it was


def test_stair_strides_keep_their_rise_and_a_storey_changes_the_level():
    rises = [0.02] + [0.34] * 8 + [0.02, 0.01] + [-0.34] * 8 + [0.02]
    walk = _walk(rises)
    held = hold_floors(walk)
    h = stance_heights(held.position[:, 2], held.steps)
    assert np.allclose(np.diff(h), np.where(np.abs(rises) >= LEVEL_RISE_MAX_M, rises, 0.0), atol=1e-12)
    v = _vertical(held)
    assert v["stair_strides"] == 16
    assert v["climb_m"] == pytest.approx(8 * 0.34) and v["descent_m"] == pytest.approx(8 * 0.34)
    assert v["removed_m"] == pytest.approx(0.07)  # 0.02 + 0.02 + 0.01 + 0.02
    assert [f["floors"] for f in v["flights"]] == [1, -1] and v["floors_up"] == 1 and v["floors_down"] == 1
    assert h[-1] == pytest.approx(0.0, abs=1e-12) and walk.position[-1, 2] == pytest.approx(0.07)


def test_a_landing_joins_two_half_flights_and_half_a_storey_is_no_floor():
    half = [0.3] * 4  # 1.2 m each, below FLOOR_MIN_RISE_M
    assert 4 * 0.3 < FLOOR_MIN_RISE_M <= 8 * 0.3
    rises = np.array(half + [0.0, 0.01] + half)
    level, flights = floor_changes(rises, np.abs(rises) >= LEVEL_RISE_MAX_M)
    assert len(flights) == 1 and flights[0]["floors"] == 1 and flights[0]["rise_m"] == pytest.approx(2.4)
    assert level.tolist() == [0] * 10 + [1]
    level, flights = floor_changes(rises[:4], np.ones(4, bool))
    assert flights[0]["floors"] == 0 and level[-1] == 0
    # a long corridor between them makes two flights, neither a floor
    rises = np.array(half + [0.0] * 6 + half)
    level, flights = floor_changes(rises, np.abs(rises) >= LEVEL_RISE_MAX_M)
    assert [f["floors"] for f in flights] == [0, 0]
    # three storeys in one flight
    level, flights = floor_changes(np.full(27, -0.34), np.ones(27, bool))
    assert flights[0]["floors"] == -3 and level[-1] == -3


@pytest.mark.parametrize("chunk", [1, 7, 100, 350, 777, 10_000])
def test_the_holder_fed_in_chunks_gives_the_whole_walk_s_numbers(chunk):
    rng = np.random.default_rng(0)
    rises = list(rng.normal(0.0, 0.04, 12)) + [0.3, 0.3, 0.3]
    walk = _walk(rises)
    whole = hold_floors(walk)
    holder = FloorHolder()
    s = np.zeros(len(walk.t), bool)
    for a, b in walk.steps:
        s[a:b] = True
    got, n = [], len(walk.t)
    for i in range(0, n, chunk):
        j = min(n, i + chunk)
        closed = j < n and s[j - 1] and not s[j]  # what the stream knows: the stance has ended
        got.append(
            holder.push(
                walk.t[i:j], walk.position[i:j], walk.velocity[i:j], walk.quaternion[i:j], s[i:j], closed=closed
            )
        )
    got.append(holder.flush())
    t, p, v, q, stance = (np.concatenate(x) for x in zip(*got))
    assert np.array_equal(t, walk.t) and np.array_equal(stance, s) and np.array_equal(q, walk.quaternion)
    assert np.array_equal(p, whole.position) and np.array_equal(v, whole.velocity)
    meta = {"model": "floors", **holder.floors().to_meta()}
    assert meta == _vertical(whole)


def test_a_stance_is_not_released_before_it_is_known_to_have_ended():
    walk = _walk([0.02, 0.02])
    s = np.zeros(len(walk.t), bool)
    for a, b in walk.steps:
        s[a:b] = True
    holder = FloorHolder()
    a1, b1 = walk.steps[1]
    # up to the middle of the second stance: the first stance is closed by the swing after it,
    # the swing waits for the second stance's height
    out = holder.push(
        walk.t[: a1 + 5], walk.position[: a1 + 5], walk.velocity[: a1 + 5], walk.quaternion[: a1 + 5], s[: a1 + 5]
    )
    assert len(out[0]) == walk.steps[0, 1]  # the first stance (closed by the swing after it)
    out = holder.push(
        walk.t[a1 + 5 : b1],
        walk.position[a1 + 5 : b1],
        walk.velocity[a1 + 5 : b1],
        walk.quaternion[a1 + 5 : b1],
        s[a1 + 5 : b1],
        closed=True,
    )
    assert len(out[0]) == b1 - walk.steps[0, 1]  # the swing and the second stance, now held
    assert np.allclose(out[1][-1, 2], 0.0, atol=1e-12)
    assert holder.held_at(float(walk.t[walk.steps[0, 1] - 1]) - 0.5) is None  # no stance ended there
    assert holder.held_at(float(walk.t[b1 - 1])) == pytest.approx(-0.02)
    assert holder.held_at(float(walk.t[b1 - 1])) is None  # asked once: forgotten, as the first stance was


def test_an_endless_stream_keeps_no_stride_records():
    # the online stream with keep=False: the same samples held, nothing that grows with the walk
    walk = _walk([0.02, -0.01, 0.015, 0.3, 0.01])
    s = np.zeros(len(walk.t), bool)
    for a, b in walk.steps:
        s[a:b] = True
    kept, bounded = FloorHolder(), FloorHolder(keep_strides=False)
    rows = [h.push(walk.t, walk.position, walk.velocity, walk.quaternion, s, closed=True) for h in (kept, bounded)]
    for a, b in zip(*rows):
        assert np.array_equal(a, b)
    assert len(kept.rises) == 5 and bounded.rises == [] and bounded.walked_m == kept.walked_m
    ends = walk.t[walk.steps[:, 1] - 1]
    assert [bounded.held_at(float(t)) for t in ends] == [kept.held_at(float(t)) for t in ends]
    assert not bounded._held_at  # each asked once: none left
    with pytest.raises(RuntimeError, match="keep_strides=False"):
        bounded.floors()


def test_fewer_than_two_stances_change_nothing():
    walk = _walk([0.03])
    one = FootTrajectory(
        t=walk.t,
        position=walk.position,
        velocity=walk.velocity,
        quaternion=walk.quaternion,
        position_std=walk.position_std,
        steps=walk.steps[:1],
    )
    held = hold_floors(one)
    assert np.array_equal(held.position, walk.position)
    assert _vertical(held)["level_strides"] == 0 and _vertical(held)["floors_changed"] == 0


# -- the swing's own rise ---------------------------------------------------------------------


def test_the_swing_rise_is_the_height_before_the_update_less_the_last_update_s():
    # updates at 0-1, 4-5 and 8; heights by hand: 1.0 at sample 1 (the last update), 1.5 at
    # sample 3 (just before the next run), 1.3 at 5, 1.2 at 7
    z = np.array([0.0, 1.0, 1.2, 1.5, 1.4, 1.3, 1.1, 1.2, 0.9])
    zupt = np.array([1, 1, 0, 0, 1, 1, 0, 0, 1], bool)
    rise, carry = swing_rises(z, zupt)
    assert np.flatnonzero(np.isfinite(rise)).tolist() == [4, 8]  # the first run has nothing before it
    np.testing.assert_allclose(rise[[4, 8]], [1.5 - 1.0, 1.2 - 1.3], atol=1e-15)
    assert carry == (0.9, True, 0.9)
    # the stances' values: the first finite one within each
    np.testing.assert_allclose(
        stance_swing_rises(rise, np.array([[0, 2], [3, 6], [8, 9]])), [np.nan, 0.5, -0.1], atol=1e-15
    )


@pytest.mark.parametrize("chunk", [1, 2, 3, 5])
def test_the_swing_rise_in_chunks_is_the_whole_s(chunk):
    rng = np.random.default_rng(3)
    z = rng.normal(size=40)
    zupt = rng.random(40) < 0.5
    whole, _ = swing_rises(z, zupt)
    carry, got = (np.nan, False, np.nan), []
    for i in range(0, 40, chunk):
        part, carry = swing_rises(z[i : i + chunk], zupt[i : i + chunk], carry)
        got.append(part)
    np.testing.assert_array_equal(np.concatenate(got), whole)


def _with_swing(walk, swing):
    """``walk`` whose stances 1.. report ``swing`` (m) as the strapdown's rise before them."""
    return replace(walk, swing_rise_m=np.concatenate(([np.nan], swing)))


def test_a_stride_the_strapdown_did_not_climb_is_held_level():
    # the filter rises 0.15 m on strides 1 and 2; the strapdown rose on stride 1 only, stride 2
    # it did not (a false residual at the landing), stride 3 rose the other way: held
    rises = [0.02, 0.15, 0.15, 0.15, 0.30]
    swing = [0.0, 0.12, 0.01, -0.2, 0.09]
    held = hold_floors(_with_swing(_walk(rises), swing))
    h = stance_heights(held.position[:, 2], held.steps)
    np.testing.assert_allclose(np.diff(h), [0.0, 0.15, 0.0, 0.0, 0.30], atol=1e-12)
    v = _vertical(held)
    assert v["stair_strides"] == 2 and v["swing_held_strides"] == 2 and v["level_strides"] == 3
    assert v["removed_m"] == pytest.approx(0.32) and v["climb_m"] == pytest.approx(0.45)
    # unknown (NaN) the filter's rise decides alone, as with no swing rise at all
    plain = hold_floors(_walk(rises))
    nan = hold_floors(_with_swing(_walk(rises), [np.nan] * 5))
    assert np.array_equal(nan.position, plain.position) and _vertical(plain)["swing_held_strides"] == 0
    assert _vertical(plain)["stair_strides"] == 4


@pytest.mark.parametrize("chunk", [1, 7, 350])
def test_the_holder_with_swing_rises_in_chunks_gives_the_whole_walk_s(chunk):
    rng = np.random.default_rng(1)
    rises = list(rng.normal(0.0, 0.1, 14))
    walk = _with_swing(_walk(rises), rng.normal(0.0, 0.1, 14))
    whole = hold_floors(walk)
    assert 0 < _vertical(whole)["swing_held_strides"] < _vertical(whole)["level_strides"]
    s = np.zeros(len(walk.t), bool)
    sw = np.full(len(walk.t), np.nan)
    for (a, b), r in zip(walk.steps, walk.swing_rise_m):
        s[a:b] = True
        sw[a + 2] = r  # within the stance: its first update need not be its first sample
    holder, got, n = FloorHolder(), [], len(walk.t)
    for i in range(0, n, chunk):
        j = min(n, i + chunk)
        closed = j < n and s[j - 1] and not s[j]
        got.append(
            holder.push(
                walk.t[i:j],
                walk.position[i:j],
                walk.velocity[i:j],
                walk.quaternion[i:j],
                s[i:j],
                closed=closed,
                swing_rise=sw[i:j],
            )
        )
    got.append(holder.flush())
    p = np.concatenate([g[1] for g in got])
    assert np.array_equal(p, whole.position)
    assert {"model": "floors", **holder.floors().to_meta()} == _vertical(whole)


def test_a_swing_rise_per_step_must_match_the_steps():
    walk = _walk([0.02, 0.02])
    from footnav.core.errors import InvalidInputError

    with pytest.raises(InvalidInputError, match="swing_rise_m"):
        replace(walk, swing_rise_m=np.zeros(2))


def test_a_strapdown_that_loses_height_at_every_stride_keeps_the_stairs():
    # an accelerometer that clips loses height in the strapdown at every stride alike (the
    # simulator's storey clipped at 3 g: -0.14 m per stride): its level strides' swing rise is
    # its offset, and a half-flight stride of +0.17 m whose swing rose only +0.03 m is a stair
    rises = [0.0, -0.02, 0.01, 0.17, 0.34, 0.0]
    swing = [-0.14, -0.15, -0.13, 0.03, 0.20, -0.14]
    held = hold_floors(_with_swing(_walk(rises), swing))
    v = _vertical(held)
    assert v["stair_strides"] == 2 and v["swing_held_strides"] == 0
    np.testing.assert_allclose(
        swing_offsets(np.array(rises), np.array(swing))[0], [0.0, 0.14, 0.145, 0.14, 0.14, 0.14], atol=1e-12
    )
    # with no level stride before it, the same stride has nothing to correct it: held
    first = hold_floors(_with_swing(_walk(rises[3:]), swing[3:]))
    assert _vertical(first)["swing_held_strides"] == 1 and _vertical(first)["stair_strides"] == 1


def test_a_sound_strapdown_s_scatter_is_no_offset_and_half_the_bound_is_a_stair():
    # level strides' swing rises of -0.02 m (within the scatter of a sound strapdown) give no
    # offset; a flight's first stride, 0.08 m in the filter and 0.07 m in the strapdown (gaitmap's
    # stairs, left foot), is a stair; 0.03 m in the strapdown is not
    rises = np.array([0.0, 0.01, 0.08, 0.08])
    swing = np.array([-0.02, -0.03, 0.07, 0.03])
    np.testing.assert_array_equal(swing_offsets(rises, swing)[0], np.zeros(4))
    held = hold_floors(_with_swing(_walk(list(rises)), list(swing)))
    assert _vertical(held)["stair_strides"] == 1 and _vertical(held)["swing_held_strides"] == 1


def _offsets_by_loop(rise, swing, bound=LEVEL_RISE_MAX_M):
    """swing_offsets' rule, one stride at a time (the reference)."""
    from footnav.nav.floors import SWING_OFFSET_STRIDES, SWING_SHARE

    hist, out = [], []
    for r, x in zip(rise, swing):
        m = float(np.median(hist[-SWING_OFFSET_STRIDES:])) if hist else 0.0
        out.append(-m if abs(m) >= SWING_SHARE * bound else 0.0)
        if abs(r) < bound and np.isfinite(x):
            hist.append(x)
    return np.array(out)


@pytest.mark.parametrize("chunk", [1, 4, 50])
def test_swing_offsets_are_the_loop_s_in_any_chunks(chunk):
    rng = np.random.default_rng(5)
    rise = rng.normal(0.0, 0.08, 50)
    swing = rng.normal(-0.05, 0.05, 50)
    swing[rng.random(50) < 0.1] = np.nan
    ref = _offsets_by_loop(rise, swing)
    assert np.count_nonzero(ref) > 10 and np.count_nonzero(ref == 0.0) > 2
    hist, got = None, []
    for i in range(0, 50, chunk):
        part, hist = swing_offsets(rise[i : i + chunk], swing[i : i + chunk], history=hist)
        got.append(part)
    np.testing.assert_allclose(np.concatenate(got), ref, atol=1e-15)
