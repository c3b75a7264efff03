"""The floors' per-stance work (:mod:`footnav.nav.floors`), compiled.

A live stream closes about one stance per foot and push, and the rule's three dozen numpy calls
(the strapdown offset's median among them, through numpy's masked arrays) cost some 50 times the
arithmetic on that one stance: :func:`close_stances` makes them one call. Each operation is the
one the vectorised rule made, in its order (:func:`footnav.nav.floors.stance_heights`, the
footprint's mean as ``np.add.reduceat`` sums it: the first sample, then numpy's pairwise sum of
the others, :func:`footnav.nav.floors.swing_offsets`' median as ``np.nanmedian`` takes it, the
running sums as ``np.cumsum`` adds them), so the numbers are the same to the bit;
``tests/nav/test_stride_hold.py`` holds the vectorised rule as the reference. So do
:func:`swing_rises_into` (:func:`footnav.nav.floors.swing_rises`' rule) and :func:`runs_of`
(:func:`footnav.core.types.stance_intervals`), which a stream calls on every push.
"""

from __future__ import annotations

import numpy as np

from footnav._numba import njit
from footnav.nav.order_stats import median, sort
from footnav.nav.windows import pairwise_sum, true_runs

__all__ = ["close_stances", "runs_of", "swing_rises_into"]


@njit(cache=True)
def _same_sign(a, b):
    # np.sign(a) == np.sign(b): False with a NaN
    return (a > 0 and b > 0) or (a < 0 and b < 0) or (a == 0 and b == 0)


@njit(cache=True)
def close_stances(t, p, v, sw, runs, bound, share, n_win, first, prev_h, prev_end, prev_x, prev_y, before,
                  walked, history):  # fmt: skip
    """The rule of :meth:`footnav.nav.floors.FloorHolder._close_stances` on the stances ``runs``.

    Parameters
    ----------
    t, p, v, sw
        (N,) time s, (N, 3) position and velocity (m, m/s; heights and vertical velocities are
        corrected in place, over ``t[:runs[-1, 1]]``), (N,) the swing's own rise (NaN but at a
        stance's first update sample).
    runs
        (K, 2) the stances (start, stop), none empty, in order.
    bound, share, n_win
        The level bound (m), the strapdown's share of it (``SWING_SHARE``) and the strides the
        strapdown's offset is the median of (``SWING_OFFSET_STRIDES``).
    first
        These start the walk: the first stance has no stride before it (the previous stance's
        height, end time and footprint are then unused).
    prev_h, prev_end, prev_x, prev_y, before, walked
        The last closed stance's height (m), end time (s) and footprint (m), the correction held
        there (m), the distance walked so far (m).
    history
        (<= n_win,) the latest level strides' swing rises, oldest first.

    Returns
    -------
    rise, stair, held, held_by_swing, heights, end_t, x, y, walked, history
        Per stance (K,): the stride's rise (m), whether it is a stair stride, the correction its
        samples got (m), whether it rose by the bound but its swing did not, its height (m), end
        time (s) and footprint (m); the distance walked after them (m) and the new history (the
        first stance of a walk counts in none of these but its height, end and footprint).
    """
    k_runs = runs.shape[0]
    h = np.empty(k_runs)
    xs, ys = np.empty(k_runs), np.empty(k_runs)
    end_t = np.empty(k_runs)
    swing = np.empty(k_runs)
    longest = 0
    for k in range(k_runs):
        longest = max(longest, runs[k, 1] - runs[k, 0])
    col = np.empty(longest)  # one stance's heights, then its x and y
    for k in range(k_runs):
        a, b = runs[k, 0], runs[k, 1]
        n = b - a
        for i in range(n):
            col[i] = p[a + i, 2]
        sort(col, n)
        h[k] = 0.5 * (col[(n - 1) // 2] + col[n // 2])
        for c in range(2):  # contiguous, as the detector's pairwise sums: one compiled version
            for i in range(n):
                col[i] = p[a + i, c]
            mean = (col[0] + pairwise_sum(col, 1, n - 1)) / n
            if c == 0:
                xs[k] = mean
            else:
                ys[k] = mean
        end_t[k] = t[b - 1]
        swing[k] = np.nan
        for i in range(a, b):
            if np.isfinite(sw[i]):
                swing[k] = sw[i]
                break
    if first:
        prev_h, prev_end, prev_x, prev_y = h[0], t[0], xs[0], ys[0]
    rise = np.empty(k_runs)
    stair = np.zeros(k_runs, dtype=np.bool_)
    held = np.empty(k_runs)
    by_swing = np.zeros(k_runs, dtype=np.bool_)
    values = np.empty(len(history) + k_runs)  # the level strides' swing rises, oldest first
    m = len(history)
    for i in range(m):
        values[i] = history[i]
    limit = share * bound
    window = np.empty(max(n_win, 1))
    for k in range(k_runs):
        counted = k > 0 or not first
        ph = h[k - 1] if k > 0 else prev_h
        pe = end_t[k - 1] if k > 0 else prev_end
        rise[k] = h[k] - ph
        sk = swing[k] if counted else np.nan
        offset = 0.0
        if m > 0:
            lo_w = max(m - n_win, 0)
            for i in range(lo_w, m):  # element by element: a slice assignment compiles numba's
                window[i - lo_w] = values[i]  # shape-mismatch error, seconds of a first call
            med = median(window, m - lo_w)
            offset = -med if abs(med) >= limit else 0.0
        if abs(rise[k]) < bound and np.isfinite(sk):
            values[m] = sk
            m += 1
        s2 = sk + offset
        agree = abs(s2) >= limit and _same_sign(s2, rise[k])
        stair[k] = abs(rise[k]) >= bound and (np.isnan(s2) or agree)
        by_swing[k] = counted and abs(rise[k]) >= bound and not stair[k]
        c = -rise[k] if counted and not stair[k] else 0.0
        at_before = held[k - 1] if k > 0 else before
        held[k] = at_before + c
        # the swing before the stance: from the last sample of the one before (the chunk's first)
        lo = runs[k - 1, 1] if k > 0 else 0
        a, b = runs[k, 0], runs[k, 1]
        span = t[a] - pe
        if not span > 0:  # only the walk's first stance can start at its first sample
            span = 1.0
        for i in range(lo, a):
            p[i, 2] += at_before + c * (t[i] - pe) / span
            v[i, 2] += c / span
        for i in range(a, b):
            p[i, 2] += held[k]
        if counted:
            px = xs[k - 1] if k > 0 else prev_x
            py = ys[k - 1] if k > 0 else prev_y
            dx, dy = xs[k] - px, ys[k] - py
            walked = walked + np.sqrt(dx * dx + dy * dy)
    return rise, stair, held, by_swing, h, end_t, xs, ys, walked, values[max(m - n_win, 0) : m].copy()


@njit(cache=True)
def swing_rises_into(z, zupt, out, z_last, prev_zupt, prev_z):
    """:func:`footnav.nav.floors.swing_rises`' rule, compiled, into ``out`` (N,: NaN on entry):
    at the first update sample of each run, the height just before it less the height at the
    last update sample before it (``z_last`` before these samples). Returns the height at the
    last update sample."""
    for i in range(len(z)):
        if zupt[i]:
            if not prev_zupt:
                out[i] = (z[i - 1] if i > 0 else prev_z) - z_last
            z_last = z[i]
        prev_zupt = zupt[i]
    return z_last


@njit(cache=True)
def runs_of(mask):
    """:func:`footnav.core.types.stance_intervals`, compiled: (start, stop) of each run of True, (K, 2)."""
    return true_runs(mask, np.int64(0), len(mask))  # int64, as the detector's: one compilation
