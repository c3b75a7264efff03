"""Band-limited dynamic time warping of two trajectories (Chistyakov et al. (2021), Sec. 3).

Chistyakov et al., Russian Technological J. 2021 (full citation in docs/references.md),
Section 3 ("trajectory similarity metric"): the DTW metric between the left- and the right-foot
trajectory, computed by dynamic programming ([12] Mueller 2007) with "an additional limit on the
maximum allowed difference between the indices of corresponding points (the index is the
sample number in the experiment)". Besides the value, the algorithm yields the sequence of
matched point pairs (Fig. 2). Table 1 reports these distances in m: :func:`dtw_align`.

What the paper builds on it lives beside this module:

* Section 4, step 1: the initial heading mismatch of the two IMUs, found "by choosing the initial
  angles that minimise the DTW metric": :func:`footnav.nav.dtw_heading.heading_mismatch`.
* Section 3 and Section 4, step 5: one averaged trajectory, from the DTW-matched pairs or on one
  time grid: :func:`footnav.nav.dtw_average.timeless_average`,
  :func:`footnav.nav.dtw_average.timed_average`.

Both use this module's input checks (``_trajectory``, ``_band``, ...) so that all three name bad
input the same way.

Frames and units: positions are in one navigation frame (x, y horizontal, z up), in m, samples
on axis 0; times in s. Nothing here aligns frames implicitly except
:func:`footnav.nav.dtw_heading.heading_mismatch`, which returns the rotation about z it found.

:func:`footnav.analysis.metrics.dtw_distance` is a thin wrapper of :func:`dtw_align` (input checks on
``dims``, same numbers).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from footnav._numba import njit  # numba.njit that survives a read-only install
from footnav.core.errors import InvalidInputError, InvalidParameterError
from footnav.core.types._arrays import _readonly  # the one copy: a read-only, C-contiguous view

__all__ = ["DtwAlignment", "dtw_align"]

_COSTS = ("euclidean", "sqeuclidean")
_NORMALIZE = ("mean", "none")


# ---------------------------------------------------------------------------------------------
# input checking
# ---------------------------------------------------------------------------------------------
def _float64(value: ArrayLike, name: str) -> NDArray[np.float64]:
    """``value`` as a float64 array; InvalidInputError naming ``name`` if it is not numeric."""
    try:
        return np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise InvalidInputError(f"cannot convert to float64 ({exc})", field=name) from None


def _trajectory(value: ArrayLike, name: str, *, min_cols: int = 1, min_rows: int = 1) -> NDArray[np.float64]:
    """``value`` as a finite, C-contiguous float64 (N, D) array with N >= min_rows, D >= min_cols."""
    arr = np.ascontiguousarray(_float64(value, name))
    if arr.ndim != 2 or arr.shape[1] < min_cols:
        raise InvalidInputError(
            f"expected positions in m of shape (N, D) with D >= {min_cols}, got {arr.shape}", field=name
        )
    if len(arr) < min_rows:
        what = "is empty" if len(arr) == 0 else f"has {len(arr)} row(s)"
        raise InvalidInputError(f"{what}; need at least {min_rows} position(s)", field=name)
    bad = ~np.isfinite(arr).all(axis=1)
    if bad.any():
        first = int(np.argmax(bad))
        raise InvalidInputError(f"non-finite value {arr[first]!r}; every value must be finite", field=name, index=first)
    return arr


def _choice(value: object, name: str, allowed: tuple[str, ...]) -> str:
    if value not in allowed:
        raise InvalidParameterError(f"{name} must be one of {', '.join(map(repr, allowed))}, got {value!r}")
    return str(value)


def _band(band: int | None, n: int, m: int) -> int:
    """The band in samples as an int; None -> unbounded (max(N, M)); too narrow -> error."""
    if band is None:
        return max(n, m)
    try:
        whole = not isinstance(band, bool) and float(band).is_integer() and band >= 0
    except (TypeError, ValueError):
        whole = False
    if not whole:
        raise InvalidParameterError(f"band must be a non-negative whole number of samples or None, got {band!r}")
    band_i = int(band)
    if band_i < abs(n - m):
        raise InvalidParameterError(
            f"band={band_i} samples cannot reach the last pair of trajectories with {n} and {m} "
            f"samples: need band >= |N - M| = {abs(n - m)} (or resample to equal rates)"
        )
    return band_i


# ---------------------------------------------------------------------------------------------
# the kernel
# ---------------------------------------------------------------------------------------------
#: Back-pointer codes (int8): which predecessor cell the minimum came from.
_STEP_DIAG, _STEP_UP, _STEP_LEFT = 0, 1, 2


@njit(cache=True, error_model="numpy")
def _dtw_kernel(a, b, band, squared, want_path):  # pragma: no cover - compiled
    """Banded DTW over cells |i - j| <= band; returns (total cost, matched pairs, back-pointers).

    Row i keeps columns lo(i) = max(0, i - band) .. hi(i) = min(M - 1, i + band) at offsets
    j - lo(i): two rows of cost and pair count (O(min(M, 2 band + 1)) memory) and, only when the
    path is wanted, N x min(M, 2 band + 1) int8 back-pointers. Nothing is allocated in the loop.
    Ties prefer the diagonal, then (i-1, j), then (i, j-1).
    """
    n, m, d = a.shape[0], b.shape[0], a.shape[1]
    w = min(m, 2 * band + 1)
    inf = np.inf
    prev = np.full(w, inf)
    cur = np.full(w, inf)
    prev_len = np.zeros(w, np.int64)
    cur_len = np.zeros(w, np.int64)
    steps = np.zeros((n, w) if want_path else (1, 1), np.int8)
    prev_lo, prev_hi = 0, -1
    for i in range(n):
        lo = max(0, i - band)
        hi = min(m - 1, i + band)
        for j in range(lo, hi + 1):
            # c = ||a_i - b_j|| (or its square)
            c = 0.0
            for q in range(d):
                diff = a[i, q] - b[j, q]
                c += diff * diff
            if not squared:
                c = np.sqrt(c)
            k = j - lo
            if i == 0 and j == 0:
                cur[k] = c  # D(0, 0) = c(a_0, b_0)
                cur_len[k] = 1
                continue
            # D(i, j) = c + min(D(i-1, j-1), D(i-1, j), D(i, j-1))
            best = inf
            blen = 0
            step = -1
            if i > 0 and prev_lo <= j - 1 <= prev_hi:
                v = prev[j - 1 - prev_lo]
                if v < best:
                    best, blen, step = v, prev_len[j - 1 - prev_lo], 0
            if i > 0 and prev_lo <= j <= prev_hi:
                v = prev[j - prev_lo]
                if v < best:
                    best, blen, step = v, prev_len[j - prev_lo], 1
            if j > lo:
                v = cur[k - 1]
                if v < best:
                    best, blen, step = v, cur_len[k - 1], 2
            cur[k] = c + best
            cur_len[k] = blen + 1
            if want_path:
                steps[i, k] = step
        prev, cur = cur, prev
        prev_len, cur_len = cur_len, prev_len
        prev_lo, prev_hi = lo, hi
    # after the swap the last row is in ``prev``; every cell of a row is written before it is read
    kend = (m - 1) - max(0, n - 1 - band)
    return prev[kend], prev_len[kend], steps


@njit(cache=True, error_model="numpy")
def _dtw_cost_kernel(a, b, band, squared, limit_mean):  # pragma: no cover - compiled
    """:func:`_dtw_kernel` without the path: (total cost, matched pairs), the very same numbers
    (same sums, same ties), or (inf, 0) once the mean distance is certain to exceed ``limit_mean``.

    Cells are kept by their diagonal ``k = j - i + band`` at ``k + 1`` of a row padded with inf,
    so the three predecessors are ``prev[k + 1]`` (diagonal), ``prev[k + 2]`` (i-1, j) and
    ``cur[k]`` (i, j-1) without a range test per cell; a cell outside the band or the matrix
    holds inf, which never wins the minimum (as the skipped predecessors of the other kernel).

    Every path passes each row, costs are non-negative and rounding is monotone, so the final
    total is at least the smallest cost of any row and the mean at least that over the most
    pairs a path has (N + M - 1): once that exceeds ``limit_mean`` (inf: never) the mean cannot
    be at or below it.
    """
    n, m, d = a.shape[0], b.shape[0], a.shape[1]
    w = 2 * band + 1
    inf = np.inf
    prev = np.full(w + 2, inf)
    cur = np.full(w + 2, inf)
    prev_len = np.zeros(w + 2, np.int64)
    cur_len = np.zeros(w + 2, np.int64)
    cost = np.empty(w)
    # D(0, 0) = c(a_0, b_0) as c + min(0, inf, inf): a zero "diagonal predecessor" of length 0
    prev[band + 1] = 0.0
    most_pairs = float(n + m - 1)
    for i in range(n):
        kmin = max(0, band - i)  # j = i - band + k >= 0
        kmax = min(w - 1, m - 1 - i + band)  # j <= m - 1
        for k in range(kmin + 1):  # (kmin itself is written below)
            cur[k] = inf
        for k in range(kmax + 2, w + 2):
            cur[k] = inf
        # the row's point costs first: independent of each other, unlike the recursion (the
        # compiler vectorises them); the plane spelled out, the same sum in the same order
        j0 = i - band
        if d == 2:
            ax, ay = a[i, 0], a[i, 1]
            for k in range(kmin, kmax + 1):
                dx, dy = ax - b[j0 + k, 0], ay - b[j0 + k, 1]
                cost[k] = 0.0 + dx * dx + dy * dy
        else:
            for k in range(kmin, kmax + 1):
                c = 0.0
                for q in range(d):
                    diff = a[i, q] - b[j0 + k, q]
                    c += diff * diff
                cost[k] = c
        if not squared:
            for k in range(kmin, kmax + 1):
                cost[k] = np.sqrt(cost[k])
        row_min = inf
        left, left_len = inf, 0  # D(i, j-1): outside the row at its start
        diag, diag_len = prev[kmin + 1], prev_len[kmin + 1]
        for k in range(kmin, kmax + 1):
            up, up_len = prev[k + 2], prev_len[k + 2]
            # min(D(i-1, j-1), D(i-1, j), D(i, j-1)), ties to the first
            best, blen = inf, 0
            if diag < best:
                best, blen = diag, diag_len
            if up < best:
                best, blen = up, up_len
            if left < best:
                best, blen = left, left_len
            left = cost[k] + best
            left_len = blen + 1
            cur[k + 1] = left
            cur_len[k + 1] = left_len
            row_min = min(row_min, left)
            diag, diag_len = up, up_len
        if row_min / most_pairs > limit_mean:
            return inf, 0
        prev, cur = cur, prev
        prev_len, cur_len = cur_len, prev_len
    kend = (m - 1) - (n - 1) + band + 1
    return prev[kend], prev_len[kend]


@njit(cache=True, error_model="numpy")
def _dtw_backtrack(steps, n, m, band, n_pairs):  # pragma: no cover - compiled
    """Warping path (n_pairs, 2) from (N-1, M-1) back to (0, 0) along the back-pointers."""
    path = np.empty((n_pairs, 2), np.int64)
    i, j = n - 1, m - 1
    for r in range(n_pairs - 1, -1, -1):
        path[r, 0] = i
        path[r, 1] = j
        if r == 0:
            break
        s = steps[i, j - max(0, i - band)]
        if s == 0:
            i -= 1
            j -= 1
        elif s == 1:
            i -= 1
        else:
            j -= 1
    return path


# ---------------------------------------------------------------------------------------------
# DTW
# ---------------------------------------------------------------------------------------------
@dataclass(frozen=True, eq=False)
class DtwAlignment:
    """Result of :func:`dtw_align`.

    Attributes
    ----------
    distance_m
        The DTW distance in m, per ``normalize`` and ``cost`` (see :func:`dtw_align`).
    total_cost
        Minimal sum of point costs along the warping path: m for ``cost="euclidean"``, m^2 for
        ``cost="sqeuclidean"``.
    n_pairs
        Number of matched pairs on the warping path, ``max(N, M) <= n_pairs <= N + M - 1``.
    path
        (n_pairs, 2) int64 index pairs (i into ``a``, j into ``b``), monotone and continuous
        from (0, 0) to (N-1, M-1); None unless requested.
    """

    distance_m: float
    total_cost: float
    n_pairs: int
    path: NDArray[np.int64] | None = None


def dtw_align(
    a: ArrayLike,
    b: ArrayLike,
    *,
    band: int | None = None,
    cost: Literal["euclidean", "sqeuclidean"] = "euclidean",
    normalize: Literal["mean", "none"] = "mean",
    return_path: bool = False,
) -> DtwAlignment:
    """Band-limited DTW distance and warping path between two trajectories (Chistyakov et al. (2021), Sec. 3).

    Parameters
    ----------
    a, b
        Trajectories (N, D) and (M, D) in m, same D (any D >= 1; pass ``[:, :2]`` for the
        horizontal plane).
    band
        Largest index difference ``|i - j|`` of matched samples; None = unbounded (full DTW).
        Must be at least ``|N - M|``.
    cost
        Point cost: ``"euclidean"`` ``||a_i - b_j||`` (default, Chistyakov et al. (2021)) or
        ``"sqeuclidean"`` ``||a_i - b_j||^2`` (dtaidistance's convention).
    normalize
        ``"mean"`` (default): ``distance_m = total_cost / n_pairs`` (``sqrt`` of it for
        ``"sqeuclidean"``, an RMS); ``"none"``: the total (``sqrt(total_cost)`` for
        ``"sqeuclidean"``, which equals ``dtaidistance.dtw_ndim.distance``).
    return_path
        Also return the warping path. Costs N x min(M, 2 band + 1) bytes of back-pointers.

    Returns
    -------
    DtwAlignment
        ``distance_m``, ``total_cost``, ``n_pairs`` and ``path``.

    Raises
    ------
    InvalidInputError
        Empty, non-finite or mismatched-dimension input.
    InvalidParameterError
        Negative or fractional band, ``band < |N - M|``, unknown ``cost`` / ``normalize``.

    Notes
    -----
    Recursion (Chistyakov et al. (2021), Sec. 3 after [12] Mueller 2007, ch. 4)::

        D(0, 0) = c(a_0, b_0)
        D(i, j) = c(a_i, b_j) + min(D(i-1, j-1), D(i-1, j), D(i, j-1)),   |i - j| <= band
        total_cost = D(N-1, M-1)

    The band is Chistyakov et al. (2021)'s "limit on the maximum allowed difference between the indices of
    corresponding points (index = sample number in the experiment)": literally
    ``|i - j| <= band`` on raw sample indices (a Sakoe-Chiba band), not the slanted
    ``|i - j N / M|``. With unequal lengths the end cell lies in the band only if
    ``band >= |N - M|``; a narrower band is an error, never silently widened. Resample both
    trajectories to one rate first if their rates differ.

    Normalisation: Chistyakov et al. (2021) does not state one, but its Table 1 lists DTW distances of
    0.09-16 m for 72-707 m walks sampled for 88-626 s, a per-point size, not a sum over tens
    of thousands of samples; hence the default mean per matched pair. The warping path
    minimises the total, not the mean; ties prefer the diagonal step.

    Time O(N x min(M, 2 band + 1)); memory O(min(M, 2 band + 1)) without the path, plus the
    int8 back-pointers of the band (never N x M unless the band covers M). numba kernel,
    compiled on first use and cached.

    Examples
    --------
    >>> import numpy as np
    >>> a = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]])
    >>> r = dtw_align(a, a[[0, 2]], return_path=True)
    >>> r.total_cost, r.n_pairs, r.path.tolist()
    (1.0, 3, [[0, 0], [1, 0], [2, 1]])
    """
    cost = _choice(cost, "cost", _COSTS)
    normalize = _choice(normalize, "normalize", _NORMALIZE)
    pa = _trajectory(a, "a")
    pb = _trajectory(b, "b")
    if pa.shape[1] != pb.shape[1]:
        raise InvalidInputError(
            f"a has {pa.shape[1]} coordinate(s) per position but b has {pb.shape[1]}; pass the same columns", field="b"
        )
    n, m = len(pa), len(pb)
    band_i = _band(band, n, m)
    if return_path:
        total, n_pairs, steps = _dtw_kernel(pa, pb, np.int64(band_i), cost == "sqeuclidean", True)
    else:
        total, n_pairs = _dtw_cost_kernel(pa, pb, np.int64(band_i), cost == "sqeuclidean", np.inf)
    total, n_pairs = float(total), int(n_pairs)
    per = total / n_pairs if normalize == "mean" else total
    distance = float(np.sqrt(per)) if cost == "sqeuclidean" else float(per)
    path = _readonly(_dtw_backtrack(steps, n, m, np.int64(band_i), np.int64(n_pairs))) if return_path else None
    return DtwAlignment(distance, total, n_pairs, path)
