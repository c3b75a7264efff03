"""The averaged pedestrian path of two foot trajectories (Chistyakov et al. (2021), Sec. 3, Sec. 4 step 5).

Chistyakov et al., Russian Technological J. 2021 (full citation in docs/references.md),
Section 3 and Section 4, step 5: one averaged trajectory, either the midpoints of the
DTW-matched pairs (:func:`footnav.nav.dtw.dtw_align`; "timeless": paired points may come from
different times, [13] Vaughan and Gabrys 2016) or, when time matters, the midpoints of both feet
interpolated to one time grid, "approximately the centre of mass": :func:`timeless_average`,
:func:`timed_average`.

Frames and units: positions are in one navigation frame (x, y horizontal, z up), in m, samples
on axis 0; times in s. Nothing here aligns frames: align the feet first
(:func:`footnav.nav.dtw_heading.heading_mismatch`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from footnav.core.errors import InvalidInputError, InvalidParameterError
from footnav.nav.dtw import _float64, _readonly, _trajectory, dtw_align
from footnav.nav.interpolation import interp_columns

__all__ = ["AveragedPath", "timed_average", "timeless_average"]


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
    t_a: ArrayLike, a: ArrayLike, t_b: ArrayLike, b: ArrayLike, *, t: ArrayLike | None = None
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
    ia, ib = interp_columns(grid, ta, pa), interp_columns(grid, tb, pb)
    return AveragedPath(_readonly(0.5 * (ia + ib)), _readonly(grid))
