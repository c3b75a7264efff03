"""Range constraint: the feet cannot be further apart than a bound (the baseline Lee et al. (2022) compares with).

Prateek et al. (2013, Lee et al. (2022)'s reference) and the methods Zhao et al. (2019) reviews ([14]-[16]) limit the
distance between the feet to a sphere of radius ``max_separation_m`` (1 m in [15], [16]). Here the
constraint is checked every ``check_interval_s`` and at every landing; when the feet are further
apart than the bound, the estimate is projected onto it and the projection applied as a position
measurement to the joint filter:

* ``projection="moving"`` (sphere limit): the standing foot is the centre; the moving foot is
  moved onto the sphere around it. With both feet moving or both standing, both are moved.
* ``projection="symmetric"``: both feet move symmetrically about their centroid.
"""

from __future__ import annotations

import math
from typing import ClassVar, Literal

import numpy as np

from footnav.component import MAX_DURATION_S, MAX_LENGTH_M, Fusion, is_number, require, require_positive
from footnav.types import FusionResult
from footnav.fusion.joint import LEFT, RIGHT, closing_time, finish_joint, fuse_on_common_span, start_joint

__all__ = ["RangeConstraintFusion"]

PROJECTIONS = ("moving", "symmetric")


class RangeConstraintFusion(Fusion):
    """Feet at most ``max_separation_m`` apart, enforced as position measurements.

    Parameters
    ----------
    max_separation_m : float
        Largest distance between the two feet's sensors, m (1 m in Zhao et al. (2019)'s refs. [15], [16]).
    projection : {"moving", "symmetric"}
        Move the moving foot onto the sphere around the standing one, or both feet about their
        centroid.
    check_interval_s : float
        How often the constraint is checked between landings, s.
    constraint_std_m : float
        Standard deviation of the projected position used as a measurement, m.
    step_width_m : float
        Lateral distance between the feet at the start, m (sets the initial positions).

    Examples
    --------
    >>> pipe = footnav.make_pipeline("threshold", "ekf", "range", fusion_params={"max_separation_m": 1.0})  # doctest: +SKIP
    """

    name = "range"
    needs_two_feet: ClassVar[bool] = True
    needs_stepable_estimator: ClassVar[bool] = True

    def __init__(
        self,
        *,
        max_separation_m: float = 1.0,
        projection: Literal["moving", "symmetric"] = "moving",
        check_interval_s: float = 0.05,
        constraint_std_m: float = 0.01,
        step_width_m: float = 0.2,
    ) -> None:
        self.max_separation_m = max_separation_m
        self.projection = projection
        self.check_interval_s = check_interval_s
        self.constraint_std_m = constraint_std_m
        self.step_width_m = step_width_m

    def validate_params(self) -> None:
        # Upper bounds (footnav.component): lengths are squared into the update's
        # covariance; a check interval longer than a minute never checks a walk.
        require_positive(self, "max_separation_m", "constraint_std_m", high=MAX_LENGTH_M)
        require_positive(self, "check_interval_s", high=MAX_DURATION_S)
        v = self.step_width_m
        require(is_number(v) and 0 <= v < self.max_separation_m, self, "step_width_m", "a number >= 0 below max_separation_m")
        require(self.projection in PROJECTIONS, self, "projection", " or ".join(map(repr, PROJECTIONS)))

    def fuse(self, estimator, left, stance_left, right=None, stance_right=None) -> FusionResult:
        """Both feet in one filter; separations beyond the bound are projected back onto it.

        On the feet's common time span; outside it each foot alone
        (:func:`footnav.fusion.joint.fuse_on_common_span`).
        """
        return fuse_on_common_span(self, estimator, left, stance_left, right, stance_right, self._fuse_span)

    def _fuse_span(self, estimator, left, stance_left, right, stance_right) -> FusionResult:
        """:meth:`fuse` on feet that share their whole time span."""
        imus, stances = (left, right), (stance_left, stance_right)
        filt = start_joint(estimator, left, stance_left, right, stance_right, self.step_width_m)
        t0, t1 = max(left.t[0], right.t[0]), min(left.t[-1], right.t[-1])
        checks = np.arange(t0, t1, self.check_interval_s)
        landings = [imu.t[stance.intervals[1:, 0]] for imu, stance in zip(imus, stances)]
        times = np.unique(np.concatenate([checks, *landings]))
        times = times[times <= closing_time(estimator, imus, stances)]
        bound = float(self.max_separation_m)
        applied = 0
        # footnav's filter checks the times in its compiled loop; any other JointFilter here
        watch = getattr(filt, "run_until_apart", None)
        i = 0
        while i < len(times):
            if watch is not None:
                found = watch(times, bound, i)
                if found is None:
                    break
                i = found
            else:
                filt.run_until(times[i])
            p = [filt.position(LEFT), filt.position(RIGHT)]
            d = p[LEFT] - p[RIGHT]
            dx, dy, dz = float(d[0]), float(d[1]), float(d[2])
            dist = math.sqrt(dx * dx + dy * dy + dz * dz)  # as InsFilter.run_until_apart, to the bit
            if dist <= bound:  # (never after run_until_apart's stop)
                i += 1
                continue
            u = d / dist
            standing = [bool(st.mask[min(filt.index(f), len(st.mask) - 1)]) for f, st in enumerate(stances)]
            if self.projection == "moving" and standing[LEFT] != standing[RIGHT]:
                anchor = LEFT if standing[LEFT] else RIGHT
                mover = 1 - anchor
                sign = 1.0 if mover == LEFT else -1.0  # d points from right to left
                z = p[anchor] + sign * bound * u
                filt.update_position(mover, z, self.constraint_std_m)
            else:
                centre = 0.5 * (p[LEFT] + p[RIGHT])
                filt.update_position(LEFT, centre + 0.5 * bound * u, self.constraint_std_m)
                filt.update_position(RIGHT, centre - 0.5 * bound * u, self.constraint_std_m)
            applied += 1
            i += 1
        meta = {"fusion": self.describe(), "constraint_updates": applied, "checks": len(times)}
        return finish_joint(estimator, filt, stance_left, stance_right, meta, imus)
