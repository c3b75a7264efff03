"""The compiled kernels and shared derivations of a pipeline run (issue 20, item 2) give the very
bits of the numpy / scipy code they replaced, and the per-run cache never outlives its run."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.ndimage import maximum_filter1d, minimum_filter1d, uniform_filter1d
from scipy.signal import find_peaks

import footnav
from footnav.core.types import GRAVITY_MPS2, REST_ACC_REL_STD, REST_GYR_RADPS, REST_WINDOW_S
from footnav.core.types._derived import row_norms, shared, sharing
from footnav.core.types.imu_checks import _at_rest, _count_beyond, _held_peak
from footnav.nav.interpolation import interp_columns
from footnav.nav.peaks import peak_candidates
from footnav.nav.windows import centred, centred_acc_magnitude_rms, centred_gyr_rms

RNG = np.random.default_rng(20)


def _signals(count: int):
    """Random, quantised (ties, plateaus) and random-walk signals of many lengths."""
    for i in range(count):
        n = int(RNG.integers(0, 300))
        kind = i % 3
        if kind == 0:
            yield RNG.standard_normal(n)
        elif kind == 1:
            yield RNG.integers(0, 4, n).astype(float)
        else:
            yield np.round(np.abs(np.cumsum(RNG.standard_normal(n))), 1)


def test_peaks_are_scipys_find_peaks():
    for x in _signals(600):
        height = float(RNG.choice([-1.0, 0.5, 1.0]))
        rel = float(RNG.choice([0.0, 0.4, 1.0]))
        candidates = peak_candidates(x, height)
        for distance in (1, 2, 7, 30):
            idx, props = find_peaks(x, height=height, prominence=0.0, distance=distance)
            expected = idx[props["prominences"] >= rel * props["peak_heights"]]
            np.testing.assert_array_equal(candidates.select(distance, rel), expected)


def test_row_norms_and_windowed_rms_are_numpys():
    for scale in (1e-3, 1.0, 1e3):
        x = RNG.standard_normal((5000, 3)) * scale
        assert np.array_equal(row_norms(x), np.linalg.norm(x, axis=1))
        for win in (1, 5, 21, 5000):
            c = np.concatenate([[0.0], np.cumsum(np.einsum("ij,ij->i", x, x))])
            gyr = centred(np.sqrt(np.maximum(c[win:] - c[:-win], 0.0) / win), win, len(x))
            d = np.concatenate([[0.0], np.cumsum((np.linalg.norm(x, axis=1) - GRAVITY_MPS2) ** 2)])
            acc = centred(np.sqrt(np.maximum(d[win:] - d[:-win], 0.0) / win), win, len(x))
            assert np.array_equal(centred_gyr_rms(x, win), gyr)
            assert np.array_equal(centred_acc_magnitude_rms(x, win), acc)


def test_unit_check_kernels_are_the_filters_they_replaced():
    for x in _signals(600):
        hold = int(RNG.integers(1, 60))
        if len(x) >= hold:
            running = minimum_filter1d(x, hold, mode="nearest")
            assert _held_peak(x, hold) == float(running[hold // 2 : len(x) - (hold - 1 - hold // 2)].max())
        centre, bound = float(RNG.standard_normal()), float(RNG.random())
        assert _count_beyond(x, centre, bound) == int(np.count_nonzero(np.abs(x - centre) > bound))
    for _ in range(300):
        n = int(RNG.integers(1, 1500))
        rate = float(RNG.choice([20.0, 60.0, 100.0, 128.0, 333.0]))
        acc = GRAVITY_MPS2 + np.where(RNG.random(n) < 0.5, 0.01, 3.0) * RNG.standard_normal(n)
        gyr = np.abs(RNG.standard_normal(n)) * float(RNG.choice([0.1, 1.0]))
        median = float(np.median(acc))
        k = max(5, round(REST_WINDOW_S * rate))
        expected = np.zeros(n, dtype=bool)
        if n >= k:
            a = acc - median
            mean_a = uniform_filter1d(a, k, mode="nearest")
            std_a = np.sqrt(np.maximum(uniform_filter1d(a * a, k, mode="nearest") - mean_a * mean_a, 0.0))
            ok = (std_a < REST_ACC_REL_STD * median) & (uniform_filter1d(gyr, k, mode="nearest") < REST_GYR_RADPS)
            expected = (
                maximum_filter1d(ok.astype(np.uint8), k, mode="constant", cval=0, origin=-1 if k % 2 == 0 else 0) > 0
            )
        np.testing.assert_array_equal(_at_rest(acc, gyr, rate, median), expected)


@pytest.mark.parametrize("start, stop", [(0, 100), (10, 60), (99, 100)])
def test_interp_columns_on_the_same_grid_copies_the_samples(start, stop):
    t = np.cumsum(RNG.random(100) + 0.01)
    values = RNG.standard_normal((100, 4))
    values[3, 1] = -0.0
    got = interp_columns(t[start:stop], t, values[:, :3])
    expected = np.column_stack([np.interp(t[start:stop], t, values[:, k]) for k in range(3)])
    assert got.flags.c_contiguous and np.array_equal(got.view(np.int64), expected.view(np.int64))
    shifted = t[start:stop] + 1e-3  # off the grid: interpolated as before
    assert np.array_equal(
        interp_columns(shifted, t, values), np.column_stack([np.interp(shifted, t, values[:, k]) for k in range(4)])
    )


def test_shared_values_live_for_one_block_and_only_for_read_only_arrays():
    calls = []

    def compute():
        calls.append(1)
        return len(calls)

    frozen = np.arange(5.0)
    frozen.setflags(write=False)
    writable = np.arange(5.0)
    assert shared("x", (frozen,), (), compute) == 1  # no block open: computed
    with sharing():
        assert shared("x", (frozen,), (), compute) == 2
        with sharing():  # nested: the outer block's cache
            assert shared("x", (frozen,), (), compute) == 2
        assert shared("x", (frozen,), (1,), compute) == 3  # other parameters
        assert shared("x", (writable,), (), compute) == 4
        assert shared("x", (writable,), (), compute) == 5  # a writable array may change: never kept
    with sharing():
        assert shared("x", (frozen,), (), compute) == 6  # a new block computes again


def test_a_run_shares_the_swing_peaks_and_repeats_identically():
    rec = footnav.simulate("straight", seed=3, distance_m=40.0)
    pipe = footnav.make_pipeline()
    first, second = pipe.run(rec), pipe.run(rec)
    assert first.meta["stance_check"] == second.meta["stance_check"]
    assert np.array_equal(first.stance_left.mask, second.stance_left.mask)
    assert np.array_equal(first.left.position, second.left.position)
