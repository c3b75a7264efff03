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
vertical edges, the ones that move height. Each stance's figures are its own samples' (summed
outward from m in a compiled loop), so chunks of whole stances give the same bits as the whole
recording.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from footnav._numba import njit  # numba.njit that survives a read-only install
from footnav.core.types._arrays import _readonly
from footnav.nav.order_stats import median

__all__ = ["settled_mask"]


@njit(cache=True, error_model="numpy")
def _settled(t, acc, a, b, v_max, max_fraction, mask):  # pragma: no cover - compiled
    for i in range(len(a)):
        lo, hi = a[i], b[i]
        n = hi - lo
        if n <= 0:
            continue
        f = np.empty(n)
        for k in range(n):
            x, y, z = acc[lo + k, 0], acc[lo + k, 1], acc[lo + k, 2]
            f[k] = np.sqrt(x * x + y * y + z * z)
        lo_mid, hi_mid = n // 4, (3 * n) // 4 + 1
        g = median(f[lo_mid:hi_mid].copy(), hi_mid - lo_mid)  # np.median's value
        m = n // 2
        cap = int(np.floor(max_fraction * n))
        start = 0  # the sample after the last one before m moving faster than v_max
        s = 0.0
        for j in range(m, 0, -1):  # v(j - 1) = -sum_{i=j}^{m} (f_i - g) dt_i
            s += (f[j] - g) * (t[lo + j] - t[lo + j - 1])
            if abs(s) >= v_max:
                start = j
                break
        stop = n  # the first one after m moving faster
        s = 0.0
        for j in range(m + 1, n):  # v(j) = sum_{i=m+1}^{j} (f_i - g) dt_i
            s += (f[j] - g) * (t[lo + j] - t[lo + j - 1])
            if abs(s) >= v_max:
                stop = j
                break
        start = min(start, cap)
        stop = max(stop, n - cap)
        for k in range(start, stop):
            mask[lo + k] = True


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
    mask = np.zeros(len(t), dtype=bool)
    iv = np.asarray(intervals, dtype=np.int64).reshape(-1, 2)
    if len(t) == 0 or len(iv) == 0:
        return mask
    _settled(  # read-only inputs, a stream's too: one compiled signature
        _readonly(np.asarray(t, dtype=np.float64)),
        _readonly(np.asarray(acc, dtype=np.float64)),
        np.ascontiguousarray(iv[:, 0]),
        np.ascontiguousarray(iv[:, 1]),
        float(v_max_mps),
        float(max_fraction),
        mask,
    )
    return mask
