"""The settled edges of the zero-velocity update (footnav.nav.stance_edges), against hand-computed cases."""

from __future__ import annotations

import numpy as np
import pytest

from footnav.core.types import GRAVITY_MPS2
from footnav.nav.stance_edges import settled_mask

RATE_HZ = 200.0


def _still(n: int, scale: float = 1.0) -> tuple[np.ndarray, np.ndarray]:
    t = np.arange(n) / RATE_HZ
    acc = np.zeros((n, 3))
    acc[:, 2] = scale * GRAVITY_MPS2
    return t, acc


def test_a_landing_pulse_is_cut_where_its_velocity_falls_below_the_bound():
    # stance samples 100..199 (m = 150); the foot decelerates at 0.5 m/s^2 over samples 100..119:
    # relative to mid-stance, v(k) = -(119 - k) 0.5 dt for k < 119, so |v| >= 0.009 m/s for
    # 119 - k >= 3.6, i.e. up to k = 115: the update starts at 116
    t, acc = _still(300)
    acc[100:120, 2] += 0.5
    mask = settled_mask(t, acc, np.array([[100, 200]]), 0.009, 0.5)
    assert np.flatnonzero(mask)[0] == 116
    assert np.flatnonzero(mask)[-1] == 199
    assert not mask[:100].any() and not mask[200:].any()


def test_a_heel_rise_cuts_the_end():
    # the heel rises from sample 180 on: v(k) = (k - 179) 0.4 dt for k >= 180, >= 0.01 m/s at k >= 184
    t, acc = _still(300)
    acc[180:200, 2] += 0.4
    mask = settled_mask(t, acc, np.array([[100, 200]]), 0.01, 0.5)
    assert np.flatnonzero(mask)[0] == 100
    assert np.flatnonzero(mask)[-1] == 184 - 1


def test_each_edge_at_most_its_fraction():
    # moving for 40 samples at either end (fast up to 138 and from 160): the caps, 25 samples, cut
    t, acc = _still(300)
    acc[100:140, 2] += 1.0
    acc[160:200, 2] -= 1.0
    mask = settled_mask(t, acc, np.array([[100, 200]]), 0.001, 0.25)
    assert np.flatnonzero(mask)[0] == 125
    assert np.flatnonzero(mask)[-1] == 174


def test_the_sensors_own_gravity_reading_is_no_motion():
    # an accelerometer reading 3 % high at rest: the stance's median |f| is its gravity
    t, acc = _still(300, scale=1.03)
    mask = settled_mask(t, acc, np.array([[20, 80], [100, 200]]), 0.01, 0.5)
    assert mask[20:80].all() and mask[100:200].all()
    assert mask.sum() == 160


def test_chunks_of_whole_stances_give_the_whole_mask():
    rng = np.random.default_rng(0)
    t, acc = _still(400)
    acc += rng.normal(0.0, 0.3, acc.shape)
    iv = np.array([[10, 90], [130, 210], [260, 350]])
    whole = settled_mask(t, acc, iv, 0.01, 0.25)
    assert 0 < whole.sum() < 250  # the noise moves some edges
    a = settled_mask(t[:120], acc[:120], iv[:1], 0.01, 0.25)
    b = settled_mask(t[120:], acc[120:], iv[1:] - 120, 0.01, 0.25)
    np.testing.assert_array_equal(np.concatenate([a, b]), whole)


def test_empty_and_degenerate_intervals():
    t, acc = _still(10)
    assert not settled_mask(t, acc, np.zeros((0, 2), np.int64), 0.01, 0.25).any()
    assert not settled_mask(t, acc, np.array([[3, 3]]), 0.01, 0.25).any()
    assert settled_mask(t, acc, np.array([[3, 4]]), 0.01, 0.25)[3]


@pytest.mark.parametrize("edges", ["detected", "settled"])
def test_the_estimators_rows_keep_the_first_stance_whole(edges):
    from footnav.estimators import EkfEstimator

    t, acc = _still(300)
    acc[100:120, 2] += 0.5
    acc[0:20, 2] += 0.5
    stance = np.zeros(300, bool)
    stance[0:60] = True
    stance[100:200] = True
    est = EkfEstimator(zupt_edges=edges, zupt_std_mps=0.009)
    rows = est.zupt_rows(t, acc, stance, first_whole=True)
    if edges == "detected":
        assert rows is None and not est.trims_stances
        return
    assert est.trims_stances
    assert rows[0:60].all()  # the first stance aligns the filter: whole
    assert np.flatnonzero(rows[60:])[0] + 60 == 116
    later = est.zupt_rows(t, acc, stance, first_whole=False)  # as a stream's later chunk: trimmed
    assert not later[:15].any() and later[15:60].all()  # at 16 by its speed, 15 by the cap (a quarter)
