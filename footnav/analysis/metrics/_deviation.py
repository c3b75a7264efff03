"""Deviation of a trajectory from a reference over the walk ([Chistyakov2021], [Li2018]): the DTW
distance, the time-matched maximum deviation and its ratio to the distance travelled, and the
interpolation that time-matches two trajectories; references in :mod:`footnav.analysis.metrics`."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from footnav.analysis.metrics._checks import _check_dims, _events, _percent, _points, _same_length
from footnav.core.errors import InvalidInputError, InvalidParameterError
from footnav.nav.dtw import DtwAlignment, dtw_align
from footnav.nav.interpolation import interp_columns

#: Minimum reference distance travelled (m) before the deviation / distance ratio of
#: :func:`max_deviation` is evaluated. [Chistyakov2021] does not say how it treats the first metres, where
#: the ratio is ill-conditioned (a few cm of deviation over a few cm of walking); 5 m is about
#: three strides, past the initial standstill and first steps.
DEFAULT_RATIO_MIN_DISTANCE_M = 5.0


# ---------------------------------------------------------------------------------------------
# dynamic time warping
# ---------------------------------------------------------------------------------------------
#: Result of :func:`dtw_distance`: ``distance_m``, ``total_cost``, ``n_pairs``, ``path``. The same
#: class as :class:`footnav.nav.dtw.DtwAlignment`, so that the wrapper returns the kernel's result
#: as it is; the name stays for callers of this module.
DtwResult = DtwAlignment


def dtw_distance(
    a: ArrayLike,
    b: ArrayLike,
    *,
    band: int | None = None,
    dims: int = 2,
    normalize: Literal["mean", "none"] = "mean",
    cost: Literal["euclidean", "sqeuclidean"] = "euclidean",
    return_path: bool = False,
) -> DtwResult:
    """Dynamic time warping distance between two trajectories, with a Sakoe-Chiba band.

    ``D(i, j) = c(a_i, b_j) + min(D(i-1, j-1), D(i-1, j), D(i, j-1))``, ``D(0, 0) = c(a_0, b_0)``,
    over cells with ``|i - j| <= band``; ``total_cost = D(N-1, M-1)``. The point cost is the
    Euclidean distance ``c = ||a_i - b_j||`` over the first ``dims`` coordinates ([Chistyakov2021] section 3,
    [Li2018] Table 2) or its square (``cost="sqeuclidean"``, the convention of dtaidistance).

    The band is [Chistyakov2021]'s "additional limit on the maximum allowed difference between the indices of
    corresponding points (index = sample number in the experiment)": literally ``|i - j| <= band``
    on raw sample indices. With unequal lengths the end cell (N-1, M-1) lies in the band only if
    ``band >= |N - M|``; a narrower band is an error (it is *not* silently widened, which would
    change the constraint). Resample both trajectories to one rate first if their rates differ.

    Normalisation (``distance_m``):

    * ``"mean"`` (default): mean cost per matched pair, ``total_cost / n_pairs`` in m (for
      ``"sqeuclidean"``: ``sqrt(total_cost / n_pairs)``, an RMS). [Chistyakov2021] Table 1 reports DTW
      distances in m of 0.09-16 m for 72-707 m walks, i.e. a per-point figure, not a sum over
      thousands of samples.
    * ``"none"``: the raw total (``sqrt(total_cost)`` for ``"sqeuclidean"``, equal to
      ``dtaidistance.dtw_ndim.distance``). [Li2018] Table 2 reports such unnormalised totals
      (8784 for a 1075 m walk, no unit given).

    The warping path minimises the total, not the mean; ties prefer the diagonal step.

    Parameters
    ----------
    a, b
        Trajectories (N, 2|3) and (M, 2|3) in m.
    band
        Maximum index difference ``|i - j|`` in samples; None = unbounded.
    dims
        2 (x, y, default) or 3.
    normalize
        ``"mean"`` or ``"none"``, see above.
    cost
        ``"euclidean"`` (default) or ``"sqeuclidean"``.
    return_path
        Also return the warping path (costs N x min(M, 2 band + 1) bytes of back-pointers, i.e.
        N x M for ``band=None``).

    Returns
    -------
    DtwResult
        ``distance_m``, ``total_cost``, ``n_pairs`` and ``path``.

    Raises
    ------
    InvalidInputError
        Empty or non-finite input.
    InvalidParameterError
        ``band < |N - M|``, negative band, unknown ``normalize`` / ``cost``.

    Notes
    -----
    Time and memory O(N x min(M, 2 band + 1)) in the numba kernel of
    :func:`footnav.nav.dtw.dtw_align`, which this wraps (first call compiles, cached).
    """
    dims = _check_dims(dims)
    pa = _points(a, "a", dims)[:, :dims]
    pb = _points(b, "b", dims)[:, :dims]
    return dtw_align(pa, pb, band=band, cost=cost, normalize=normalize, return_path=return_path)


# ---------------------------------------------------------------------------------------------
# deviation from a reference
# ---------------------------------------------------------------------------------------------
def interpolate_positions(t: ArrayLike, position: ArrayLike, t_new: ArrayLike) -> NDArray[np.float64]:
    """Positions linearly interpolated to times ``t_new`` (s), for time-matched comparisons.

    Parameters
    ----------
    t
        Strictly increasing times (N,) in s.
    position
        (N, 2|3) positions in m.
    t_new
        (K,) times in s within ``[t[0], t[-1]]`` (no extrapolation).
    """
    tt = _events(t, "t").astype(np.float64)
    p = _points(position, "position", 2)
    _same_length(tt, p, "t", "position")
    tn = _events(t_new, "t_new").astype(np.float64)
    if len(tt) < 2 or (np.diff(tt) <= 0).any():
        raise InvalidInputError("need at least 2 strictly increasing times", field="t")
    if len(tn) and (tn.min() < tt[0] or tn.max() > tt[-1]):
        raise InvalidInputError(f"times outside [{tt[0]:g}, {tt[-1]:g}] s would need extrapolation", field="t_new")
    return interp_columns(tn, tt, p)


@dataclass(frozen=True)
class MaxDeviation:
    """Maximum deviation from a reference, [Chistyakov2021] Table 2.

    Attributes
    ----------
    max_deviation_m
        ``max_k || e_k - r_k ||``, m.
    max_deviation_index
        Sample index k where it occurs.
    max_ratio
        ``max_k || e_k - r_k || / s_k`` (fraction, not percent) with ``s_k`` the reference distance
        travelled up to sample k, over samples with ``s_k >= min_distance_m`` (nan if none).
    max_ratio_index
        Sample index of ``max_ratio`` (-1 if none).
    distance_m
        Total reference distance travelled, m.
    max_deviation_percent
        ``100 max_deviation_m / distance_m``, the "no more than 2 % of the full length" figure of
        [Chistyakov2021] section 6.
    """

    max_deviation_m: float
    max_deviation_index: int
    max_ratio: float
    max_ratio_index: int
    distance_m: float
    max_deviation_percent: float


def max_deviation(
    estimate: ArrayLike, reference: ArrayLike, *, dims: int = 2, min_distance_m: float = DEFAULT_RATIO_MIN_DISTANCE_M
) -> MaxDeviation:
    """Maximum deviation from the reference and its maximum ratio to the distance travelled ([Chistyakov2021] Table 2).

    [Chistyakov2021] section 6: "deviation is understood as the Euclidean distance between points of the
    trajectories at a fixed moment of time" -- time-matched, not nearest-point: row k of the
    estimate is compared with row k of the reference. Table 2 also gives "the maximum ratio of the
    deviation to the length of the path travelled". Its values (0.03-0.11) are far above
    max deviation / total length (e.g. 0.53 m / 71.92 m = 0.007 for walk 1), so the ratio is taken
    per sample against the distance travelled *so far*: ``max_k d_k / s_k``, with ``s_k`` the
    reference's cumulative distance. Samples with ``s_k < min_distance_m`` are skipped, where the
    ratio is ill-conditioned (the paper does not say how it handles the start).

    Parameters
    ----------
    estimate, reference
        Time-matched positions (N, 2|3) in m, same N (see :func:`interpolate_positions`), same
        frame (align first if needed; [Chistyakov2021] uses a known common start).
    dims
        2 (horizontal, default: [Chistyakov2021] compares with horizontal RTK fixes on level walks) or 3.
    min_distance_m
        Minimum reference distance travelled before the ratio is evaluated, m.
    """
    dims = _check_dims(dims)
    est = _points(estimate, "estimate", dims)[:, :dims]
    ref = _points(reference, "reference", dims)[:, :dims]
    _same_length(est, ref, "estimate", "reference")
    if not np.isfinite(min_distance_m) or min_distance_m < 0:
        raise InvalidParameterError(f"min_distance_m must be >= 0 m, got {min_distance_m!r}")
    dev = np.linalg.norm(est - ref, axis=1)
    s = np.concatenate(([0.0], np.cumsum(np.linalg.norm(np.diff(ref, axis=0), axis=1))))
    k_dev = int(np.argmax(dev))
    ok = (s >= min_distance_m) & (s > 0)
    if ok.any():
        ratio = np.where(ok, dev / np.where(ok, s, 1.0), -np.inf)
        k_ratio = int(np.argmax(ratio))
        max_ratio = float(ratio[k_ratio])
    else:
        k_ratio, max_ratio = -1, float("nan")
    total = float(s[-1])
    return MaxDeviation(float(dev[k_dev]), k_dev, max_ratio, k_ratio, total, _percent(float(dev[k_dev]), total))
