"""Accuracy metrics for foot-mounted inertial navigation, as defined in footnav's seed papers.

Plain functions on numpy arrays, SI units (positions in m, times in s, event positions in
samples). Positions are ``(N, 2)`` or ``(N, 3)`` arrays in one frame, samples on axis 0; the
``dims`` keyword selects the horizontal plane (``dims=2``: x, y) or full 3-D (``dims=3``).

References (full citations in docs/references.md):

* [Zhao2019] Zhao et al., IEEE Sensors J. 2019 -- final foot separation E_s and final position error
  E_p, eq. (8), Table I.
* [Chistyakov2021] Chistyakov et al., Russian Technological J. 2021 -- DTW distance between the left and the
  right foot with a limit on the index difference (section 3, Table 1); maximum deviation from the
  RTK reference and its maximum ratio to the distance travelled (Table 2).
* [Li2018] Li, Derrode et al., TAIMA 2018 -- steps found / missing / false (Table 1); end-to-end
  error, travelled distance and its relative error, DTW distance (Table 2).
* [Lee2022] Lee, Cho, Park, JPNT 2022 -- position error at surveyed waypoints (Table 3).

Dataset papers whose truth some metrics are shaped for:

* [IPOL] Voisard, de l'Escalopier, Ricard, Oudre, "A Reference Data Set for the Study of Healthy
  Subject Gait with Inertial Measurement Units", IPOL 13 (2023), art. 497 -- hand-checked
  swings (toe-off, heel strike) inside trial boundaries: :func:`step_detection_from_swings`.
* [GD] Cetin & Koroglu, "A Stride-Wise Annotated Mini-Dataset for Gait-Driven Learning-Based
  Inertial Navigation", Turk. J. EE&CS 2026 -- hand-marked footprint positions:
  :func:`footprint_errors`.

Trajectory metrics compare arrays *as given*: none of them aligns frames implicitly. Use
:func:`rigid_align` first when the reference lives in another frame (motion capture, RTK).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Iterator, Literal, NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.optimize import linear_sum_assignment

from footnav.core.dtw import DtwAlignment, dtw_align
from footnav.core.errors import DataQualityWarning, InvalidInputError, InvalidParameterError
from footnav.core.types import stance_intervals
from footnav.core.warning_log import warn

__all__ = [
    "DEFAULT_RATIO_MIN_DISTANCE_M",
    "RigidAlignment",
    "EndpointError",
    "DistanceError",
    "DtwResult",
    "MaxDeviation",
    "StrideLengthErrors",
    "FootprintErrors",
    "EventMatches",
    "StepDetection",
    "SampleScores",
    "TimingError",
    "WaypointErrors",
    "rigid_align",
    "align_at_start",
    "waypoint_errors",
    "ate_rmse",
    "final_separation",
    "final_position_error",
    "travelled_distance",
    "travelled_distance_error",
    "end_to_end_error",
    "loop_closure_error",
    "interpolate_positions",
    "dtw_distance",
    "max_deviation",
    "stride_length_errors",
    "footprint_errors",
    "match_events",
    "step_detection",
    "step_detection_from_events",
    "step_detection_from_swings",
    "sample_scores",
    "event_timing_error",
]

#: Minimum reference distance travelled (m) before the deviation / distance ratio of
#: :func:`max_deviation` is evaluated. [Chistyakov2021] does not say how it treats the first metres, where
#: the ratio is ill-conditioned (a few cm of deviation over a few cm of walking); 5 m is about
#: three strides, past the initial standstill and first steps.
DEFAULT_RATIO_MIN_DISTANCE_M = 5.0

#: Percent per unit fraction.
_PERCENT = 100.0

_VALID_DIMS = (2, 3)


# ---------------------------------------------------------------------------------------------
# input checking
# ---------------------------------------------------------------------------------------------
def _check_dims(dims: int) -> int:
    if dims not in _VALID_DIMS:
        raise InvalidParameterError(f"dims must be 2 (horizontal x, y) or 3 (x, y, z), got {dims!r}")
    return int(dims)


def _finite(arr: NDArray, name: str) -> None:
    bad = ~np.isfinite(arr)
    if bad.any():
        first = int(np.argmax(bad.reshape(len(arr), -1).any(axis=1)))
        raise InvalidInputError(f"non-finite value {arr[first]!r}; every value must be finite", field=name, index=first)


def _float64(value: ArrayLike, name: str) -> NDArray[np.float64]:
    """``value`` as a float64 array; InvalidInputError naming ``name`` if it is not numeric."""
    try:
        return np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise InvalidInputError(f"cannot convert to float64 ({exc})", field=name) from None


def _points(value: ArrayLike, name: str, dims: int, *, min_rows: int = 1) -> NDArray[np.float64]:
    """``value`` as a finite float64 (N, D) position array with D >= dims and N >= min_rows."""
    arr = _float64(value, name)
    if arr.ndim != 2 or arr.shape[1] < dims or arr.shape[1] > 3:
        raise InvalidInputError(
            f"expected positions in m of shape (N, {dims})"
            + (" or (N, 3)" if dims == 2 else "")
            + f", got {arr.shape}",
            field=name,
        )
    if len(arr) < min_rows:
        what = "is empty" if len(arr) == 0 else f"has {len(arr)} row(s)"
        raise InvalidInputError(f"{what}; need at least {min_rows} position(s)", field=name)
    _finite(arr, name)
    return arr


def _point(value: ArrayLike, name: str, dims: int) -> NDArray[np.float64]:
    """A single position (D,), or the last row of an (N, D) trajectory."""
    arr = _float64(value, name)
    if arr.ndim == 1:
        arr = arr[None, :]
    return _points(arr, name, dims)[-1]


def _same_length(a: NDArray, b: NDArray, name_a: str, name_b: str) -> None:
    if len(a) != len(b):
        raise InvalidInputError(
            f"has {len(b)} rows but {name_a!r} has {len(a)}; the rows must correspond one to one "
            "(same time stamps; resample with interpolate_positions)",
            field=name_b,
        )


def _events(value: ArrayLike, name: str) -> NDArray:
    """Event positions (samples) as a finite 1-D array; empty is allowed (no events)."""
    try:
        arr = np.asarray(value)
        if arr.dtype == bool or not np.issubdtype(arr.dtype, np.number):
            raise TypeError(f"dtype {arr.dtype} is not numeric (pass event indices, not a mask)")
    except (TypeError, ValueError) as exc:
        raise InvalidInputError(f"cannot read event indices ({exc})", field=name) from None
    if arr.ndim != 1:
        raise InvalidInputError(f"expected event indices of shape (K,), got {arr.shape}", field=name)
    if not np.issubdtype(arr.dtype, np.integer):
        arr = arr.astype(np.float64)
        _finite(arr, name)
    return arr


def _mask(value: ArrayLike, name: str) -> NDArray[np.bool_]:
    try:
        arr = np.asarray(value)
    except (TypeError, ValueError) as exc:  # pragma: no cover - numpy accepts almost anything
        raise InvalidInputError(f"cannot read mask ({exc})", field=name) from None
    if arr.ndim != 1:
        raise InvalidInputError(f"expected a per-sample mask of shape (N,), got {arr.shape}", field=name)
    if len(arr) == 0:
        raise InvalidInputError("is empty; need at least one sample", field=name)
    if arr.dtype != bool:
        if not np.issubdtype(arr.dtype, np.number):
            raise InvalidInputError(f"dtype {arr.dtype} is not boolean or numeric", field=name)
        _finite(arr.astype(np.float64), name)
        bad = (arr != 0) & (arr != 1)
        if bad.any():
            i = int(np.argmax(bad))
            raise InvalidInputError(f"value {arr[i]!r} is not 0/1 or boolean", field=name, index=i)
    return arr.astype(bool)


def _readonly(a: NDArray) -> NDArray:
    a = np.ascontiguousarray(a)
    a.setflags(write=False)
    return a


def _percent(num: float, den: float) -> float:
    # nan, not inf or an error, when the denominator is zero: the metric is undefined there
    return float(_PERCENT * num / den) if den > 0 else float("nan")


# ---------------------------------------------------------------------------------------------
# alignment
# ---------------------------------------------------------------------------------------------
@dataclass(frozen=True, eq=False)
class RigidAlignment:
    """Result of :func:`rigid_align`; unpacks as ``aligned, rotation, translation``.

    Attributes
    ----------
    aligned
        The estimate mapped onto the reference, same shape as the estimate, m.
    rotation
        Proper rotation (det = +1), (D, D) with D the estimate's column count. For ``dims=2`` and
        3-column input it is a rotation about z: ``[[c, -s, 0], [s, c, 0], [0, 0, 1]]``.
    translation
        (D,) in m; for ``dims=2`` its z component is 0.
    scale
        Scale factor (1.0 unless ``with_scale``). For ``dims=2`` it applies to x, y only.
    dims
        2 or 3, as requested.
    """

    aligned: NDArray[np.float64]
    rotation: NDArray[np.float64]
    translation: NDArray[np.float64]
    scale: float
    dims: int

    def __iter__(self) -> Iterator[NDArray[np.float64]]:
        # lets callers write ``aligned, R, t = rigid_align(...)``
        return iter((self.aligned, self.rotation, self.translation))

    def apply(self, points: ArrayLike) -> NDArray[np.float64]:
        """Map other points of the estimate's frame (e.g. footprints), (K, D) in m, the same way."""
        p = _points(points, "points", self.rotation.shape[0])
        if p.shape[1] != self.rotation.shape[0]:
            raise InvalidInputError(f"expected {self.rotation.shape[0]} columns, got {p.shape[1]}", field="points")
        out = p @ self.rotation.T
        out[:, : self.dims] *= self.scale
        return out + self.translation


def _umeyama(src: NDArray, dst: NDArray, with_scale: bool) -> tuple[NDArray, NDArray, float]:
    """Least-squares ``dst ~ s R src + t`` (Umeyama 1991, eq. 40-42), R a proper rotation."""
    n, k = src.shape
    mu_s, mu_d = src.mean(axis=0), dst.mean(axis=0)
    xs, xd = src - mu_s, dst - mu_d
    cov = xd.T @ xs / n
    u, d, vt = np.linalg.svd(cov)
    sign = np.ones(k)
    # Flip the weakest axis when U V' would be a reflection: the best *proper* rotation
    # (Umeyama eq. 39/43); Kabsch without this returns mirror images for mirrored input.
    if np.linalg.det(u) * np.linalg.det(vt) < 0:
        sign[-1] = -1.0
    rot = u @ np.diag(sign) @ vt
    if with_scale:
        var_s = float((xs**2).sum() / n)
        if var_s == 0.0:
            raise InvalidInputError("all points are identical; the scale is undefined", field="estimate")
        scale = float((d * sign).sum() / var_s)
    else:
        scale = 1.0
    trans = mu_d - scale * rot @ mu_s
    return rot, trans, scale


def rigid_align(
    estimate: ArrayLike, reference: ArrayLike, *, dims: int = 2, with_scale: bool = False
) -> RigidAlignment:
    """Least-squares rigid alignment of ``estimate`` onto ``reference`` (Umeyama / Kabsch).

    Finds the proper rotation R (det R = +1, never a reflection), translation t and, with
    ``with_scale``, scale s minimising ``sum_i || ref_i - (s R est_i + t) ||^2`` over the
    corresponding rows (Umeyama, IEEE TPAMI 13(4), 1991, eq. 40-42).

    * ``dims=2``: R is a rotation about z (heading), fitted on x, y only; t has no z component
      and z is left unchanged (the nav frame's z is up and gravity-defined, so only heading and
      horizontal offset are unobservable). s, if fitted, scales x, y only.
    * ``dims=3``: full 3-D rotation and translation (for references in an arbitrary frame).

    Parameters
    ----------
    estimate, reference
        Positions in m, (N, 3) or (N, 2) for ``dims=2``; row i of one corresponds to row i of the
        other (same time stamps).
    dims
        2 (heading + horizontal offset) or 3 (full rigid motion).
    with_scale
        Also fit a scale factor (similarity transform).

    Returns
    -------
    RigidAlignment
        ``aligned`` (estimate in the reference frame), ``rotation``, ``translation``, ``scale``;
        unpacks as ``aligned, R, t`` with ``aligned = est @ R.T * s + t`` (for ``dims=2`` the
        scale acts on x, y).

    Raises
    ------
    InvalidInputError
        Shapes differ, fewer than 2 rows, non-finite values.
    """
    dims = _check_dims(dims)
    est = _points(estimate, "estimate", dims, min_rows=2)
    ref = _points(reference, "reference", dims, min_rows=2)
    _same_length(est, ref, "estimate", "reference")
    rot_k, trans_k, scale = _umeyama(est[:, :dims], ref[:, :dims], with_scale)
    ncol = est.shape[1]
    rot = np.eye(ncol)
    rot[:dims, :dims] = rot_k
    trans = np.zeros(ncol)
    trans[:dims] = trans_k
    aligned = est @ rot.T
    aligned[:, :dims] *= scale
    aligned += trans
    return RigidAlignment(_readonly(aligned), _readonly(rot), _readonly(trans), scale, dims)


def align_at_start(estimate: ArrayLike, reference: ArrayLike, *, distance_m: float = 2.0) -> RigidAlignment:
    """The estimate moved to the reference's start and turned about z to its initial heading.

    The papers' end, return and deviation errors compare trajectories that share a known start
    and initial heading ([Zhao2019] Sec. V, [Chistyakov2021] Sec. 6, [Li2018] Table 2), not a best fit over the
    whole walk (which :func:`rigid_align` gives, and which hides drift). Here the start points
    coincide (3-D) and the heading is the rotation about the start that best maps the estimate's
    first ``distance_m`` of reference walking onto the reference (least squares, closed form).

    Parameters
    ----------
    estimate, reference
        Time-matched positions (N, 3) in m.
    distance_m
        How much of the start (reference distance travelled, m) sets the heading: about one
        stride; long enough to average a step's sway, short enough to precede most drift.

    Returns
    -------
    RigidAlignment
        As :func:`rigid_align` with ``dims=2``.
    """
    est = _points(estimate, "estimate", 3, min_rows=2)
    ref = _points(reference, "reference", 3, min_rows=2)
    _same_length(est, ref, "estimate", "reference")
    if not (np.isfinite(distance_m) and distance_m > 0):
        raise InvalidParameterError(f"distance_m must be > 0 m, got {distance_m!r}")
    s = np.concatenate(([0.0], np.cumsum(np.linalg.norm(np.diff(ref[:, :2], axis=0), axis=1))))
    k = max(2, int(np.searchsorted(s, distance_m, side="right")))
    a, b = est[:k, :2] - est[0, :2], ref[:k, :2] - ref[0, :2]
    yaw = float(np.arctan2(np.sum(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]), np.sum(a[:, 0] * b[:, 0] + a[:, 1] * b[:, 1])))
    c, sn = np.cos(yaw), np.sin(yaw)
    ncol = est.shape[1]
    rot = np.eye(ncol)
    rot[:2, :2] = [[c, -sn], [sn, c]]
    trans = ref[0] - rot @ est[0]
    aligned = est @ rot.T + trans
    return RigidAlignment(_readonly(aligned), _readonly(rot), _readonly(trans), 1.0, 2)


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
        errors_m=_readonly(e), index=_readonly(np.asarray(index, dtype=np.int64)), waypoint=_readonly(np.asarray(which, dtype=np.int64)),
        mean_m=float(e.mean()) if len(e) else float("nan"), max_m=float(e.max()) if len(e) else float("nan"),
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
    pos: ArrayLike,
    reference: ArrayLike | None = None,
    *,
    dims: int = 2,
    reference_distance_m: float | None = None,
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


# ---------------------------------------------------------------------------------------------
# dynamic time warping
# ---------------------------------------------------------------------------------------------
#: Result of :func:`dtw_distance`: ``distance_m``, ``total_cost``, ``n_pairs``, ``path``. The same
#: class as :class:`footnav.core.dtw.DtwAlignment`, so that the wrapper returns the kernel's result
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
    :func:`footnav.core.dtw.dtw_align`, which this wraps (first call compiles, cached).
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
    return np.stack([np.interp(tn, tt, p[:, k]) for k in range(p.shape[1])], axis=1)


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
    estimate: ArrayLike,
    reference: ArrayLike,
    *,
    dims: int = 2,
    min_distance_m: float = DEFAULT_RATIO_MIN_DISTANCE_M,
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


# ---------------------------------------------------------------------------------------------
# strides
# ---------------------------------------------------------------------------------------------
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


def footprint_errors(
    estimate: ArrayLike,
    footprints: ArrayLike,
    index: ArrayLike | None = None,
) -> FootprintErrors:
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
        :func:`footnav.core.io.read_gaitdriven` does).
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
                f"footprint index {idx[i]!r} is not a sample of the estimate (0..{len(est) - 1})", field="index", index=i
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


# ---------------------------------------------------------------------------------------------
# detection metrics
# ---------------------------------------------------------------------------------------------
class EventMatches(NamedTuple):
    """One-to-one matching of events (:func:`match_events`); a plain 3-tuple.

    Attributes
    ----------
    matches
        (K, 2) pairs ``[detected, reference]`` of event positions (samples), sorted by reference.
    missed
        Reference events without a detected partner (sorted).
    false
        Detected events without a reference partner (sorted).
    """

    matches: NDArray
    missed: NDArray
    false: NDArray


def match_events(detected: ArrayLike, reference: ArrayLike, *, tolerance: float) -> EventMatches:
    """Match detected to reference events one to one, within ``tolerance`` samples.

    A detected event d and a reference event r may match if ``|d - r| <= tolerance``. Among all
    one-to-one matchings the one with the most pairs is chosen, and among those the one with the
    smallest total ``sum |d - r|`` (linear sum assignment, ``scipy.optimize.linear_sum_assignment``,
    on each cluster of events that lie within ``tolerance`` of each other, so large inputs stay
    cheap). Each event is used at most once: a detected event never counts for two references.

    Parameters
    ----------
    detected, reference
        Event positions in samples (K,) and (L,), any order; either may be empty.
    tolerance
        Largest allowed ``|d - r|`` in samples (inclusive), >= 0.

    Returns
    -------
    EventMatches
        ``(matches, missed, false)``; found = ``len(matches)``.
    """
    det = _events(detected, "detected")
    ref = _events(reference, "reference")
    tol = float(tolerance)
    if not np.isfinite(tol) or tol < 0:
        raise InvalidParameterError(f"tolerance must be >= 0 samples, got {tolerance!r}")
    dtype = np.result_type(det.dtype, ref.dtype)
    det_s = np.sort(det).astype(dtype)
    ref_s = np.sort(ref).astype(dtype)
    nd, nr = len(det_s), len(ref_s)
    used_d = np.zeros(nd, bool)
    used_r = np.zeros(nr, bool)
    pairs: list[tuple[int, int]] = []
    if nd and nr:
        values = np.concatenate((det_s, ref_s)).astype(np.float64)
        is_ref = np.concatenate((np.zeros(nd, bool), np.ones(nr, bool)))
        idx = np.concatenate((np.arange(nd), np.arange(nr)))
        order = np.argsort(values, kind="stable")
        values, is_ref, idx = values[order], is_ref[order], idx[order]
        # No pair can span a gap wider than the tolerance, so clusters are independent problems.
        cuts = np.flatnonzero(np.diff(values) > tol) + 1
        for lo, hi in zip(np.concatenate(([0], cuts)), np.concatenate((cuts, [len(values)]))):
            r_in = is_ref[lo:hi]
            di, ri = idx[lo:hi][~r_in], idx[lo:hi][r_in]
            if len(di) == 0 or len(ri) == 0:
                continue
            if len(di) == 1 and len(ri) == 1:
                if abs(float(det_s[di[0]]) - float(ref_s[ri[0]])) <= tol:
                    pairs.append((int(di[0]), int(ri[0])))
                continue
            c = np.abs(det_s[di].astype(np.float64)[:, None] - ref_s[ri].astype(np.float64)[None, :])
            allowed = c <= tol
            # A forbidden pair costs more than any complete set of allowed pairs, so the assignment
            # first maximises the number of allowed pairs, then minimises their summed distance.
            big = (tol + 1.0) * (min(c.shape) + 1)
            rows, cols = linear_sum_assignment(np.where(allowed, c, big))
            for r_, c_ in zip(rows, cols):
                if allowed[r_, c_]:
                    pairs.append((int(di[r_]), int(ri[c_])))
    if pairs:
        pi = np.array(pairs, dtype=np.int64)
        pi = pi[np.argsort(pi[:, 1], kind="stable")]
        used_d[pi[:, 0]] = True
        used_r[pi[:, 1]] = True
        matches = np.stack((det_s[pi[:, 0]], ref_s[pi[:, 1]]), axis=1)
    else:
        matches = np.empty((0, 2), dtype=dtype)
    return EventMatches(_readonly(matches), _readonly(ref_s[~used_r]), _readonly(det_s[~used_d]))


@dataclass(frozen=True, eq=False)
class StepDetection:
    """Steps found / missed / false, [Li2018] Table 1.

    Attributes
    ----------
    n_detected
        Detected stance phases ("Steps Number").
    n_reference
        Reference stance phases.
    n_found
        Detected stances matched one to one to a reference stance.
    n_missed
        Reference stances without a match ("Missing Number").
    n_false
        Detected stances without a match (extra detections).
    missed_percent
        ``100 n_missed / n_reference`` (nan if no reference stance).
    false_percent
        ``100 n_false / n_reference``, [Li2018]'s "(rate in %)": 6 / 729 = 0.823 %.
    matches
        The :class:`EventMatches` of the stance anchors (samples).
    """

    n_detected: int
    n_reference: int
    n_found: int
    n_missed: int
    n_false: int
    missed_percent: float
    false_percent: float
    matches: EventMatches

    # Short names of the three counts ("steps found / missed / false").
    @property
    def found(self) -> int:
        """Same as ``n_found``."""
        return self.n_found

    @property
    def missed(self) -> int:
        """Same as ``n_missed``."""
        return self.n_missed

    @property
    def false(self) -> int:
        """Same as ``n_false``."""
        return self.n_false

    @property
    def precision(self) -> float:
        """``n_found / n_detected``: the fraction of detected stances that are real (nan if none)."""
        return self.n_found / self.n_detected if self.n_detected else float("nan")

    @property
    def recall(self) -> float:
        """``n_found / n_reference``: the fraction of reference stances found (nan if none)."""
        return self.n_found / self.n_reference if self.n_reference else float("nan")

    @property
    def f1(self) -> float:
        """Step F1 = ``2 n_found / (n_detected + n_reference)`` (nan if both are 0).

        The harmonic mean of precision and recall, one number that penalises missed and false
        steps alike.
        """
        den = self.n_detected + self.n_reference
        return 2.0 * self.n_found / den if den else float("nan")


def _step_detection(m: EventMatches) -> StepDetection:
    """The counts of one-to-one matches: detected = matched + false, reference = matched + missed."""
    n_ref = len(m.matches) + len(m.missed)
    return StepDetection(
        len(m.matches) + len(m.false),
        n_ref,
        len(m.matches),
        len(m.missed),
        len(m.false),
        _percent(len(m.missed), n_ref),
        _percent(len(m.false), n_ref),
        m,
    )


def _anchors(mask: NDArray[np.bool_], anchor: str) -> NDArray[np.float64]:
    iv = stance_intervals(mask)
    if anchor == "center":
        # midpoint of the first and last stance sample
        return (iv[:, 0] + iv[:, 1] - 1) / 2.0
    return iv[:, 0].astype(np.float64)


def step_detection(
    detected_mask: ArrayLike,
    reference_mask: ArrayLike,
    *,
    tolerance_samples: float,
    anchor: Literal["center", "onset"] = "center",
) -> StepDetection:
    """Steps found / missed / false by matching stance phases ([Li2018] Table 1).

    Each run of True in a mask is one stance phase (one step of that foot). A stance is represented
    by its ``anchor``: ``"center"`` (default, midpoint of its first and last sample -- robust to
    detectors that start or end stances early or late, which move one edge only) or ``"onset"``
    (first sample). Detected and reference anchors are matched one to one with
    :func:`match_events` within ``tolerance_samples``. [Li2018] Table 1 reports "Steps Number",
    "Missing Number" and "False Negative (rate in %)"; its numbers (735 detected for 729 true
    steps, 0 missing, 6 = 0.823 % of 729) show the last column counts *extra* detections relative
    to the reference count, which is ``n_false`` / ``false_percent`` here.

    Parameters
    ----------
    detected_mask, reference_mask
        Per-sample stance masks (N,), same N.
    tolerance_samples
        Largest anchor distance for a match, samples (e.g. a quarter of a gait cycle).
    anchor
        ``"center"`` or ``"onset"``.
    """
    det = _mask(detected_mask, "detected_mask")
    ref = _mask(reference_mask, "reference_mask")
    _same_length(ref, det, "reference_mask", "detected_mask")
    if anchor not in ("center", "onset"):
        raise InvalidParameterError(f"anchor must be 'center' or 'onset', got {anchor!r}")
    m = match_events(_anchors(det, anchor), _anchors(ref, anchor), tolerance=tolerance_samples)
    return _step_detection(m)


def step_detection_from_events(
    detected_mask: ArrayLike,
    reference_events: ArrayLike,
    *,
    tolerance_samples: float = 0.0,
) -> StepDetection:
    """Steps found / missed / false against one reference event per stance ([Li2018] Table 1).

    For references that mark each stance by one instant (mocap-derived mid-stance or foot-flat
    events) instead of a stance mask. A reference event is found when it lies inside a detected
    stance phase, widened by ``tolerance_samples`` on each side; each detected stance finds at most
    one event (one to one, :func:`match_events` on the nearest anchor inside the phase). Detected
    stances outside the span of the reference events (a standstill before the first labelled
    stride or after the last) are neither found nor false: the reference says nothing there.

    Parameters
    ----------
    detected_mask
        Per-sample stance mask (N,).
    reference_events
        Reference stance events as sample indices (K,).
    tolerance_samples
        Widening of each detected stance phase, samples.
    """
    det = _mask(detected_mask, "detected_mask")
    ref = np.sort(_events(reference_events, "reference_events").astype(np.float64))
    if tolerance_samples < 0:
        raise InvalidParameterError(f"tolerance_samples must be >= 0, got {tolerance_samples!r}")
    runs = stance_intervals(det)
    if len(ref):
        inside_span = (runs[:, 1] - 1 + tolerance_samples >= ref[0]) & (runs[:, 0] - tolerance_samples <= ref[-1])
        runs = runs[inside_span]
    # each stance phase takes the free reference event nearest its centre among those inside it;
    # phases are visited in time order, so a widened phase cannot take its neighbour's event twice
    pairs: list[tuple[int, int]] = []
    used_ref: set[int] = set()
    for j, (a, b) in enumerate(runs):
        hits = [i for i in np.flatnonzero((ref >= a - tolerance_samples) & (ref <= b - 1 + tolerance_samples)) if i not in used_ref]
        if hits:
            centre = 0.5 * (a + b - 1)
            r = int(min(hits, key=lambda i: abs(ref[i] - centre)))
            pairs.append((j, r))
            used_ref.add(r)
    used_det = {d for d, _ in pairs}
    matches = np.array([[0.5 * (runs[d, 0] + runs[d, 1] - 1), ref[r]] for d, r in pairs]).reshape(-1, 2)
    missed = np.array([ref[i] for i in range(len(ref)) if i not in used_ref])
    false = np.array([0.5 * (runs[j, 0] + runs[j, 1] - 1) for j in range(len(runs)) if j not in used_det])
    # every kept run is matched or false, every reference event matched or missed
    return _step_detection(EventMatches(matches, missed, false))


def _swing_pairs(value: ArrayLike, n: int) -> NDArray[np.int64]:
    arr = _float64(value, "swings")
    if arr.size == 0:
        return np.empty((0, 2), dtype=np.int64)
    if arr.ndim != 2 or arr.shape[1] != 2:
        raise InvalidInputError(f"expected (K, 2) [toe_off, heel_strike] sample indices, got {arr.shape}", field="swings")
    _finite(arr, "swings")
    bad = (arr != np.round(arr)).any(axis=1) | (arr < 0).any(axis=1) | (arr > n).any(axis=1) | (arr[:, 0] >= arr[:, 1])
    if bad.any():
        i = int(np.argmax(bad))
        raise InvalidInputError(
            f"swing {arr[i].tolist()} is not [toe_off, heel_strike] with 0 <= toe_off < heel_strike <= {n}",
            field="swings",
            index=i,
        )
    return arr.astype(np.int64)


def _match_inside(anchors: NDArray[np.float64], ref_runs: NDArray[np.int64], tol: float) -> EventMatches:
    """One-to-one matching of detected anchors to reference runs [a, b) that contain them (+- tol)."""
    centres = (ref_runs[:, 0] + ref_runs[:, 1] - 1) / 2.0 if len(ref_runs) else np.empty(0)
    pairs: list[tuple[int, int]] = []
    if len(anchors) and len(ref_runs):
        allowed = (anchors[:, None] >= ref_runs[None, :, 0] - tol) & (anchors[:, None] <= ref_runs[None, :, 1] - 1 + tol)
        cost = np.abs(anchors[:, None] - centres[None, :])
        # a forbidden pair costs more than any set of allowed ones: most pairs first, then closest
        big = (float(cost.max()) + 1.0) * (min(cost.shape) + 1)
        rows, cols = linear_sum_assignment(np.where(allowed, cost, big))
        pairs = [(int(r), int(c)) for r, c in zip(rows, cols) if allowed[r, c]]
    pairs.sort(key=lambda rc: rc[1])
    used_d = {r for r, _ in pairs}
    used_r = {c for _, c in pairs}
    matches = np.array([[anchors[r], centres[c]] for r, c in pairs], dtype=np.float64).reshape(-1, 2)
    missed = np.array([centres[j] for j in range(len(centres)) if j not in used_r], dtype=np.float64)
    false = np.array([anchors[i] for i in range(len(anchors)) if i not in used_d], dtype=np.float64)
    return EventMatches(_readonly(matches), _readonly(missed), _readonly(false))


def step_detection_from_swings(
    detected_mask: ArrayLike,
    swings: ArrayLike,
    boundaries: tuple[int, int] | ArrayLike,
    *,
    tolerance_samples: float,
    anchor: Literal["center", "onset"] = "center",
) -> StepDetection:
    """Steps found / missed / false against labelled swings inside trial boundaries ([IPOL], [Li2018]).

    For references that label each SWING of a foot (toe-off, heel strike) and only inside the
    trial's boundaries, as [IPOL] does (hand-checked; steps after the trial's end and the
    standing before its start are not labelled).

    * Swing k covers samples ``toe_off_k <= i < heel_strike_k``; the labelled span is
      ``start <= i < end`` (``boundaries``, half-open: [IPOL]'s end boundary is the last heel
      strike, so the span ends as the last swing ends).
    * Reference stance phases are the runs of labelled, non-swing samples: the gaps between
      consecutive swings (heel strike k to toe-off k + 1), and also the standing still before
      the foot's first swing and after its last swing, as far as they lie inside the span. The
      foot does stand there (the walk starts and ends standing), so those are stances; [IPOL]'s
      start boundary is a toe-off, so the foot that starts walking has no leading stance in the
      span while the other foot has a partial one (from the start boundary to its first toe-off).
    * Detected stances are clipped to the span: a detected stance outside it is neither found
      nor false; one that straddles a boundary counts by its inside part. An inside part of at
      most ``tolerance_samples`` samples that touches the span's edge is dropped: it is a
      detection ending (or starting) a few samples past a boundary that coincides with a
      labelled swing's edge, timing jitter within the tolerance, not a stance.
    * A detected stance (represented by its ``anchor``) is found when the anchor lies inside a
      reference stance widened by ``tolerance_samples`` on each side, one to one (a reference
      stance split in two by a detector finds one; the other is false). Inside, not near the
      reference's centre: the reference stance runs from heel strike to toe-off, the whole
      ground contact, while a zero-velocity detector finds its still middle, usually shifted
      toward heel-off (on IPOL trial 1-1, 10-15 samples from the reference centre). Among the
      admissible one-to-one pairings the one with most pairs, then the smallest summed distance
      of anchors to reference centres, is taken (linear sum assignment, as :func:`match_events`).

    Parameters
    ----------
    detected_mask
        Per-sample stance mask (N,) of the foot.
    swings
        (K, 2) labelled swings ``[toe_off, heel_strike]`` as sample indices of the same foot
        (``FootTruth.events["toe_off"]`` / ``["heel_strike"]``), in time order; swings outside
        the span are allowed (they only end reference stances).
    boundaries
        ``(start, end)`` sample indices of the labelled span, half-open
        (``FootTruth.meta["trial_boundaries"]`` of :func:`footnav.core.io.read_ipol`).
    tolerance_samples
        Widening of each reference stance, samples; also the longest boundary sliver dropped.
    anchor
        ``"center"`` (default) or ``"onset"`` of each (clipped) detected stance run.

    Returns
    -------
    StepDetection
        Counts inside the span; ``precision``, ``recall`` and ``f1`` as properties;
        ``matches`` holds ``[detected anchor, reference stance centre]`` pairs, the missed
        reference centres and the false detected anchors.
    """
    det = _mask(detected_mask, "detected_mask")
    n = len(det)
    sw = _swing_pairs(swings, n)
    b = _float64(boundaries, "boundaries").reshape(-1)
    if len(b) != 2 or not np.isfinite(b).all() or (b != np.round(b)).any() or not 0 <= b[0] < b[1] <= n:
        raise InvalidInputError(f"expected (start, end) sample indices with 0 <= start < end <= {n}, got {b.tolist()}", field="boundaries")
    start, end = int(b[0]), int(b[1])
    tol = float(tolerance_samples)
    if not np.isfinite(tol) or tol < 0:
        raise InvalidParameterError(f"tolerance_samples must be >= 0, got {tolerance_samples!r}")
    if anchor not in ("center", "onset"):
        raise InvalidParameterError(f"anchor must be 'center' or 'onset', got {anchor!r}")
    labelled = np.zeros(n, dtype=bool)
    labelled[start:end] = True
    ref = labelled.copy()
    for a, z in sw:
        ref[a:z] = False
    runs = stance_intervals(det)
    clipped = np.column_stack((np.maximum(runs[:, 0], start), np.minimum(runs[:, 1], end))) if len(runs) else runs
    keep = clipped[:, 1] > clipped[:, 0] if len(runs) else np.zeros(0, dtype=bool)
    # boundary slivers: clipped at an edge and no longer than the timing tolerance
    at_edge = (runs[:, 0] < start) | (runs[:, 1] > end) if len(runs) else keep
    keep &= ~(at_edge & (clipped[:, 1] - clipped[:, 0] <= tol))
    det_in = np.zeros(n, dtype=bool)
    for a, z in clipped[keep]:
        det_in[a:z] = True
    # runs of det_in are the kept runs: clipped runs of one mask never touch each other
    m = _match_inside(_anchors(det_in, anchor), stance_intervals(ref), tol)
    return _step_detection(m)


@dataclass(frozen=True)
class SampleScores:
    """Per-sample classification scores of a stance mask (stance = positive class).

    Precision, recall, F1 and accuracy are fractions in [0, 1]; nan where the denominator is 0.
    """

    precision: float
    recall: float
    f1: float
    accuracy: float
    n_true_positive: int
    n_false_positive: int
    n_false_negative: int
    n_true_negative: int


def sample_scores(detected_mask: ArrayLike, reference_mask: ArrayLike) -> SampleScores:
    """Per-sample precision, recall, F1 and accuracy of a stance mask against a reference mask.

    ``precision = TP / (TP + FP)``, ``recall = TP / (TP + FN)``,
    ``F1 = 2 TP / (2 TP + FP + FN)``, ``accuracy = (TP + TN) / N``, stance (True) being the
    positive class. Not in the seed papers (which count steps, :func:`step_detection`); the
    standard per-sample complement.

    Parameters
    ----------
    detected_mask, reference_mask
        Per-sample stance masks (N,), same N, bool or 0/1.
    """
    det = _mask(detected_mask, "detected_mask")
    ref = _mask(reference_mask, "reference_mask")
    _same_length(ref, det, "reference_mask", "detected_mask")
    tp = int(np.sum(det & ref))
    fp = int(np.sum(det & ~ref))
    fn = int(np.sum(~det & ref))
    tn = int(np.sum(~det & ~ref))

    def ratio(num: int, den: int) -> float:
        return num / den if den else float("nan")

    return SampleScores(
        precision=ratio(tp, tp + fp),
        recall=ratio(tp, tp + fn),
        f1=ratio(2 * tp, 2 * tp + fp + fn),
        accuracy=ratio(tp + tn, len(det)),
        n_true_positive=tp,
        n_false_positive=fp,
        n_false_negative=fn,
        n_true_negative=tn,
    )


@dataclass(frozen=True)
class TimingError:
    """Timing error of matched events, s.

    Attributes
    ----------
    mean_abs_error_s, std_abs_error_s, max_abs_error_s
        Mean, population standard deviation (ddof = 0) and maximum of ``|t_det - t_ref|``, s
        (nan when nothing matched).
    mean_error_s
        Mean signed ``t_det - t_ref`` (positive = detected late), s.
    n_matched, n_missed, n_false
        Event counts of the underlying :func:`match_events`.
    """

    mean_abs_error_s: float
    std_abs_error_s: float
    max_abs_error_s: float
    mean_error_s: float
    n_matched: int
    n_missed: int
    n_false: int


def event_timing_error(detected: ArrayLike, reference: ArrayLike, *, tolerance: float, rate_hz: float) -> TimingError:
    """Timing error in s of detected gait events against reference events.

    Events are matched one to one within ``tolerance`` samples (:func:`match_events`); for the K
    matched pairs ``e_k = (d_k - r_k) / rate_hz`` and the result gives mean, std and max of
    ``|e_k|`` and the mean of ``e_k``. Complements the counts of [Li2018] Table 1 (which gives no
    timing figure) for detectors that report gait events (heel strike, toe off, ...).

    Parameters
    ----------
    detected, reference
        Event positions in samples (K,), (L,).
    tolerance
        Matching tolerance in samples.
    rate_hz
        Sampling rate in Hz converting samples to s.
    """
    if not np.isfinite(rate_hz) or rate_hz <= 0:
        raise InvalidParameterError(f"rate_hz must be a positive rate in Hz, got {rate_hz!r}")
    m = match_events(detected, reference, tolerance=tolerance)
    nan = float("nan")
    if len(m.matches) == 0:
        return TimingError(nan, nan, nan, nan, 0, len(m.missed), len(m.false))
    e = (m.matches[:, 0].astype(np.float64) - m.matches[:, 1].astype(np.float64)) / float(rate_hz)
    ae = np.abs(e)
    return TimingError(
        float(ae.mean()), float(ae.std()), float(ae.max()), float(e.mean()), len(m.matches), len(m.missed), len(m.false)
    )
