"""Band-limited dynamic time warping of two trajectories, and what Chistyakov et al. (2021) builds on it.

Chistyakov et al., Russian Technological J. 2021 (full citation in docs/references.md):

* Section 3 ("trajectory similarity metric"): the DTW metric between the left- and the right-foot
  trajectory, computed by dynamic programming ([12] Mueller 2007) with "an additional limit on the
  maximum allowed difference between the indices of corresponding points (the index is the
  sample number in the experiment)". Besides the value, the algorithm yields the sequence of
  matched point pairs (Fig. 2). Table 1 reports these distances in m: :func:`dtw_align`.
* Section 4, step 1: the initial heading mismatch of the two IMUs, found "by choosing the initial
  angles that minimise the DTW metric": :func:`heading_mismatch`.
* Section 3 and Section 4, step 5: one averaged trajectory, either the midpoints of the
  DTW-matched pairs ("timeless": paired points may come from different times, [13] Vaughan and
  Gabrys 2016) or, when time matters, the midpoints of both feet interpolated to one time grid,
  "approximately the centre of mass": :func:`timeless_average`, :func:`timed_average`.

Frames and units: positions are in one navigation frame (x, y horizontal, z up), in m, samples
on axis 0; times in s. Nothing here aligns frames implicitly except :func:`heading_mismatch`,
which returns the rotation about z it found.

:func:`footnav.core.metrics.dtw_distance` is a thin wrapper of :func:`dtw_align` (input checks on
``dims``, same numbers).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.optimize import minimize_scalar

from footnav.core._numba import njit  # numba.njit that survives a read-only install
from footnav.core.errors import InvalidInputError, InvalidParameterError

__all__ = [
    "DtwAlignment",
    "HeadingMismatch",
    "AveragedPath",
    "dtw_align",
    "heading_mismatch",
    "timeless_average",
    "timed_average",
]

#: Coarse grid of the heading search: 36 angles over the full turn, 10 deg apart.
DEFAULT_HEADING_GRID = 36
#: Angle tolerance of the bounded refinement of the heading search, rad (about 0.006 deg).
HEADING_XATOL_RAD = 1e-4

_COSTS = ("euclidean", "sqeuclidean")
_NORMALIZE = ("mean", "none")
_TRANSLATION = ("none", "start")


# ---------------------------------------------------------------------------------------------
# input checking
# ---------------------------------------------------------------------------------------------
def _readonly(a: NDArray) -> NDArray:
    a = np.ascontiguousarray(a)
    a.setflags(write=False)
    return a


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


def _times(value: ArrayLike, n: int, name: str) -> NDArray[np.float64]:
    """Strictly increasing finite times (n,) in s."""
    t = _float64(value, name)
    if t.shape != (n,):
        raise InvalidInputError(f"expected times in s of shape ({n},) (one per position), got {t.shape}", field=name)
    bad = ~np.isfinite(t)
    if bad.any():
        raise InvalidInputError(f"non-finite time {t[bad][0]!r}", field=name, index=int(np.argmax(bad)))
    back = np.diff(t) <= 0
    if back.any():
        k = int(np.argmax(back)) + 1
        raise InvalidInputError(f"times must increase strictly, got {t[k - 1]!r} then {t[k]!r}", field=name, index=k)
    return t


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
            f"a has {pa.shape[1]} coordinate(s) per position but b has {pb.shape[1]}; pass the same columns",
            field="b",
        )
    n, m = len(pa), len(pb)
    band_i = _band(band, n, m)
    total, n_pairs, steps = _dtw_kernel(pa, pb, np.int64(band_i), cost == "sqeuclidean", bool(return_path))
    total, n_pairs = float(total), int(n_pairs)
    per = total / n_pairs if normalize == "mean" else total
    distance = float(np.sqrt(per)) if cost == "sqeuclidean" else float(per)
    path = _readonly(_dtw_backtrack(steps, n, m, np.int64(band_i), np.int64(n_pairs))) if return_path else None
    return DtwAlignment(distance, total, n_pairs, path)


# ---------------------------------------------------------------------------------------------
# initial heading mismatch (Chistyakov et al. (2021), Sec. 4 step 1)
# ---------------------------------------------------------------------------------------------
def _rotate_xy(xy: NDArray[np.float64], angle_rad: float) -> NDArray[np.float64]:
    # [x'; y'] = [cos -sin; sin cos] [x; y]: counter-clockwise about +z (z up)
    c, s = np.cos(angle_rad), np.sin(angle_rad)
    return np.ascontiguousarray(xy @ np.array([[c, s], [-s, c]]))


def _wrap(angle_rad: float) -> float:
    return float((angle_rad + np.pi) % (2.0 * np.pi) - np.pi)


@dataclass(frozen=True, eq=False)
class HeadingMismatch:
    """Result of :func:`heading_mismatch`: the horizontal motion that best lays ``b`` onto ``a``.

    ``b`` is mapped to ``pivot + shift + R_z(angle) (b - pivot)`` in the x, y plane (z unchanged).

    Attributes
    ----------
    angle_rad
        Rotation of ``b`` about the vertical (+z up, counter-clockwise positive) in (-pi, pi].
    distance_m
        Mean DTW distance (:func:`dtw_align`, ``normalize="mean"``) after the motion, m.
    pivot_m
        (2,) point the rotation is about, m: ``b``'s first horizontal position.
    shift_m
        (2,) horizontal translation applied after the rotation, m (zero for
        ``translation="none"``).
    """

    angle_rad: float
    distance_m: float
    pivot_m: NDArray[np.float64]
    shift_m: NDArray[np.float64]

    def apply(self, points: ArrayLike) -> NDArray[np.float64]:
        """``points`` (N, 2|3) in m moved like ``b``; z (if any) unchanged."""
        p = _trajectory(points, "points", min_cols=2).copy()
        p[:, :2] = self.pivot_m + self.shift_m + _rotate_xy(p[:, :2] - self.pivot_m, self.angle_rad)
        return p


def heading_mismatch(
    a: ArrayLike,
    b: ArrayLike,
    *,
    band: int | None,
    translation: Literal["none", "start"] = "none",
    grid: int = DEFAULT_HEADING_GRID,
) -> HeadingMismatch:
    """Rotation of ``b`` about the vertical minimising its DTW distance to ``a`` (Chistyakov et al. (2021), Sec. 4).

    Chistyakov et al. (2021), Sec. 4 step 1: "determine the initial mismatch of the IMUs' orientations: the
    value of the DTW metric is minimised by choosing the initial angles". A foot trajectory from
    a strapdown INS turns rigidly about its start when its initial yaw changes, so ``b`` is
    rotated about its first point. The search is over one angle: ``grid`` equally spaced angles
    over the full turn, then ``scipy.optimize.minimize_scalar(method="bounded")`` within one grid
    step either side of the best.

    Parameters
    ----------
    a, b
        Trajectories (N, 2|3) and (M, 2|3) in m in the nav frame (z up); only x, y are used.
        Decimate long recordings first (e.g. to 10 Hz): each evaluation is one banded DTW.
    band
        Largest index difference of matched samples (:func:`dtw_align`); None = unbounded.
    translation
        ``"none"`` (default): rotation only, the positions as given (Chistyakov et al. (2021) searches angles
        only). ``"start"``: also move ``b``'s first point onto ``a``'s, for trajectories that
        each start at their own origin.
    grid
        Number of coarse angles (>= 4); 36 = 10 deg apart.

    Returns
    -------
    HeadingMismatch
        ``angle_rad`` (rad), ``distance_m`` (m), and ``apply(b)`` to move ``b``.

    Raises
    ------
    InvalidInputError, InvalidParameterError
        As :func:`dtw_align`; unknown ``translation``; ``grid < 4``.

    Notes
    -----
    The mean DTW distance is continuous but not smooth in the angle (the warping path changes
    discretely), and it can have several minima for closed or symmetric walks: the coarse grid
    picks the basin, the bounded refinement (``xatol`` = 1e-4 rad) its bottom.

    Two feet walk a step width apart, so the DTW-optimal angle is not exactly their initial
    heading mismatch (turning one loop slightly brings it nearer the other on some sides). On
    the simulated 20 m x 10 m rectangle (feet 0.2 m apart, 10 Hz, band 20) the error was
    0.009-0.012 rad with ``translation="none"`` and 0.014-0.015 rad with ``"start"``
    (``tests/core/test_dtw_core.py``); for one trajectory and a rotated copy of it, below 1e-3 rad.

    Examples
    --------
    >>> import numpy as np
    >>> a = np.column_stack([np.linspace(0, 10, 50), np.zeros(50)])
    >>> b = np.column_stack([np.zeros(50), np.linspace(0, 10, 50)])  # a turned by +90 deg
    >>> round(heading_mismatch(a, b, band=5).angle_rad, 3)
    -1.571
    """
    translation = _choice(translation, "translation", _TRANSLATION)
    if isinstance(grid, bool) or not isinstance(grid, (int, np.integer)) or grid < 4:
        raise InvalidParameterError(f"grid must be a whole number of angles >= 4, got {grid!r}")
    pa = _trajectory(a, "a", min_cols=2)[:, :2]
    pb = _trajectory(b, "b", min_cols=2)[:, :2]
    _band(band, len(pa), len(pb))  # fail before the search, not inside it
    pivot = pb[0].copy()
    shift = pa[0] - pb[0] if translation == "start" else np.zeros(2)
    a_rel = np.ascontiguousarray(pa - pivot - shift)  # compare in b's rotation frame
    b_rel = pb - pivot

    def cost(angle: float) -> float:
        return dtw_align(a_rel, _rotate_xy(b_rel, angle), band=band).distance_m

    angles = np.linspace(-np.pi, np.pi, int(grid), endpoint=False)
    costs = np.array([cost(x) for x in angles])
    best = float(angles[int(np.argmin(costs))])
    step = 2.0 * np.pi / grid
    res = minimize_scalar(
        cost, bounds=(best - step, best + step), method="bounded", options={"xatol": HEADING_XATOL_RAD}
    )
    angle, dist = (float(res.x), float(res.fun)) if res.fun <= costs.min() else (best, float(costs.min()))
    return HeadingMismatch(_wrap(angle), dist, _readonly(pivot), _readonly(np.asarray(shift, dtype=np.float64)))


# ---------------------------------------------------------------------------------------------
# averaged pedestrian path (Chistyakov et al. (2021), Sec. 3, Sec. 4 step 5)
# ---------------------------------------------------------------------------------------------
@dataclass(frozen=True, eq=False)
class AveragedPath:
    """Result of :func:`timeless_average` and :func:`timed_average`.

    Attributes
    ----------
    position
        (L, D) midpoints in m, same frame and columns as the inputs (nav frame, z up).
    t
        (L,) times in s: the common grid (timed), or the mean of each pair's two times
        (timeless, non-decreasing; None when no times were given).
    pairs
        (L, 2) int64 indices (into ``a``, into ``b``) of the DTW-matched pairs (timeless);
        None for the timed average.
    distance_m
        Mean DTW distance of the matching in m (:func:`dtw_align`, ``normalize="mean"``, over
        the matched columns), timeless only; None for the timed average.
    """

    position: NDArray[np.float64]
    t: NDArray[np.float64] | None = None
    pairs: NDArray[np.int64] | None = None
    distance_m: float | None = None


def timeless_average(
    a: ArrayLike,
    b: ArrayLike,
    *,
    band: int | None,
    dims: int | None = None,
    t_a: ArrayLike | None = None,
    t_b: ArrayLike | None = None,
) -> AveragedPath:
    """Midpoints of the DTW-matched point pairs of two trajectories ("DTW pairing", Chistyakov et al. (2021), Sec. 3).

    "If for every such pair of points [matched by the modified DTW algorithm] one takes the
    middle of the segment joining them, one obtains an averaged curve ([13] Vaughan and Gabrys
    2016) ... averaging this way loses the measurement times, since matched points may come
    from different moments" (Chistyakov et al. (2021), Sec. 3). Point k of the result is
    ``(a[i_k] + b[j_k]) / 2`` for the k-th pair (i_k, j_k) of the banded DTW path.

    Parameters
    ----------
    a, b
        Trajectories (N, D) and (M, D) in m, same frame (nav, z up) and columns.
    band
        Largest index difference of matched samples (:func:`dtw_align`); None = unbounded.
    dims
        Number of leading columns the matching uses (2: horizontal, as in Chistyakov et al. (2021), Fig. 2);
        default all. All D columns are averaged.
    t_a, t_b
        Optional sample times (N,), (M,) in s; if both are given, ``t`` of the result is the mean
        of each pair's times.

    Returns
    -------
    AveragedPath
        ``position`` (L, D) in m with ``max(N, M) <= L <= N + M - 1``, ``pairs`` (L, 2),
        ``t`` (L,) in s or None, and the matching's mean DTW distance ``distance_m`` in m.

    Raises
    ------
    InvalidInputError, InvalidParameterError
        As :func:`dtw_align`; ``dims`` out of range; only one of ``t_a``, ``t_b`` given.
    """
    pa = _trajectory(a, "a")
    pb = _trajectory(b, "b")
    if pa.shape[1] != pb.shape[1]:
        raise InvalidInputError(f"a has {pa.shape[1]} coordinate(s) per position but b has {pb.shape[1]}", field="b")
    ncol = pa.shape[1]
    if dims is None:
        dims = ncol
    if isinstance(dims, bool) or not isinstance(dims, (int, np.integer)) or not 1 <= dims <= ncol:
        raise InvalidParameterError(f"dims must be a whole number from 1 to {ncol} (the inputs' columns), got {dims!r}")
    if (t_a is None) != (t_b is None):
        raise InvalidParameterError("give both t_a and t_b (times of a and b in s) or neither")
    if t_a is not None:
        ta, tb = _times(t_a, len(pa), "t_a"), _times(t_b, len(pb), "t_b")
    res = dtw_align(pa[:, :dims], pb[:, :dims], band=band, return_path=True)
    i, j = res.path[:, 0], res.path[:, 1]
    position = 0.5 * (pa[i] + pb[j])  # midpoint of each matched pair
    t = None if t_a is None else _readonly(0.5 * (ta[i] + tb[j]))
    return AveragedPath(_readonly(position), t, res.path, res.distance_m)


def timed_average(
    t_a: ArrayLike,
    a: ArrayLike,
    t_b: ArrayLike,
    b: ArrayLike,
    *,
    t: ArrayLike | None = None,
) -> AveragedPath:
    """Midpoints of two trajectories interpolated to one time grid (Chistyakov et al. (2021), Sec. 3).

    "If time matters (e.g. to compare with a high-accuracy reference), it suffices to
    interpolate the points of one of them to bring both feet to one time grid. The middle of
    the segment joining the feet at one moment then approximately corresponds to the
    pedestrian's centre of mass" (Chistyakov et al. (2021), Sec. 3). Point k is
    ``(a(t_k) + b(t_k)) / 2`` with both trajectories linearly interpolated in time.

    Parameters
    ----------
    t_a, a
        Strictly increasing times (N,) in s and positions (N, D) in m (nav frame, z up).
    t_b, b
        Likewise (M,), (M, D) for the other foot, same frame, columns and clock.
    t
        Output times (L,) in s, strictly increasing and inside both trajectories' time spans.
        Default: ``t_a`` within the common span ``[max(t_a[0], t_b[0]), min(t_a[-1], t_b[-1])]``
        (only ``b`` is interpolated, as in the paper); nothing is extrapolated.

    Returns
    -------
    AveragedPath
        ``t`` (L,) in s and ``position`` (L, D) in m; ``pairs`` is None.

    Raises
    ------
    InvalidInputError
        Bad shapes or times, time spans that do not overlap, ``t`` outside the common span.
    """
    pa = _trajectory(a, "a")
    pb = _trajectory(b, "b")
    if pa.shape[1] != pb.shape[1]:
        raise InvalidInputError(f"a has {pa.shape[1]} coordinate(s) per position but b has {pb.shape[1]}", field="b")
    ta, tb = _times(t_a, len(pa), "t_a"), _times(t_b, len(pb), "t_b")
    start, stop = max(ta[0], tb[0]), min(ta[-1], tb[-1])
    if start > stop:
        raise InvalidInputError(
            f"the time spans do not overlap: a covers {ta[0]!r}..{ta[-1]!r} s, b covers {tb[0]!r}..{tb[-1]!r} s "
            "(synchronise the clocks first)",
            field="t_b",
        )
    if t is None:
        grid = ta[(ta >= start) & (ta <= stop)]
    else:
        grid = _times(t, np.size(t), "t")
        outside = (grid < start) | (grid > stop)
        if outside.any():
            k = int(np.argmax(outside))
            raise InvalidInputError(
                f"time {grid[k]!r} s is outside the common span {start!r}..{stop!r} s; nothing is extrapolated",
                field="t",
                index=k,
            )
    ia = np.column_stack([np.interp(grid, ta, pa[:, q]) for q in range(pa.shape[1])])
    ib = np.column_stack([np.interp(grid, tb, pb[:, q]) for q in range(pb.shape[1])])
    return AveragedPath(_readonly(0.5 * (ia + ib)), _readonly(grid))
