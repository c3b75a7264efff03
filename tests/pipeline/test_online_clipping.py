"""``footnav follow`` and the online stream report saturation when it happens, after the first
seconds' window and without keeping the walk (issue 34)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

import footnav
from footnav.core.types.imu_checks import ACC_FULL_SCALES_G, CLIP_MIN_ACC_MPS2, GRAVITY_MPS2
from footnav.core.warning_log import recording
from footnav.pipeline.online_checks import _ExtremeTally


def test_a_plateau_split_across_chunks_is_one_plateau():
    tally = _ExtremeTally(CLIP_MIN_ACC_MPS2, ACC_FULL_SCALES_G, GRAVITY_MPS2)
    x = np.zeros((10, 3))
    x[8:, 1] = 160.0
    tally.add(x, 0)
    assert tally.clipped() is None  # two samples at the largest value: not yet a plateau
    y = np.zeros((5, 3))
    y[0, 1] = 160.0
    tally.add(y, 10)
    assert tally.clipped() == (3, 8, 16.0)
    z = np.zeros((2, 3))
    z[1, 1] = 170.0  # a larger value: a new extreme, held once
    tally.add(z, 15)
    assert tally.clipped() is None


def test_stream_without_keep_warns_about_late_clipping_by_index():
    rec = footnav.simulate("straight", seed=2, distance_m=40.0, rate_hz=100.0)
    acc = rec.left.acc.copy()
    acc[2000:2005, 2] = 160.0  # 20 s in: after the first seconds' window
    left = replace(rec.left, acc=acc)
    stream = footnav.make_pipeline("threshold", estimator_params={"smoother": "step"}).online(feet=1, keep=False)
    with recording() as caught:
        for a in range(0, left.n_samples, 50):
            stream.push(left=(left.t[a : a + 50], left.acc[a : a + 50], left.gyr[a : a + 50]))
            if a == 2050:
                assert any("first at index 2000" in w.message and "clipping" in w.message for w in caught)
        stream.close()
    assert sum("clipping" in w.message for w in caught) == 1


def _tally_by_numpy(value, count, first, x, offset):
    """_ExtremeTally.add's rule in numpy (the reference of the compiled tally)."""
    both = np.concatenate([x, -x], axis=1)
    peak = both.max(axis=0)
    for k in range(6):
        if np.isnan(value[k]) or peak[k] > value[k]:
            same = both[:, k] == peak[k]
            value[k], count[k], first[k] = peak[k], same.sum(), offset + int(np.argmax(same))
        elif peak[k] == value[k]:
            count[k] += int(np.count_nonzero(both[:, k] == peak[k]))


def test_the_compiled_tally_is_the_numpy_rule():
    # quantised values (ties within and across chunks, a plateau at either extreme), chunks of
    # one sample to many
    rng = np.random.default_rng(8)
    for trial in range(40):
        tally = _ExtremeTally(CLIP_MIN_ACC_MPS2, ACC_FULL_SCALES_G, GRAVITY_MPS2)
        value, count, first = np.full(6, np.nan), np.zeros(6, np.int64), np.zeros(6, np.int64)
        offset = 0
        for _ in range(30):
            x = rng.integers(-4, 5, (int(rng.integers(1, 40)), 3)).astype(float) * (1.0 + trial)
            tally.add(x, offset)
            _tally_by_numpy(value, count, first, x, offset)
            offset += len(x)
            np.testing.assert_array_equal(tally.value, value)
            np.testing.assert_array_equal(tally.count, count)
            np.testing.assert_array_equal(tally.first, first)
