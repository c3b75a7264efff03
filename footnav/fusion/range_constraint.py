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
from typing import Any, ClassVar, Literal

import numpy as np

from footnav.core.component import FootEstimator, Fusion
from footnav.core.parameters import MAX_DURATION_S, MAX_LENGTH_M, is_number, require, require_positive
from footnav.core.types import FusionResult, ImuData, StanceResult
from footnav.fusion.joint import LEFT, RIGHT, FeetView, closing_time, finish_joint, fuse_on_common_span, start_joint

__all__ = ["RangeConstraintFusion", "RangeSession"]

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
    >>> params = {"max_separation_m": 1.0}
    >>> pipe = footnav.make_pipeline("threshold", "ekf", "range", fusion_params=params)  # doctest: +SKIP
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
        """Check every parameter (:meth:`footnav.core.component.Component.validate_params`); raises
        InvalidParameterError."""
        # Upper bounds (footnav.core.component): lengths are squared into the update's
        # covariance; a check interval longer than a minute never checks a walk.
        require_positive(self, "max_separation_m", "constraint_std_m", high=MAX_LENGTH_M)
        require_positive(self, "check_interval_s", high=MAX_DURATION_S)
        v = self.step_width_m
        require(
            is_number(v) and 0 <= v < self.max_separation_m,
            self,
            "step_width_m",
            "a number >= 0 below max_separation_m",
        )
        require(self.projection in PROJECTIONS, self, "projection", " or ".join(map(repr, PROJECTIONS)))

    def fuse(
        self,
        estimator: FootEstimator,
        left: ImuData,
        stance_left: StanceResult,
        right: ImuData | None = None,
        stance_right: StanceResult | None = None,
    ) -> FusionResult:
        """Both feet in one filter; separations beyond the bound are projected back onto it.

        On the feet's common time span; outside it each foot alone
        (:func:`footnav.fusion.joint.fuse_on_common_span`).
        """
        return fuse_on_common_span(self, estimator, left, stance_left, right, stance_right, self._fuse_span)

    def session(self, estimator: Any, start_s: float) -> RangeSession:
        """The constraint's checks and projections, from the feet's common start ``start_s``
        (s), on a joint filter that grows as samples arrive (online mode;
        :class:`footnav.core.component.FusionSession`)."""
        self.validate_params()
        return RangeSession(self, start_s)  # (a closed loop needs the walk's end: offline only)

    def _fuse_span(self, estimator, left, stance_left, right, stance_right) -> FusionResult:
        """:meth:`fuse` on feet that share their whole time span: one session over the whole walk."""
        imus, stances = (left, right), (stance_left, stance_right)
        filt = start_joint(estimator, left, stance_left, right, stance_right, self.step_width_m)
        session = RangeSession(self, max(left.t[0], right.t[0]), closing_time(estimator, imus, stances))
        landings = [imu.t[stance.intervals[1:, 0]] for imu, stance in zip(imus, stances)]
        stop = min(left.t[-1], right.t[-1])
        session.advance(filt, stop, landings, FeetView.of(imus, stances), stop_s=stop)
        meta = session.finish()
        return finish_joint(estimator, filt, stance_left, stance_right, meta, imus)


class RangeSession:
    """The range constraint's work on one joint filter: checks every ``check_interval_s`` from
    the feet's common start and at every landing, each a projection when the feet are too far
    apart (:class:`RangeConstraintFusion`; :class:`footnav.core.component.FusionSession`).

    The check times are ``np.arange(start_s, stop_s, check_interval_s)``, made a block at a time
    with numpy's own arithmetic (the first two values, then ``start + i * delta``), so a walk whose
    end is not yet known gets the very times its offline run gets.

    Parameters
    ----------
    fusion
        The range fusion (its parameters).
    start_s
        The feet's common start, s.
    closing_s
        No check after this time, s (the estimator's closed loop takes over there).
    """

    #: The constraint reads no past sample.
    history_s = 0.0

    def __init__(self, fusion: RangeConstraintFusion, start_s: float, closing_s: float = math.inf) -> None:
        self.fusion = fusion
        self.step_width_m = float(fusion.step_width_m)
        self.closing_s = float(closing_s)
        self.applied = 0
        self.n_times = 0
        self._landings: list[float] = []  # known landings not yet checked, s
        self._i = 0  # the next check
        self._step = float(fusion.check_interval_s)
        self._t0 = float(start_s)
        self._delta = (self._t0 + self._step) - self._t0  # numpy's arange: start + i * (the second value - start)

    def _checks(self, a: int, b: int) -> np.ndarray:
        """Check times ``a:b`` as ``np.arange`` makes them: the start, the start plus the step,
        then ``start + i * delta`` (delta: the second value minus the start)."""
        i = np.arange(a, b)
        t = self._t0 + i * self._delta
        t[i == 0] = self._t0
        t[i == 1] = self._t0 + self._step
        return t

    def _times(self, until_s: float, stop_s: float | None) -> np.ndarray:
        """The check and landing times <= ``until_s`` not done yet (checks before ``stop_s``,
        as arange stops), sorted and unique, and at most ``closing_s``."""
        n_max = math.inf if stop_s is None else max(math.ceil((stop_s - self._t0) / self._step), 0)
        # every check <= until_s lies below this index (delta rounds the step by far less than one)
        reach = math.floor((until_s - self._t0) / self._delta) + 2 if until_s < math.inf else n_max
        b = int(min(n_max, max(reach, self._i)))
        checks = self._checks(self._i, b)
        checks = checks[: int(np.searchsorted(checks, until_s, side="right"))]
        self._i += len(checks)
        now = [t for t in self._landings if t <= until_s]
        self._landings = [t for t in self._landings if t > until_s]
        times = np.unique(np.concatenate([checks, np.array(now, dtype=float)]))
        return times[times <= self.closing_s]

    def known_until(self, view, final_s: float) -> float:
        """A check at a time needs nothing later: every final sample's time."""
        return final_s

    def advance(self, filt, until_s: float, landings, view, *, stop_s: float | None = None) -> None:
        """Check and project at every time <= ``until_s`` (s); ``landings``: each foot's newly
        known stance starts, s; ``view``: the feet's stance (:class:`footnav.fusion.joint.FeetView`);
        ``stop_s``: the feet's common end, once known."""
        for new in landings:
            self._landings.extend(float(t) for t in np.asarray(new, dtype=float).ravel())
        times = self._times(until_s, stop_s)
        self.n_times += len(times)
        fusion = self.fusion
        bound = float(fusion.max_separation_m)
        # footnav's filter checks and projects in its compiled loop, all but a distance that is
        # not a number (reported below); any other JointFilter here, to the same arithmetic
        inside = getattr(filt, "run_range_constrained", None)
        i = 0
        while i < len(times):
            if inside is not None:
                found, applied = inside(times, bound, fusion.constraint_std_m, fusion.projection == "symmetric", i)
                self.applied += applied
                if found is None:
                    break
                i = found
            else:
                filt.run_until(times[i])
            p = [filt.position(LEFT), filt.position(RIGHT)]
            d = p[LEFT] - p[RIGHT]
            dx, dy, dz = float(d[0]), float(d[1]), float(d[2])
            dist = math.sqrt(dx * dx + dy * dy + dz * dz)  # as InsFilter.run_range_constrained, to the bit
            if dist <= bound:  # (never after run_range_constrained stopped: not a number)
                i += 1
                continue
            u = d / dist
            feet_standing = [view.standing(f, filt.index(f)) for f in (LEFT, RIGHT)]
            if fusion.projection == "moving" and feet_standing[LEFT] != feet_standing[RIGHT]:
                anchor = LEFT if feet_standing[LEFT] else RIGHT
                mover = 1 - anchor
                sign = 1.0 if mover == LEFT else -1.0  # d points from right to left
                z = p[anchor] + sign * bound * u
                filt.update_position(mover, z, fusion.constraint_std_m)
            else:
                centre = 0.5 * (p[LEFT] + p[RIGHT])
                filt.update_position(LEFT, centre + 0.5 * bound * u, fusion.constraint_std_m)
                filt.update_position(RIGHT, centre - 0.5 * bound * u, fusion.constraint_std_m)
            self.applied += 1
            i += 1

    def finish(self) -> dict:
        """The fusion's meta, after the last :meth:`advance` (with ``stop_s``)."""
        return {"fusion": self.fusion.describe(), "constraint_updates": self.applied, "checks": self.n_times}
