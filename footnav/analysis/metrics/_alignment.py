"""Rigid alignment of an estimate onto a reference: the least-squares fit over the whole walk
(:func:`rigid_align`, Umeyama 1991) and the start-and-initial-heading alignment of the papers'
end and deviation errors (:func:`align_at_start`, :func:`align_on_first_steps`)."""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from footnav.analysis.metrics._checks import _check_dims, _points, _readonly, _same_length
from footnav.core.errors import InvalidInputError, InvalidParameterError


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


def _umeyama(
    src: NDArray, dst: NDArray, with_scale: bool, *, reflection: bool = False
) -> tuple[NDArray, NDArray, float]:
    """Least-squares ``dst ~ s R src + t`` (Umeyama 1991, eq. 40-42), R a proper rotation; with
    ``reflection``, R the best improper one (det R = -1: a rotation and a mirror), which the truth
    checks compare against the proper fit to tell a mirrored reference."""
    n, k = src.shape
    mu_s, mu_d = src.mean(axis=0), dst.mean(axis=0)
    xs, xd = src - mu_s, dst - mu_d
    cov = xd.T @ xs / n
    u, d, vt = np.linalg.svd(cov)
    sign = np.ones(k)
    # Flip the weakest axis when U V' would have the wrong determinant: the best *proper* rotation
    # (Umeyama eq. 39/43); Kabsch without this returns mirror images for mirrored input.
    if (np.linalg.det(u) * np.linalg.det(vt) < 0) != reflection:
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
    yaw = float(
        np.arctan2(np.sum(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]), np.sum(a[:, 0] * b[:, 0] + a[:, 1] * b[:, 1]))
    )
    c, sn = np.cos(yaw), np.sin(yaw)
    ncol = est.shape[1]
    rot = np.eye(ncol)
    rot[:2, :2] = [[c, -sn], [sn, c]]
    trans = ref[0] - rot @ est[0]
    aligned = est @ rot.T + trans
    return RigidAlignment(_readonly(aligned), _readonly(rot), _readonly(trans), 1.0, 2)


def align_on_first_steps(
    estimate: ArrayLike, reference: ArrayLike, landings: ArrayLike, *, steps: int = 5
) -> RigidAlignment:
    """:func:`align_at_start` with the heading set by the foot's first ``steps`` steps (Lee, Cho
    & Park (2022), Sec. 2.1: "the shoe's initial direction and the walking direction were
    matched using the estimated position during the initial five steps").

    Parameters
    ----------
    estimate, reference
        Time-matched positions (N, 3) in m.
    landings
        Sample indices (into both) of the foot's landings (heel strikes), ascending; the span
        ends at the ``steps``-th (or the last, if fewer).
    steps
        How many steps set the heading (the paper: 5).
    """
    ref = _points(reference, "reference", 3, min_rows=2)
    idx = np.asarray(landings, dtype=np.int64).ravel()
    idx = idx[(idx > 0) & (idx < len(ref))]
    if not (isinstance(steps, (int, np.integer)) and steps >= 1):
        raise InvalidParameterError(f"steps must be an integer >= 1, got {steps!r}")
    if len(idx) == 0:
        raise InvalidInputError("landings: no landing inside the walk")
    k = int(idx[min(steps, len(idx)) - 1])
    walked = float(np.sum(np.linalg.norm(np.diff(ref[: k + 1, :2], axis=0), axis=1)))
    # the span that sets the heading ends at the landing (the next sample's distance is past it)
    return align_at_start(estimate, ref, distance_m=max(walked, 1e-9))
