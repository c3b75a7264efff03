"""DTW fusion: two feet aligned by dynamic time warping and tied at mid-swing (Chistyakov et al. (2021), Alg. 2).

Chistyakov et al. 2021, Sec. 4, for two IMUs:

1. Each foot alone (Alg. 1), and the initial heading mismatch of the two IMUs "by choosing the
   initial angles that minimise the DTW metric" between the two trajectories. The DTW is
   band-limited: "the maximum allowed difference between the indices of matched points".
2. The feet processed step by step, alternately; at the middle of each step of one foot
   (``n = k + step_len / 2``) its horizontal position is updated with the other foot's position
   (Alg. 2: ``H = [I_2x2 O_2x7]``): "when one foot rests and the other is in the middle of its
   step, the sensors' horizontal positions are a few centimetres apart".
3. RTS smoothing of both (as Alg. 1).
4. One averaged trajectory: the midpoints of the point pairs DTW matches ("timeless": the
   paired points may come from different times), or the midpoint on a common time grid ("timed").

footnav's reading. Both feet run in one joint filter, so the mid-swing measurement is the
*relative* horizontal position ``p_moving - p_standing = offset + noise`` (``H = [I -I]``): it
corrects both feet by their uncertainties instead of treating the standing foot as exact. The
heading search turns the right foot's start about z (coarse grid, then bounded refinement) on the
single-foot solutions decimated to ``dtw_rate_hz``. The DTW itself, the heading search and the
pairing are :mod:`footnav.nav.dtw`'s, :mod:`footnav.nav.dtw_heading`'s and
:mod:`footnav.nav.dtw_average`'s; this module only resamples the feet for them
(:func:`feet_heading_mismatch`, :func:`feet_timeless_average`).
"""

from __future__ import annotations

from typing import ClassVar, Literal

import numpy as np
from numpy.typing import NDArray

from footnav.core.component import FootEstimator, Fusion
from footnav.core.parameters import MAX_LENGTH_M, require, require_non_negative, require_positive
from footnav.core.types import FootTrajectory, FusionResult, ImuData, Path, StanceResult
from footnav.fusion.joint import LEFT, RIGHT, finish_joint, forward_only, fuse_on_common_span, start_filter, start_joint
from footnav.nav import dtw_average, dtw_heading
from footnav.nav import quaternion as quat
from footnav.nav.interpolation import interp_columns

__all__ = ["DtwFusion", "feet_heading_mismatch", "feet_timeless_average"]

PATHS = ("timeless", "timed")


def _resample(traj: FootTrajectory, t: NDArray[np.float64], dims: int) -> NDArray[np.float64]:
    """The first ``dims`` position columns (m) linearly interpolated to times ``t`` (s)."""
    return interp_columns(t, traj.t, traj.position[:, :dims])


def _decimate(traj: FootTrajectory, rate_hz: float) -> NDArray[np.float64]:
    """Horizontal positions (m) on a uniform grid at ``rate_hz`` over the foot's own time span."""
    return _resample(traj, np.arange(traj.t[0], traj.t[-1], 1.0 / rate_hz), 2)


def feet_heading_mismatch(
    a: NDArray[np.float64], b: NDArray[np.float64], band: int, grid: int = dtw_heading.DEFAULT_HEADING_GRID
) -> tuple[float, float]:
    """Rotation of ``b`` about its start (rad) minimising the banded DTW distance to ``a``.

    Chistyakov et al. (2021), Sec. 4 step 1, as :func:`footnav.nav.dtw_heading.heading_mismatch` with
    ``translation="start"``: each single-foot solution starts at its own origin, so both tracks
    are compared from their first points.

    Parameters
    ----------
    a, b
        Horizontal tracks (N, 2) and (M, 2) in m (nav frame), e.g. decimated to 10 Hz.
    band
        Largest index difference of matched samples, at least ``|N - M|``.
    grid
        Number of coarse angles (>= 4) before the bounded refinement.

    Returns
    -------
    tuple of float
        (angle of ``b`` about +z in rad in (-pi, pi], mean DTW distance after the turn in m).

    Raises
    ------
    InvalidInputError, InvalidParameterError
        As :func:`footnav.nav.dtw_heading.heading_mismatch` (bad tracks, ``band < |N - M|``, ``grid < 4``).
    """
    found = dtw_heading.heading_mismatch(a, b, band=band, translation="start", grid=grid)
    return found.angle_rad, found.distance_m


def feet_timeless_average(left: FootTrajectory, right: FootTrajectory, band_s: float, rate_hz: float) -> Path:
    """Midpoints of the point pairs of the banded DTW between the feet (Chistyakov et al. (2021), Sec. 4 step 4).

    Both feet are resampled to ``rate_hz`` over their common time span (the pairing then costs
    O(N x band) at that rate, and feet sampled at different rates pair correctly), then paired
    in 3-D by :func:`footnav.nav.dtw_average.timeless_average`. The time of each midpoint is the mean of
    its pair's times (non-decreasing along the path): the path is "timeless" in the paper's
    sense, paired points need not be simultaneous.

    Parameters
    ----------
    left, right
        The two feet's trajectories in the nav frame (m, s).
    band_s
        Largest time difference of matched points, s (at least one sample at ``rate_hz``).
    rate_hz
        Common resampling rate, Hz.

    Returns
    -------
    Path
        Midpoints (L, 3) in m at times (L,) in s; ``meta["dtw_distance_m"]`` is the mean DTW
        distance of the pairing in m.

    Raises
    ------
    InvalidInputError
        As :func:`footnav.nav.dtw_average.timeless_average`, e.g. field ``a`` empty when the feet's time
        spans share no sample at ``rate_hz``.
    """
    t = np.arange(max(left.t[0], right.t[0]), min(left.t[-1], right.t[-1]), 1.0 / rate_hz)
    band = max(1, int(round(band_s * rate_hz)))
    avg = dtw_average.timeless_average(_resample(left, t, 3), _resample(right, t, 3), band=band, t_a=t, t_b=t)
    assert avg.t is not None  # given t_a
    return Path(
        t=avg.t,
        position=avg.position,
        meta={"path": "DTW pairing (timeless)", "rate_hz": rate_hz, "dtw_distance_m": avg.distance_m},
    )


class DtwFusion(Fusion):
    """Two feet tied at every mid-swing, aligned and averaged by DTW (Chistyakov et al. (2021), Alg. 2).

    Parameters
    ----------
    midswing_std_m : float
        Standard deviation of the mid-swing relative horizontal position, m (the sensors pass
        within "a few centimetres" plus the step width).
    lateral_offset_m : float
        Expected horizontal distance of the swinging foot's sensor from the standing one at
        mid-swing, across the walking direction, m (0 as in the paper).
    band_s : float
        Largest time difference between matched points of the DTW, s (the paper's maximum
        index difference, here in seconds so that it does not depend on the rate).
    dtw_rate_hz : float
        Rate the single-foot tracks are resampled to for the heading search, Hz.
    initial_heading : {"dtw", "first-step"}
        Align the right foot's heading to the left by minimising the DTW distance (the paper),
        or by each foot's first step.
    heading_tracks : {"forward", "smoothed"}
        The single-foot tracks the DTW heading search compares: the forward filter alone, or
        each foot's Alg. 1 output (the estimator as configured: smoothed, and closed with its
        ``closed_loop``) as the paper does. On the simulator's rectangle (seeds 0-2) the two
        found headings within 0.004 rad of each other and the same end positions to 1 mm;
        "forward" saves a smoothing pass per foot.
    path : {"timeless", "timed"}
        The pedestrian path: midpoints of DTW-paired points (at ``dtw_rate_hz``), or midpoints
        at the left foot's times.
    step_width_m : float
        Lateral distance between the feet at the start, m.

    Examples
    --------
    >>> pipe = footnav.make_pipeline("glrt", "ekf", "dtw")  # doctest: +SKIP
    """

    name = "dtw"
    needs_two_feet: ClassVar[bool] = True
    needs_stepable_estimator: ClassVar[bool] = True

    def __init__(
        self,
        *,
        midswing_std_m: float = 0.15,
        lateral_offset_m: float = 0.0,
        band_s: float = 2.0,
        dtw_rate_hz: float = 10.0,
        initial_heading: Literal["dtw", "first-step"] = "dtw",
        heading_tracks: Literal["smoothed", "forward"] = "forward",
        path: Literal["timeless", "timed"] = "timeless",
        step_width_m: float = 0.2,
    ) -> None:
        self.midswing_std_m = midswing_std_m
        self.lateral_offset_m = lateral_offset_m
        self.band_s = band_s
        self.dtw_rate_hz = dtw_rate_hz
        self.initial_heading = initial_heading
        self.heading_tracks = heading_tracks
        self.path = path
        self.step_width_m = step_width_m

    def validate_params(self) -> None:
        """Check every parameter (:meth:`footnav.core.component.Component.validate_params`); raises
        InvalidParameterError."""
        # The DTW kernel holds (duration x dtw_rate_hz) x (2 band_s dtw_rate_hz + 1) int8
        # back-pointers: 50 Hz and 10 s keep a one-hour walk near 180 MB (at 1 MHz one minute
        # needed terabytes). Lengths overflow when squared.
        require_positive(self, "dtw_rate_hz", high=50.0)
        require_positive(self, "band_s", high=10.0)
        require_positive(self, "midswing_std_m", high=MAX_LENGTH_M)
        require_non_negative(self, "lateral_offset_m", "step_width_m", high=MAX_LENGTH_M)
        require(self.initial_heading in ("dtw", "first-step"), self, "initial_heading", "'dtw' or 'first-step'")
        require(self.path in PATHS, self, "path", " or ".join(map(repr, PATHS)))
        require(self.heading_tracks in ("smoothed", "forward"), self, "heading_tracks", "'smoothed' or 'forward'")

    def fuse(
        self,
        estimator: FootEstimator,
        left: ImuData,
        stance_left: StanceResult,
        right: ImuData | None = None,
        stance_right: StanceResult | None = None,
    ) -> FusionResult:
        """Both feet in one filter, tied at each mid-swing; smoothed; averaged.

        On the feet's common time span; outside it each foot alone
        (:func:`footnav.fusion.joint.fuse_on_common_span`).
        """
        return fuse_on_common_span(self, estimator, left, stance_left, right, stance_right, self._fuse_span)

    def _fuse_span(self, estimator, left, stance_left, right, stance_right) -> FusionResult:
        """:meth:`fuse` on feet that share their whole time span."""
        meta: dict = {"fusion": self.describe()}
        if self.initial_heading == "dtw":
            tracker = (
                estimator.clone(heading="first-step") if self.heading_tracks == "smoothed" else forward_only(estimator)
            )
            singles = [tracker.estimate(imu, st) for imu, st in ((left, stance_left), (right, stance_right))]
            a, b = (_decimate(s, self.dtw_rate_hz) for s in singles)
            band = max(int(round(self.band_s * self.dtw_rate_hz)), abs(len(a) - len(b)))
            angle, dist = feet_heading_mismatch(a, b, band)
            meta["heading_mismatch_rad"], meta["initial_dtw_distance_m"] = angle, dist
            yaws = [float(s.meta.get("heading_rotation_rad", 0.0)) for s in singles]
            yaws[RIGHT] += angle
            filt = start_filter(estimator, (left, right), (stance_left, stance_right), yaws, self.step_width_m)
        else:
            filt = start_joint(estimator, left, stance_left, right, stance_right, self.step_width_m)
        imus, stances = (left, right), (stance_left, stance_right)
        runs = [st.intervals for st in stances]
        events = []  # (mid-swing time, moving foot)
        for foot in (LEFT, RIGHT):
            r = runs[foot]
            for j in range(len(r) - 1):
                t_off, t_on = imus[foot].t[r[j, 1] - 1], imus[foot].t[r[j + 1, 0]]
                events.append((0.5 * (t_off + t_on), foot))
        events.sort()
        big = filt.covariance.shape[0]
        hs = []  # H = [I -I] on the horizontal positions, by moving foot
        for moving in (LEFT, RIGHT):
            h = np.zeros((2, big))
            h[:, filt.block(moving, "pos").start : filt.block(moving, "pos").start + 2] = np.eye(2)
            h[:, filt.block(1 - moving, "pos").start : filt.block(1 - moving, "pos").start + 2] = -np.eye(2)
            hs.append(h)
        applied = skipped = 0
        for t, moving in events:
            other = 1 - moving
            k = int(np.searchsorted(imus[other].t, t, side="right")) - 1
            if k < 0 or k >= len(stances[other].mask) or not stances[other].mask[k]:
                skipped += 1  # the other foot is not standing: no anchor (running, turning on the spot)
                continue
            filt.run_until(t)
            h = hs[moving]
            offset = np.zeros(2)
            if self.lateral_offset_m:
                # across the standing foot's heading, towards the moving foot's side
                yaw = quat.yaw_of(filt.quaternion(other))
                side = 1.0 if moving == LEFT else -1.0
                offset = side * self.lateral_offset_m * np.array([-np.sin(yaw), np.cos(yaw)])
            y = (filt.position(moving) - filt.position(other))[:2] - offset
            filt.update(h, y, self.midswing_std_m**2)
            applied += 1
        meta.update(midswing_updates=applied, skipped_other_foot_moving=skipped)
        result = finish_joint(estimator, filt, stance_left, stance_right, meta, imus)
        if self.path == "timeless":
            assert result.right is not None  # finish_joint returns both feet
            path = feet_timeless_average(result.left, result.right, self.band_s, self.dtw_rate_hz)
            result = FusionResult(
                left=result.left, right=result.right, path=path, meta={**result.meta, "path": path.meta}
            )
        return result
