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
