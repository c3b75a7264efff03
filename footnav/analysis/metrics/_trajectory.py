"""Trajectory errors against a reference: absolute trajectory error (ATE), errors at surveyed
waypoints ([Lee2022]), final separation and final position error ([Zhao2019]), end-to-end and
loop-closure errors and the travelled distance ([Li2018]); references in :mod:`footnav.analysis.metrics`."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from footnav.analysis.metrics._alignment import rigid_align
from footnav.analysis.metrics._checks import (
    _check_dims,
    _finite,
    _float64,
    _percent,
    _point,
    _points,
    _readonly,
    _same_length,
)
from footnav.core.errors import InvalidInputError


@dataclass(frozen=True)
class WaypointErrors:
    """Result of :func:`waypoint_errors`: one row per pass of the reference by a waypoint.

    Attributes
    ----------
    errors_m
        Estimate-to-reference distance at each pass, m.
    index
        The sample of each pass (the reference's closest approach), int.
    waypoint
        Which waypoint each pass belongs to, int.
    mean_m, max_m
        Mean and maximum of ``errors_m`` (nan without passes), m.
    """

    errors_m: NDArray[np.float64]
    index: NDArray[np.int64]
    waypoint: NDArray[np.int64]
    mean_m: float
    max_m: float


def waypoint_errors(
    estimate: ArrayLike, reference: ArrayLike, waypoints: ArrayLike, *, radius_m: float = 1.0, dims: int = 2
) -> WaypointErrors:
    """Position error where the walk passes surveyed waypoints ([Lee2022] Table 3).

    Each time the reference comes within ``radius_m`` of a waypoint (horizontally) is one pass;
    its sample is the closest approach, and the error there is ``|| e_k - r_k ||``. A walk of
    several laps passes a waypoint several times.

    Parameters
    ----------
    estimate, reference
        Time-matched positions (N, 2|3) in m, one frame (align first, e.g. :func:`align_at_start`).
    waypoints
        (K, 2) horizontal waypoint positions in the reference's frame, m.
    radius_m
        How close a pass comes, m (the feet pass a centre-line mark at half the step width).
    dims
        2 (horizontal, default, as [Lee2022]) or 3.
    """
    dims = _check_dims(dims)
    est = _points(estimate, "estimate", dims)[:, :dims]
    ref = _points(reference, "reference", dims)
    _same_length(est, ref, "estimate", "reference")
    wp = _points(waypoints, "waypoints", 2)[:, :2]
    errors, index, which = [], [], []
    for j, w in enumerate(wp):
        d = np.linalg.norm(ref[:, :2] - w, axis=1)
        near = d <= radius_m
        if not near.any():
            continue
        edges = np.flatnonzero(np.diff(np.concatenate(([0], near.astype(np.int8), [0]))))
        for a, b in edges.reshape(-1, 2):
            k = a + int(np.argmin(d[a:b]))
            errors.append(float(np.linalg.norm(est[k] - ref[k, :dims])))
            index.append(k)
            which.append(j)
    e = np.asarray(errors, dtype=float)
    return WaypointErrors(
        errors_m=_readonly(e),
        index=_readonly(np.asarray(index, dtype=np.int64)),
        waypoint=_readonly(np.asarray(which, dtype=np.int64)),
        mean_m=float(e.mean()) if len(e) else float("nan"),
        max_m=float(e.max()) if len(e) else float("nan"),
    )


def ate_rmse(estimate: ArrayLike, reference: ArrayLike, *, dims: int = 2, with_scale: bool = False) -> float:
    """Absolute trajectory error: RMSE in m after :func:`rigid_align`.

    ``ATE = sqrt( (1/N) sum_i || ref_i - (s R est_i + t) ||^2 )`` over the first ``dims``
    coordinates (Sturm et al., IROS 2012, eq. 3, with Umeyama alignment). Not one of the seed
    papers' metrics; the usual trajectory benchmark.

    Parameters
    ----------
    estimate, reference
        Corresponding positions in m, (N, 2|3).
    dims
        2: x, y only (heading + horizontal offset aligned); 3: full 3-D.
    with_scale
        Fit a scale too (then the ATE ignores a scale error of the estimate).

    Returns
    -------
    float
        RMSE in m.
    """
    dims = _check_dims(dims)
    res = rigid_align(estimate, reference, dims=dims, with_scale=with_scale)
    ref = np.asarray(reference, dtype=np.float64)
    diff = res.aligned[:, :dims] - ref[:, :dims]
    return float(np.sqrt(np.mean(np.sum(diff**2, axis=1))))


def height_rmse(estimate: ArrayLike, reference: ArrayLike) -> float:
    """Vertical RMSE in m after removing the best constant height offset.

    ``sqrt( (1/N) sum_i (d_i - mean(d))^2 )`` with ``d_i = z_est,i - z_ref,i``: the height error
    that no choice of the start height removes (a climb that is not there, a flight of stairs
    too short), whatever the plane does. Not rotated: z is up in both frames.

    Parameters
    ----------
    estimate, reference
        Corresponding positions in m, (N, 3), or heights (N,).

    Returns
    -------
    float
        RMSE in m.
    """
    est = _float64(estimate, "estimate")
    ref = _float64(reference, "reference")
    z_est = est[:, 2] if est.ndim == 2 else est
    z_ref = ref[:, 2] if ref.ndim == 2 else ref
    _same_length(z_est, z_ref, "estimate", "reference")
    _finite(z_est, "estimate")
    _finite(z_ref, "reference")
    d = z_est - z_ref
    return float(np.sqrt(np.mean((d - d.mean()) ** 2)))


# ---------------------------------------------------------------------------------------------
# end-point metrics
# ---------------------------------------------------------------------------------------------
def final_separation(left_pos: ArrayLike, right_pos: ArrayLike, *, dims: int = 3) -> float:
    """Final foot separation E_s of [Zhao2019] eq. (8), in m.

    ``E_s = || P_hat_1,end^n - P_hat_2,end^n ||``, the 2-norm of the difference of the two feet's
    estimated end positions in the navigation frame. [Zhao2019] defines P^n as the (3-D) n-frame
    position state p^n, so the default is the 3-D norm; ``dims=2`` gives the horizontal one.

    Parameters
    ----------
    left_pos, right_pos
        Either foot's trajectory (N, 2|3) in m (its last row is used) or its end position (D,).
    dims
        3 (as [Zhao2019]) or 2 (x, y only).

    Returns
    -------
    float
        E_s in m.
    """
    dims = _check_dims(dims)
    a = _point(left_pos, "left_pos", dims)[:dims]
    b = _point(right_pos, "right_pos", dims)[:dims]
    return float(np.linalg.norm(a - b))


def final_position_error(pos: ArrayLike, reference_final: ArrayLike, *, dims: int = 3) -> float:
    """Final position error E_p of [Zhao2019] eq. (8), in m.

    ``E_p = || P_hat_i,end^n - P_i,end^n ||``, the 2-norm of the difference between one foot's
    estimated and true end position (n-frame, 3-D by default as in [Zhao2019]); [Zhao2019] Table I reports it
    per foot. For [Zhao2019]'s closed-loop walks the true end position is the start position.

    Parameters
    ----------
    pos
        The foot's trajectory (N, 2|3) in m (last row used) or its end position (D,).
    reference_final
        True end position (D,) in m, or a reference trajectory whose last row is used.
    dims
        3 (as [Zhao2019]) or 2 (x, y only).

    Returns
    -------
    float
        E_p in m.
    """
    dims = _check_dims(dims)
    a = _point(pos, "pos", dims)[:dims]
    b = _point(reference_final, "reference_final", dims)[:dims]
    return float(np.linalg.norm(a - b))


@dataclass(frozen=True)
class EndpointError:
    """An end-point distance (end-to-end or loop-closure error).

    Attributes
    ----------
    error_m
        The distance in m.
    error_percent
        ``100 * error_m / distance_m`` (nan if ``distance_m`` is 0).
    distance_m
        The travelled distance used as denominator, m.
    """

    error_m: float
    error_percent: float
    distance_m: float


@dataclass(frozen=True)
class DistanceError:
    """Travelled-distance error of [Li2018] Table 2.

    Attributes
    ----------
    distance_m
        Distance travelled by the estimate, m.
    reference_distance_m
        Reference distance, m.
    error_m
        Signed ``distance_m - reference_distance_m``, m.
    error_percent
        Signed ``100 * error_m / reference_distance_m`` ([Li2018] reports the magnitude).
    """

    distance_m: float
    reference_distance_m: float
    error_m: float
    error_percent: float


def travelled_distance(pos: ArrayLike, *, dims: int = 2) -> float:
    """Distance travelled along a polyline, in m: ``sum_k || p_{k+1} - p_k ||`` ([Li2018] Table 2).

    Sample-rate positions add the stance-phase jitter and the swing arc of the foot (3-D); pass
    footprints (one point per stance, :attr:`FootTrajectory.footprints`) for the step-level
    distance.

    Parameters
    ----------
    pos
        Positions (N, 2|3) in m, N >= 1.
    dims
        2 (horizontal, default) or 3.
    """
    dims = _check_dims(dims)
    p = _points(pos, "pos", dims)[:, :dims]
    return float(np.linalg.norm(np.diff(p, axis=0), axis=1).sum())


def travelled_distance_error(pos: ArrayLike, reference: ArrayLike | float, *, dims: int = 2) -> DistanceError:
    """Travelled-distance error of [Li2018] Table 2 ("Relative Error of Travel Distance (%)").

    ``error_percent = 100 (d_est - d_ref) / d_ref``. [Li2018]'s numbers follow this with d_ref the
    ground-truth length: (1077.69 - 1075) / 1075 = 0.250 % and (1131.19 - 1075) / 1075 = 5.227 %
    (reported 0.25 and 5.22).

    Parameters
    ----------
    pos
        Estimated positions (N, 2|3) in m.
    reference
        Reference positions (M, 2|3) in m, or the known reference length in m (e.g. a surveyed
        course).
    dims
        2 (horizontal, default) or 3.
    """
    dims = _check_dims(dims)
    d_est = travelled_distance(pos, dims=dims)
    d_ref = _reference_distance(reference, dims)
    return DistanceError(d_est, d_ref, d_est - d_ref, _percent(d_est - d_ref, d_ref))


def _reference_distance(reference: ArrayLike | float, dims: int, name: str = "reference") -> float:
    if np.ndim(reference) == 0:
        try:
            d = float(reference)  # type: ignore[arg-type]
        except (TypeError, ValueError):
            d = float("nan")
        if not np.isfinite(d) or d <= 0:
            raise InvalidInputError(f"must be a positive length in m, got {reference!r}", field=name)
        return d
    return travelled_distance(_points(reference, name, dims), dims=dims)


def end_to_end_error(
    pos: ArrayLike, reference: ArrayLike | None = None, *, dims: int = 2, reference_distance_m: float | None = None
) -> EndpointError:
    """End-to-end error of [Li2018] Table 2 ("End-to-End Error (m)" and "Positioning Accuracy (%)").

    * ``reference`` given: ``|| p_end - p_ref,end ||``, percent of the *reference* distance
      travelled. [Li2018]'s Table 2 percentages follow this: 23.31 / 1075 = 2.168 %, 24.76 / 1075 =
      2.303 %, 16.11 / 1075 = 1.499 % (reported, truncated, 2.16, 2.30, 1.49); dividing by the
      estimate's own distance would give 2.19 % instead of 2.30 % for the second column.
    * ``reference`` None (closed loop, the walk ends where it started): ``|| p_end - p_start ||``,
      percent of the estimate's distance travelled (same as :func:`loop_closure_error`).

    Both trajectories must be in one frame with a common start (footnav's nav frame: origin at the
    start); align first otherwise.

    Parameters
    ----------
    pos
        Estimated positions (N, 2|3) in m.
    reference
        Reference trajectory (M, 2|3) in m (need not have the estimate's time stamps), or None.
    dims
        2 (horizontal, default) or 3.
    reference_distance_m
        Denominator for the percentage instead of the travelled distance (e.g. the surveyed
        course length, 1075 m in [Li2018]).
    """
    dims = _check_dims(dims)
    p = _points(pos, "pos", dims)[:, :dims]
    if reference is None:
        err = float(np.linalg.norm(p[-1] - p[0]))
        den = travelled_distance(p, dims=dims)
    else:
        ref = _points(reference, "reference", dims)[:, :dims]
        err = float(np.linalg.norm(p[-1] - ref[-1]))
        den = travelled_distance(ref, dims=dims)
    if reference_distance_m is not None:
        den = _reference_distance(reference_distance_m, dims, "reference_distance_m")
    return EndpointError(err, _percent(err, den), den)


def loop_closure_error(pos: ArrayLike, *, dims: int = 2) -> EndpointError:
    """Loop-closure error of a walk that returns to its start, in m and % of the distance travelled.

    ``|| p_end - p_start ||`` and ``100 ||p_end - p_start|| / sum_k ||p_{k+1} - p_k||`` -- the
    closed-loop form of [Li2018]'s end-to-end error and of [Zhao2019]'s E_p for closed-loop trials ("the
    feet were expected to return to their start positions", [Zhao2019] section V-B).

    Parameters
    ----------
    pos
        Positions (N, 2|3) in m.
    dims
        2 (horizontal, default) or 3.
    """
    return end_to_end_error(pos, None, dims=dims)
