"""Where in a detected stance the foot is still: the settled edges of the zero-velocity update.

A stance detector declares stance while the foot still comes down (the sole compresses, the
foot rolls flat) and keeps it while the heel already rises; a zero-velocity update there takes
that real motion for an error grown over the swing, and the smoother lifts the footprint by
about v T_swing / 2 (docs/height.md, sections 2 and 8). The accelerometer sees the motion: a
foot moving at v relative to its rest has integrated (|f| - g) to v. :func:`settled_mask` keeps,
of each stance, the samples whose vertical velocity relative to mid-stance is within ``v_max``
(the update's own std: it asserts no more than that),

    v(k) = -sum_{j=k+1}^{m} (|f_j| - g_s) dt_j   (k < m),   v(k) = sum_{j=m+1}^{k} (|f_j| - g_s) dt_j   (k > m),

with m the stance's middle sample and g_s its median |f| over the stance's middle half (the
sensor's own reading of gravity there, whatever its scale). The update starts after the last
sample before m that moves faster and ends before the first one after m that does, each edge
at most ``max_fraction`` of the stance. |f| - g is the vertical acceleration to first order
(the foot is near level in stance; a horizontal a_h adds a_h^2 / 2g), so these are the
vertical edges, the ones that move height.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

__all__ = ["settled_mask"]


def settled_mask(
    t: NDArray[np.float64],
    acc: NDArray[np.float64],
    intervals: NDArray[np.int64],
    v_max_mps: float,
    max_fraction: float,
) -> NDArray[np.bool_]:
    """The stance samples where the foot has settled, as a mask over ``t``.

    Parameters
    ----------
    t, acc
        Sample times (s) and specific force (N, 3), m/s^2, body frame.
    intervals
        The stances to trim, (K, 2) start and stop (exclusive) indices; samples outside them are
        False.
    v_max_mps
        The vertical speed relative to mid-stance a settled sample stays within, m/s.
    max_fraction
        Neither edge takes more than this fraction of its stance (floor), in [0, 0.5].

    Returns
    -------
    numpy.ndarray
        (N,) bool: True where the zero-velocity update applies.
    """
    n = len(t)
    mask = np.zeros(n, dtype=bool)
    iv = np.asarray(intervals, dtype=np.int64).reshape(-1, 2)
    iv = iv[iv[:, 1] > iv[:, 0]]
    if n == 0 or len(iv) == 0:
        return mask
    a, b = iv[:, 0], iv[:, 1]
    length = b - a
    dt = np.diff(t, prepend=t[0])
    fmag = np.sqrt(np.einsum("ij,ij->i", acc, acc))
    # cumulative sums with a leading zero: S[k] = sum_{j<k}
    cf = np.concatenate(([0.0], np.cumsum(fmag * dt)))
    ct = np.concatenate(([0.0], np.cumsum(dt)))
    q1, q3 = a + length // 4, a + (3 * length) // 4 + 1
    # the stance's median |f| over its middle half (a mean takes in the motion of the edges)
    g = _segment_medians(fmag, q1, q3)
    m = a + length // 2
    # per stance sample: its stance, v relative to m (cf, ct at k + 1 and m + 1: sums through k, m)
    first = np.cumsum(length) - length  # each stance's first entry in the stacked samples
    s = np.repeat(np.arange(len(iv)), length)
    k = np.repeat(a - first, length) + np.arange(int(length.sum()))
    v = (cf[k + 1] - cf[m[s] + 1]) - g[s] * (ct[k + 1] - ct[m[s] + 1])
    fast = np.abs(v) >= v_max_mps
    cap = np.floor(max_fraction * length).astype(np.int64)
    # the last fast sample before m and the first after it, per stance (-1 / n: none)
    before = np.where(fast & (k < m[s]), k, -1)
    after = np.where(fast & (k > m[s]), k, n)
    start = np.maximum.reduceat(before, first) + 1
    stop = np.minimum.reduceat(after, first)
    start = np.clip(np.maximum(start, a), a, a + cap)
    stop = np.clip(np.minimum(stop, b), b - cap, b)
    keep = (k >= start[s]) & (k < stop[s])
    mask[k[keep]] = True
    return mask


def _segment_medians(x: NDArray[np.float64], lo: NDArray[np.int64], hi: NDArray[np.int64]) -> NDArray[np.float64]:
    """np.median of each ``x[lo[i]:hi[i]]`` (non-empty, disjoint), in one sort."""
    n = hi - lo
    first = np.cumsum(n) - n
    seg = np.repeat(np.arange(len(n)), n)
    idx = np.repeat(lo - first, n) + np.arange(int(n.sum()))
    order = np.lexsort((x[idx], seg))  # by segment, then value: exact values, as np.median sorts them
    v = x[idx][order]
    return 0.5 * (v[first + (n - 1) // 2] + v[first + n // 2])
