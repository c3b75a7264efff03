"""Windowed statistics of IMU signals: window lengths, O(N) window sums and RMS values.

Shared by the stance detectors (Skog, Händel, Nilsson and Rantakokko, "Zero-velocity detection --
an algorithm evaluation", IEEE Trans. Biomed. Eng. 57(11), 2010, Sec. III: ARE, MAG and MV as
root-mean-squares in physical units) and by the gait-cycle analysis of
:mod:`footnav.nav.gait_cycles`. A window of W samples is indexed by its first sample; the
statistic of the window *centred* on each sample is :func:`centred` (for the ARE and MAG
statistics, :func:`centred_gyr_rms` and :func:`centred_acc_magnitude_rms` in one pass). The
cumulative sums of ``||w||^2`` and ``(||f|| - g)^2`` serve every window length; within a pipeline
run they are computed once per foot (:mod:`footnav.core.types._derived`).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from footnav._numba import njit
from footnav.core.types import GRAVITY_MPS2
from footnav.core.types._arrays import _readonly  # the kernels' inputs read-only always: one compiled signature each
from footnav.core.types._derived import cumulative, row_norms, shared

__all__ = [
    "acc_dev_sq",
    "acc_dev_sq_cumulative",
    "acc_magnitude_rms",
    "acc_moving_std",
    "centred",
    "centred_acc_magnitude_rms",
    "centred_gyr_rms",
    "centred_rms",
    "cumulative_sum",
    "gyr_rms",
    "gyr_sq",
    "gyr_sq_cumulative",
    "pairwise_sum",
    "true_runs",
    "window_samples",
    "window_sums",
]

#: Added to half the window length in samples before rounding down (see :func:`window_samples`).
_ROUNDING_SLACK = 1e-6


def window_samples(window_s: float, rate_hz: float, n_samples: int) -> int:
    """Window length W in samples: ``window_s * rate_hz`` rounded to an odd number, 1 <= W <= N.

    Odd, so that a window can be centred on a sample (W//2 samples either side): an even window
    would shift every stance edge by half a sample, differently at each rate. ``2 floor(x/2) + 1``
    is the odd number nearest ``x`` (ties upward). A recording shorter than the window is one
    window (W = N).
    """
    # the slack keeps the upward tie stable: a rate from a median interval is inexact
    # (1 / 0.01 s = 99.99999999999999 Hz), and 0.04 s x that must still give 5 samples, not 3
    win = 2 * int(np.floor(window_s * rate_hz / 2.0 + _ROUNDING_SLACK)) + 1
    return int(min(max(win, 1), n_samples))


def window_sums(x: NDArray[np.float64], win: int) -> NDArray[np.float64]:
    """Sum of ``x`` (N, ...) over every full window of ``win`` samples, by start index: (N-W+1, ...).

    Window k covers samples ``k .. k+W-1``. O(N) by one cumulative sum (no per-window loop); the
    difference of two cumulative sums loses ~1e-16 of the running total, far below any threshold.
    """
    c = cumulative(x)
    return c[win:] - c[:-win]


def centred(stat: NDArray[np.float64], win: int, n_samples: int) -> NDArray[np.float64]:
    """Per-sample values of a per-window statistic (N-W+1,): the window centred on each sample,
    the first / last full window at the ends of the recording. Shape (N,)."""
    k = np.clip(np.arange(n_samples) - win // 2, 0, n_samples - win)
    return stat[k]


def _rms(sum_of_squares: NDArray[np.float64], win: int) -> NDArray[np.float64]:
    # a difference of cumulative sums can dip a few ulp below 0 where the true sum is 0
    return np.sqrt(np.maximum(sum_of_squares, 0.0) / win)


def gyr_sq(gyr: NDArray[np.float64]) -> NDArray[np.float64]:
    """``||w_l||^2`` of each sample, (rad/s)^2, (N,)."""
    return np.einsum("ij,ij->i", gyr, gyr)


def acc_dev_sq(acc: NDArray[np.float64]) -> NDArray[np.float64]:
    """``(||f_l|| - g)^2`` of each sample, (m/s^2)^2, (N,)."""
    return (row_norms(acc) - GRAVITY_MPS2) ** 2


def gyr_sq_cumulative(gyr: NDArray[np.float64]) -> NDArray[np.float64]:
    """Cumulative sum of ``||w_l||^2`` (N + 1,): every window length's sums are its differences,
    so the detector's window and the swing peaks' share one (within a pipeline run, too)."""
    return shared("gyr_sq_cumulative", (gyr,), (), lambda: cumulative(gyr_sq(gyr)))


def acc_dev_sq_cumulative(acc: NDArray[np.float64]) -> NDArray[np.float64]:
    """Cumulative sum of ``(||f_l|| - g)^2`` (N + 1,), shared like :func:`gyr_sq_cumulative`."""
    return shared("acc_dev_sq_cumulative", (acc,), (), lambda: cumulative(acc_dev_sq(acc)))


def gyr_rms(gyr: NDArray[np.float64], win: int) -> NDArray[np.float64]:
    """ARE statistic: ``sqrt((1/W) sum ||w_l||^2)`` of every window, rad/s, (N-W+1,)."""
    c = gyr_sq_cumulative(gyr)
    return _rms(c[win:] - c[:-win], win)


def acc_magnitude_rms(acc: NDArray[np.float64], win: int) -> NDArray[np.float64]:
    """MAG statistic: ``sqrt((1/W) sum (||f_l|| - g)^2)`` of every window, m/s^2, (N-W+1,)."""
    c = acc_dev_sq_cumulative(acc)
    return _rms(c[win:] - c[:-win], win)


@njit(cache=True)
def _centred_rms(c: NDArray[np.float64], win: int) -> NDArray[np.float64]:
    # centred(_rms(c[win:] - c[:-win], win), win, n) in one pass: the same operations per sample
    # (so the same bits), without the three temporaries and the index array
    n = len(c) - 1
    half, last = win // 2, n - win
    rms = np.empty(last + 1)
    for k in range(last + 1):  # a branch-free loop the compiler vectorises
        rms[k] = np.sqrt(max(c[k + win] - c[k], 0.0) / win)
    # element by element: a slice assignment of an array compiles numba's shape-mismatch error
    # and its message formatting, seconds of the first call's compilation
    out = np.empty(n)
    for k in range(n):
        out[k] = rms[min(max(k - half, 0), last)]  # the first / last full window at the ends
    return out


#: ``centred_rms(c, win)``: the RMS of the ``win``-sample window centred on each sample (the
#: first / last full window at the ends) from the cumulative sum ``c`` (N + 1,) of the squares,
#: (N,); compiled, so compiled code calls it too.
centred_rms = _centred_rms


@njit(cache=True)
def cumulative_sum(x: NDArray[np.float64]) -> NDArray[np.float64]:
    """:func:`footnav.core.types._derived.cumulative` of a (N,) array, compiled (for code that is):
    the same running sum, so the same bits."""
    c = np.empty(len(x) + 1)
    c[0] = 0.0
    s = 0.0
    for i in range(len(x)):
        s = x[i] if i == 0 else s + x[i]
        c[i + 1] = s
    return c


def centred_gyr_rms(gyr: NDArray[np.float64], win: int) -> NDArray[np.float64]:
    """``centred(gyr_rms(gyr, win), win, N)``: the ARE statistic of the window centred on each
    sample, rad/s, (N,)."""
    return _centred_rms(_readonly(gyr_sq_cumulative(gyr)), win)


def centred_acc_magnitude_rms(acc: NDArray[np.float64], win: int) -> NDArray[np.float64]:
    """``centred(acc_magnitude_rms(acc, win), win, N)``: the MAG statistic of the window centred
    on each sample, m/s^2, (N,)."""
    return _centred_rms(_readonly(acc_dev_sq_cumulative(acc)), win)


def acc_moving_std(acc: NDArray[np.float64], win: int) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """MV statistic ``sqrt((1/W) sum ||f_l - f_mean||^2)`` (m/s^2) and the window means f_mean
    (m/s^2, (N-W+1, 3)) of every window.

    The variance is ``mean ||f||^2 - ||f_mean||^2``; both terms are taken about the recording's
    mean specific force, which leaves the variance unchanged and keeps the two terms small, so the
    subtraction does not cancel ~g^2 = 96 against itself.
    """
    offset = acc.mean(axis=0)
    centred = acc - offset
    mean_c = window_sums(centred, win) / win
    mean_sq_c = window_sums(np.einsum("ij,ij->i", centred, centred), win) / win
    variance = np.maximum(mean_sq_c - np.einsum("ij,ij->i", mean_c, mean_c), 0.0)
    return np.sqrt(variance), mean_c + offset


@njit(cache=True)
def _block_sum(x, a, n):
    # numpy's pairwise summation of up to 128 values (numpy/_core/src/umath/loops_utils.h.src):
    # one by one under 8, else 8 running sums of every 8th value, added in pairs, then the rest
    if n < 8:
        s = -0.0
        for i in range(a, a + n):
            s += x[i]
        return s
    r = x[a : a + 8].copy()
    i = 8
    while i < n - n % 8:
        for j in range(8):
            r[j] += x[a + i + j]
        i += 8
    s = ((r[0] + r[1]) + (r[2] + r[3])) + ((r[4] + r[5]) + (r[6] + r[7]))
    while i < n:
        s += x[a + i]
        i += 1
    return s


@njit(cache=True)
def pairwise_sum(x, a, n):
    """``np.add.reduce(x[a : a + n])`` of a (N,) array (a strided view too) to the bit: numpy's
    pairwise summation (the adaptive detector's pivots, the floors' footprints), whose halves
    (above 128 values, split at a multiple of 8) are walked here with a stack, not by recursion
    (numba's cache does not keep a recursive function)."""
    if n <= 128:  # an int64 start, as below: a caller's literal would compile _block_sum twice
        return _block_sum(x, np.int64(a), n)
    sa, sn, st, sv = np.empty(64, np.int64), np.empty(64, np.int64), np.zeros(64, np.int64), np.empty(64)
    sa[0], sn[0], top = a, n, 1
    while True:
        f = top - 1
        if sn[f] > 128:  # descend into the first half
            half = sn[f] // 2
            half -= half % 8
            st[f] = 1
            sa[top], sn[top], st[top] = sa[f], half, 0
            top += 1
            continue
        val = _block_sum(x, sa[f], sn[f])
        top -= 1
        while top > 0:  # hand the sum up: a first half's waits for its second half
            p = top - 1
            if st[p] == 1:
                half = sn[p] // 2
                half -= half % 8
                sv[p], st[p] = val, 2
                sa[top], sn[top], st[top] = sa[p] + half, sn[p] - half, 0
                top += 1
                break
            val = sv[p] + val
            top -= 1
        if top == 0:
            return val


@njit(cache=True)
def true_runs(mask, a, b):
    """(start, stop) of the runs of True in ``mask[a:b]``, global indices, (R, 2)."""
    out = np.empty(((b - a + 1) // 2 + 1, 2), dtype=np.int64)
    r = 0
    i = a
    while i < b:
        if mask[i]:
            j = i
            while j < b and mask[j]:
                j += 1
            out[r, 0] = i
            out[r, 1] = j
            r += 1
            i = j
        else:
            i += 1
    return out[:r]
