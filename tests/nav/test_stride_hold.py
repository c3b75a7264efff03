"""The compiled stride rule (footnav.nav.stride_hold) against the vectorised numpy rule it
replaced on a stream's few stances (FloorHolder keeps it for many): the same bits on random walks
pushed in any chunks, with stairs, swing rises known and unknown, a clipping strapdown's offset and
a walk starting in stance; and the compiled swing rises and stance runs against numpy's."""

from __future__ import annotations

from itertools import pairwise

import numpy as np
import pytest

from footnav.nav.floors import SWING_SHARE, FloorHolder


def _holder(compiled: bool) -> FloorHolder:
    """A FloorHolder closing every batch of stances compiled, or every one by the vectorised rule
    (the numpy rule the kernel replaced on a live stream's few stances: the reference)."""
    holder = FloorHolder()
    holder.compiled_max_stances = 10**9 if compiled else -1
    return holder


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
        for _ in range(n_st):
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
    for a, b in pairwise(edges):
        out.append(
            holder.push(
                t[a:b], p[a:b], v[a:b], q[a:b], s[a:b], swing_rise=sw[a:b], closed=bool(b < len(t) and not s[b])
            )
        )
    out.append(holder.flush())
    return [np.concatenate(x) for x in zip(*out)]


@pytest.mark.parametrize("seed", range(12))
def test_the_compiled_rule_is_the_numpy_rule_to_the_bit(seed):
    walk = _random_walk(seed)
    rng = np.random.default_rng(100 + seed)
    n = len(walk[0])
    for chunks in ([], sorted(rng.choice(np.arange(1, n), size=40, replace=False).tolist()), list(range(97, n, 97))):
        ref, new = _holder(compiled=False), _holder(compiled=True)
        want, got = _hold(ref, walk, chunks), _hold(new, walk, chunks)
        for a, b in zip(want, got):
            np.testing.assert_array_equal(a, b)
        assert ref.rises == new.rises and ref.stairs == new.stairs
        assert (ref.swing_held, ref.walked_m, ref._before) == (new.swing_held, new.walked_m, new._before)
        assert list(ref._held_at.items()) == list(new._held_at.items())
        assert list(ref._offsets) == list(new._offsets)
        assert ref.floors().to_meta() == new.floors().to_meta()
        assert sum(new.stairs) >= 2 and new.swing_held + sum(not x for x in new.stairs) > 3  # both kinds met


def test_a_whole_walk_closes_by_the_vectorised_rule_and_a_stream_s_push_compiled(monkeypatch):
    # the kernel's compilation is a live stream's only: hold_floors never calls it
    from footnav.core.types import FootTrajectory, stance_intervals
    from footnav.nav import floors, stride_hold

    t, p, v, q, s, _ = _random_walk(0, n_strides=20)
    traj = FootTrajectory(
        t=t, position=p, velocity=v, quaternion=q, position_std=np.zeros_like(p), steps=stance_intervals(s)
    )
    calls = []
    compiled = stride_hold.close_stances
    monkeypatch.setattr(floors, "close_stances", lambda *a: calls.append(a) or compiled(*a))
    floors.hold_floors(traj)
    assert not calls
    holder = FloorHolder()
    holder.push(t[:300], p[:300], v[:300], q[:300], s[:300])
    assert len(calls) == 1
    assert SWING_SHARE == 0.5  # the kernel takes the share as a parameter: the module's constant


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
    from footnav.core.types import stance_intervals
    from footnav.nav.stride_hold import runs_of

    rng = np.random.default_rng(3)
    for n in [0, 1, 2, 3, 10, 101]:
        for p in (0.0, 0.3, 0.8, 1.0):
            mask = rng.random(n) < p
            np.testing.assert_array_equal(runs_of(mask), stance_intervals(mask))
            assert runs_of(mask).shape == stance_intervals(mask).shape
