"""Step-level comparisons: per-stride length errors ([Zhao2019]) and footprint errors after one
rigid 2-D fit ([GD]); references in :mod:`footnav.analysis.metrics`."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from footnav.analysis.metrics._alignment import RigidAlignment, rigid_align
from footnav.analysis.metrics._checks import _check_dims, _events, _points, _readonly, _same_length
from footnav.core.errors import DataQualityWarning, InvalidInputError
from footnav.core.warning_log import warn


@dataclass(frozen=True, eq=False)
class StrideLengthErrors:
    """Per-stride length errors of :func:`stride_length_errors`.

    Attributes
    ----------
    errors_m
        Signed ``L_est,k - L_ref,k`` per matched stride, m.
    mean_error_m
        Mean signed error (bias), m.
    mean_abs_error_m
        Mean absolute error, m.
    rmse_m
        Root mean square error, m.
    max_abs_error_m
        Largest absolute error, m.
    n_strides
        Number of strides compared.
    """

    errors_m: NDArray[np.float64]
    mean_error_m: float
    mean_abs_error_m: float
    rmse_m: float
    max_abs_error_m: float
    n_strides: int


def stride_length_errors(est_footprints: ArrayLike, ref_footprints: ArrayLike, *, dims: int = 2) -> StrideLengthErrors:
    """Per-stride length error: estimated minus reference stride length, strides matched in order.

    A stride is the displacement between consecutive footprints of one foot,
    ``L_k = || f_{k+1} - f_k ||`` (horizontal by default, the "step length ... travelled distance
    in the forward ... direction" of [Zhao2019] section III-B, here per foot). Stride k of the estimate
    is compared with stride k of the reference, for the first ``min(K_est, K_ref) - 1`` strides.

    Parameters
    ----------
    est_footprints, ref_footprints
        Footprints (K, 2|3) in m, in walking order, K >= 2 (e.g.
        :attr:`FootTrajectory.footprints`).
    dims
        2 (horizontal, default) or 3.

    Warns
    -----
    DataQualityWarning
        When the footprint counts differ: a missed or extra step shifts the in-order pairing of
        every later stride, so the errors past it are not meaningful.
    """
    dims = _check_dims(dims)
    fe = _points(est_footprints, "est_footprints", dims, min_rows=2)[:, :dims]
    fr = _points(ref_footprints, "ref_footprints", dims, min_rows=2)[:, :dims]
    if len(fe) != len(fr):
        warn(
            f"{len(fe)} estimated vs {len(fr)} reference footprints: comparing the first "
            f"{min(len(fe), len(fr)) - 1} strides in order; a missed/extra step shifts the pairing",
            DataQualityWarning,
            stacklevel=2,
        )
    k = min(len(fe), len(fr))
    le = np.linalg.norm(np.diff(fe[:k], axis=0), axis=1)
    lr = np.linalg.norm(np.diff(fr[:k], axis=0), axis=1)
    err = le - lr
    return StrideLengthErrors(
        _readonly(err),
        float(err.mean()),
        float(np.abs(err).mean()),
        float(np.sqrt(np.mean(err**2))),
        float(np.abs(err).max()),
        int(len(err)),
    )


@dataclass(frozen=True, eq=False)
class FootprintErrors:
    """Footprint errors after one rigid 2-D fit (:func:`footprint_errors`).

    Attributes
    ----------
    rmse_m
        RMSE over the footprints of the horizontal distance between the fitted estimate and the
        footprint, m.
    final_m
        The last footprint's horizontal error after that same fit, m.
    n
        Number of footprints compared.
    errors_m
        (n,) each footprint's horizontal error after the fit, m.
    alignment
        The fit (:class:`RigidAlignment` of the estimate's footprint positions onto the
        footprints), e.g. to map the whole trajectory with ``alignment.apply``.
    """

    rmse_m: float
    final_m: float
    n: int
    errors_m: NDArray[np.float64]
    alignment: RigidAlignment


def footprint_errors(estimate: ArrayLike, footprints: ArrayLike, index: ArrayLike | None = None) -> FootprintErrors:
    """Footprint RMSE and final-footprint error after one rigid 2-D fit ([GD]).

    For a reference that knows only where each footprint lies (hand-marked on a floor-tile grid
    in [GD], ``FootTruth(frame="footprints")``), the estimate's position at each footprint's
    sample is fitted to the footprints by ONE proper rigid transform in the horizontal plane
    (heading + offset, :func:`rigid_align` with ``dims=2``; the footprints' origin and heading
    are arbitrary), then

    ``rmse_m = sqrt( (1/K) sum_k || fp_k - (R est_k + t) ||^2 )`` and
    ``final_m = || fp_K - (R est_K + t) ||``, horizontal (x, y) distances in m.

    One fit for the whole walk (not one per footprint), so heading drift shows up as error. The
    final error uses the same fit; it is not an end-point error after aligning the start.

    Parameters
    ----------
    estimate
        Estimated positions in m, (N, 2|3): a per-sample trajectory when ``index`` is given,
        else one row per footprint (K, 2|3).
    footprints
        Reference footprints (x, y[, z]) in m, (K, 2|3), K >= 2, in time order, in a z-up frame
        (a z-down frame's footprints are mirrored: negate their y first, as
        :func:`footnav.data.io.read_gaitdriven` does).
    index
        (K,) sample index of each footprint into ``estimate`` (the data set's ``strideIndex``,
        0-based), or None when ``estimate`` already holds one row per footprint.

    Returns
    -------
    FootprintErrors
        ``rmse_m``, ``final_m`` (m), ``n`` = K, per-footprint ``errors_m`` and the fit.

    Raises
    ------
    InvalidInputError
        Fewer than 2 footprints, row counts differ, an index outside the estimate (named with the
        first bad index), non-finite values.
    """
    fp = _points(footprints, "footprints", 2, min_rows=2)
    est = _points(estimate, "estimate", 2)
    if index is not None:
        idx = _events(index, "index")
        bad = (idx != np.round(idx)) | (idx < 0) | (idx >= len(est))
        if bad.any():
            i = int(np.argmax(bad))
            raise InvalidInputError(
                f"footprint index {idx[i]!r} is not a sample of the estimate (0..{len(est) - 1})",
                field="index",
                index=i,
            )
        _same_length(fp, idx, "footprints", "index")
        est = est[idx.astype(np.int64)]
    _same_length(fp, est, "footprints", "estimate")
    fit = rigid_align(est[:, :2], fp[:, :2], dims=2)
    err = np.linalg.norm(fit.aligned - fp[:, :2], axis=1)
    return FootprintErrors(
        rmse_m=float(np.sqrt(np.mean(err**2))),
        final_m=float(err[-1]),
        n=len(err),
        errors_m=_readonly(err),
        alignment=fit,
    )
