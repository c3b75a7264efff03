"""The initial heading mismatch of two foot trajectories by DTW (Chistyakov et al. (2021), Sec. 4 step 1).

Chistyakov et al., Russian Technological J. 2021 (full citation in docs/references.md),
Section 4, step 1: the initial heading mismatch of the two IMUs, found "by choosing the initial
angles that minimise the DTW metric" (:func:`footnav.nav.dtw.dtw_align`): :func:`heading_mismatch`.

Frames and units: positions are in one navigation frame (x, y horizontal, z up), in m, samples
on axis 0. :func:`heading_mismatch` returns the rotation about z it found; it moves nothing
itself (:meth:`HeadingMismatch.apply` does).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from footnav.core.errors import InvalidParameterError
from footnav.nav.dtw import _band, _choice, _dtw_cost_kernel, _readonly, _trajectory, dtw_align
from footnav.nav.quaternion import wrap_angle

__all__ = ["HeadingMismatch", "heading_mismatch"]

#: Coarse grid of the heading search: 36 angles over the full turn, 10 deg apart.
DEFAULT_HEADING_GRID = 36
#: Angle tolerance of the bounded refinement of the heading search, rad (about 0.006 deg).
HEADING_XATOL_RAD = 1e-4

_TRANSLATION = ("none", "start")


# ---------------------------------------------------------------------------------------------
# initial heading mismatch (Chistyakov et al. (2021), Sec. 4 step 1)
# ---------------------------------------------------------------------------------------------
def _rotate_xy(xy: NDArray[np.float64], angle_rad: float) -> NDArray[np.float64]:
    # [x'; y'] = [cos -sin; sin cos] [x; y]: counter-clockwise about +z (z up)
    c, s = np.cos(angle_rad), np.sin(angle_rad)
    return np.ascontiguousarray(xy @ np.array([[c, s], [-s, c]]))


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
    (``tests/nav/test_dtw.py``); for one trajectory and a rotated copy of it, below 1e-3 rad.

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
    # The coarse grid needs only its smallest value exactly: an angle whose DTW is certain to
    # exceed the best so far stops early (left inf), which leaves argmin and min as they are.
    # The angles nearest 0 first: tracks already turned alike (e.g. each to its first step) find
    # the best early, and the others stop within their first rows.
    band_i = np.int64(_band(band, len(a_rel), len(b_rel)))
    costs = np.full(len(angles), np.inf)
    for i in np.argsort(np.abs(angles), kind="stable"):
        total, pairs = _dtw_cost_kernel(a_rel, _rotate_xy(b_rel, float(angles[i])), band_i, False, float(costs.min()))
        if pairs:
            costs[i] = float(total) / int(pairs)
    best = float(angles[int(np.argmin(costs))])
    step = 2.0 * np.pi / grid
    from scipy.optimize import minimize_scalar  # here: scipy.optimize is slow to import

    res = minimize_scalar(
        cost, bounds=(best - step, best + step), method="bounded", options={"xatol": HEADING_XATOL_RAD}
    )
    angle, dist = (float(res.x), float(res.fun)) if res.fun <= costs.min() else (best, float(costs.min()))
    return HeadingMismatch(wrap_angle(angle), dist, _readonly(pivot), _readonly(np.asarray(shift, dtype=np.float64)))
