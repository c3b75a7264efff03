"""Compiled sorting and medians for the kernels, without numba's ``np.sort`` and ``np.median``.

numba compiles its own ``np.sort`` (a quicksort) and ``np.median`` (a partition select) for
every kernel that uses them, a second or more each with an empty cache; these few loops compile
in a fraction of that. Each gives the value numpy gives: :func:`median` is ``np.median`` (and
``np.nanmedian``) of finite values to the bit, the middle value, or the mean of the two middle
ones.
"""

from __future__ import annotations

import numpy as np

from footnav._numba import njit

__all__ = ["median", "sort"]


@njit(cache=True)
def sort(x, n):  # pragma: no cover - compiled
    """``x[:n]`` sorted in place, ascending: a heapsort (O(n log n), no recursion: numba's cache
    does not keep a recursive function). Equal values may change places: only values are read."""
    for start in range(n // 2 - 1, -1, -1):
        _sift(x, start, n)
    for end in range(n - 1, 0, -1):
        x[0], x[end] = x[end], x[0]
        _sift(x, np.int64(0), end)  # an int64 root, as above: a literal 0 compiles _sift twice


@njit(cache=True)
def _sift(x, root, n):  # pragma: no cover - compiled
    while True:
        child = 2 * root + 1
        if child >= n:
            return
        if child + 1 < n and x[child] < x[child + 1]:
            child += 1
        if not x[root] < x[child]:
            return
        x[root], x[child] = x[child], x[root]
        root = child


@njit(cache=True)
def median(x, n):  # pragma: no cover - compiled
    """The median of the finite ``x[:n]`` (n >= 1), which it sorts in place: the middle one
    (added to itself and halved, as numpy's masked median does), or the mean of the middle two."""
    sort(x, n)
    h = n // 2
    lo = x[h] if n % 2 == 1 else x[h - 1]
    return (lo + x[h]) / 2.0
