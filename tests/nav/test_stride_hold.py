"""The compiled stride rule (footnav.nav.stride_hold) against the vectorised numpy rule it
replaced (kept here as the reference): the same bits on random walks pushed in any chunks, with
stairs, swing rises known and unknown, a clipping strapdown's offset and a walk starting in stance."""

from __future__ import annotations

import numpy as np
import pytest

from footnav.nav.floors import (
    SWING_SHARE,
    FloorHolder,
    _ranges,
    stair_strides,
    stance_heights,
    stance_swing_rises,
    swing_offsets,
)


class _NumpyHolder(FloorHolder):
    """FloorHolder with the stances closed by the vectorised rule (the reference)."""

    def _close_stances(self, t, p, v, sw, runs):
        a, b = runs[:, 0], runs[:, 1]
        n = b - a
        h = stance_heights(p[:, 2], runs)
        idx = _ranges(a, n)
        first = np.concatenate(([0], np.cumsum(n)[:-1]))
        xy = np.add.reduceat(p[idx, :2], first, axis=0) / n[:, None]
        end_t = t[b - 1]
        if self._prev_h is None:
            prev_h = np.concatenate(([h[0]], h[:-1]))
            prev_xy = np.concatenate((xy[:1], xy[:-1]))
            prev_end = np.concatenate(([t[0]], end_t[:-1]))
            counted = np.arange(len(runs)) > 0
        else:
            prev_h = np.concatenate(([self._prev_h], h[:-1]))
            prev_xy = np.concatenate((self._prev_xy[None], xy[:-1]))
            prev_end = np.concatenate(([self._prev_end_t], end_t[:-1]))
            counted = np.ones(len(runs), bool)
        rise = h - prev_h
        swing = np.where(counted, stance_swing_rises(sw, runs), np.nan)
        offset, self._offsets = swing_offsets(rise, swing, self.level_rise_max_m, self._offsets)
        stair = stair_strides(rise, swing + offset, self.level_rise_max_m)
        held_by_swing = (np.abs(rise) >= self.level_rise_max_m) & ~stair
        level = counted & ~stair
        c = np.where(level, -rise, 0.0)
        held = np.cumsum(np.concatenate(([self._before], c)))[1:]
        before = np.concatenate(([self._before], held[:-1]))
        lo = np.concatenate(([0], b[:-1]))
        m = a - lo
        sw_idx = _ranges(lo, m)
        k = np.repeat(np.arange(len(runs)), m)
        span = t[a] - prev_end
        span = np.where(span > 0, span, 1.0)
        p[sw_idx, 2] += before[k] + c[k] * (t[sw_idx] - prev_end[k]) / span[k]
        v[sw_idx, 2] += (c / span)[k]
        p[idx, 2] += np.repeat(held, n)
        if self.keep_strides:
            self.rises.extend(rise[counted].tolist())
            self.stairs.extend((~level[counted]).tolist())
        self.swing_held += int(np.sum(held_by_swing & counted))
        steps_m = np.linalg.norm(xy - prev_xy, axis=1)[counted]
        self.walked_m = float(np.cumsum(np.concatenate(([self.walked_m], steps_m)))[-1])
        self._held_at.update(zip(end_t.tolist(), held.tolist()))
        self._before = float(held[-1])
        self._prev_h, self._prev_end_t, self._prev_xy = float(h[-1]), float(end_t[-1]), xy[-1].copy()


def _random_walk(seed: int, n_strides: int = 60):
    """A foot with stances and swings of random lengths (one sample to over 128: the pairwise
    sum's blocks), stairs and level strides with drift, swing rises mostly known, some clipping."""
    rng = np.random.default_rng(seed)
    t, p, s, sw = [], [], [], []
    k, h, x = 0, rng.normal(0, 0.05), 0.0
    in_stance_first = bool(rng.random() < 0.5)
    for i in range(n_strides):
        n_st = int(rng.choice([1, 2, 7, 8, 9, 30, 57, 129, 300]))
        n_sw = int(rng.integers(1, 90))
        for j in range(n_st):
            t.append(k / 100.0)
            p.append([x + rng.normal(0, 0.01), rng.normal(0, 0.01), h + rng.normal(0, 0.004)])
            s.append(True)
            sw.append(np.nan)
            k += 1
        if rng.random() < 0.85:  # the swing's own rise, at the stance's first update sample
            sw[-n_st] = rng.normal(0, 0.06) - (0.12 if seed % 3 == 0 else 0.0)
        if i == 0 and not in_stance_first:
            s[:n_st] = [False] * n_st
        rise = rng.choice([0.0, 0.02, -0.03, 0.17, -0.18, 0.08])
        for j in range(n_sw):
            t.append(k / 100.0)
            p.append([x + j * 0.02, 0.01 * j, h + rise * j / n_sw])
            s.append(False)
            sw.append(np.nan)
            k += 1
        h, x = h + rise + rng.normal(0, 0.02), x + n_sw * 0.02
    n = len(t)
    v = rng.normal(0, 0.1, (n, 3))
    q = np.tile([1.0, 0.0, 0.0, 0.0], (n, 1))
    return np.array(t), np.array(p), v, q, np.array(s), np.array(sw)


def _hold(holder, walk, chunks):
    t, p, v, q, s, sw = walk
    out, edges = [], [0, *chunks, len(t)]
    for a, b in zip(edges[:-1], edges[1:]):
        out.append(holder.push(t[a:b], p[a:b], v[a:b], q[a:b], s[a:b], swing_rise=sw[a:b], closed=bool(b < len(t) and not s[b])))
    out.append(holder.flush())
    return [np.concatenate(x) for x in zip(*out)]


@pytest.mark.parametrize("seed", range(12))
def test_the_compiled_rule_is_the_numpy_rule_to_the_bit(seed):
    walk = _random_walk(seed)
    rng = np.random.default_rng(100 + seed)
    n = len(walk[0])
    for chunks in ([], sorted(rng.choice(np.arange(1, n), size=40, replace=False).tolist()), list(range(97, n, 97))):
        ref, new = _NumpyHolder(), FloorHolder()
        want, got = _hold(ref, walk, chunks), _hold(new, walk, chunks)
        for a, b in zip(want, got):
            np.testing.assert_array_equal(a, b)
        assert ref.rises == new.rises and ref.stairs == new.stairs
        assert (ref.swing_held, ref.walked_m, ref._before) == (new.swing_held, new.walked_m, new._before)
        assert list(ref._held_at.items()) == list(new._held_at.items())
        assert list(ref._offsets) == list(new._offsets)
        assert ref.floors().to_meta() == new.floors().to_meta()
        assert sum(new.stairs) >= 2 and new.swing_held + sum(not x for x in new.stairs) > 3  # both kinds met


def test_the_strapdown_share_is_the_floors_own():
    # the kernel takes the share as a parameter: the holder passes the module's constant
    assert SWING_SHARE == 0.5


def _swing_rises_by_numpy(z, zupt, before=(np.nan, False, np.nan)):
    """swing_rises' vectorised rule (the reference of the compiled one)."""
    out = np.full(len(z), np.nan)
    if len(z) == 0:
        return out, before
    z_last, prev_zupt, prev_z = before
    starts = np.flatnonzero(zupt & ~np.concatenate(([prev_zupt], zupt[:-1])))
    rows = np.flatnonzero(zupt)
    j = np.searchsorted(rows, starts)
    last = np.where(j > 0, z[rows[np.maximum(j - 1, 0)]], z_last)
    just_before = np.where(starts > 0, z[np.maximum(starts - 1, 0)], prev_z)
    out[starts] = just_before - last
    return out, (float(z[rows[-1]]) if len(rows) else float(z_last), bool(zupt[-1]), float(z[-1]))


@pytest.mark.parametrize("seed", range(6))
def test_the_compiled_swing_rises_are_the_numpy_rule_in_any_chunks(seed):
    from footnav.nav.floors import swing_rises

    rng = np.random.default_rng(seed)
    n = 600
    z = np.cumsum(rng.normal(0, 0.01, n))
    zupt = rng.random(n) < (0.3 + 0.4 * (seed % 2))
    for chunk in (1, 3, 50, n):
        ref, new = (np.nan, False, np.nan), (np.nan, False, np.nan)
        for a in range(0, n, chunk):
            want, ref = _swing_rises_by_numpy(z[a : a + chunk], zupt[a : a + chunk], ref)
            got, new = swing_rises(z[a : a + chunk], zupt[a : a + chunk], new)
            np.testing.assert_array_equal(got, want)
            np.testing.assert_array_equal(np.array(new, dtype=float), np.array(ref, dtype=float))


def test_the_compiled_runs_are_stance_intervals():
    from footnav.nav.stride_hold import runs_of
    from footnav.types import stance_intervals

    rng = np.random.default_rng(3)
    for n in [0, 1, 2, 3, 10, 101]:
        for p in (0.0, 0.3, 0.8, 1.0):
            mask = rng.random(n) < p
            np.testing.assert_array_equal(runs_of(mask), stance_intervals(mask))
            assert runs_of(mask).shape == stance_intervals(mask).shape
