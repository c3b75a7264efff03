"""Step-vector fusion: the relative position of the feet at each step (seed 001, Zhao et al. 2019).

At each step the front foot lands while the rear foot supports the body. The inverted-pendulum
model (seed 001 Sec. III-B) gives the step length from the supporting foot's attitude change
between its heel strike and the front foot's heel strike::

    q = q1 (x) q2*,   theta = 2 acos(q[1])      (eq. 5)
    S = 2 l sin(theta / 2)                      (eq. 6)

The relative position of the front foot in the rear foot's heading frame is
``[S, +-step_width, step_elevation]`` (+ when the front foot is the left one), rotated into the nav
frame by the rear foot's walking heading. Both feet share one error-state filter (one time
update, two measurement updates: ZUPT per foot and this relative position, eq. 7)::

    z = (p^_front - p^_rear) - dp^n,   H = [0 0 I]_front - [0 0 I]_rear

Updates are suspended while turning (Sec. V-C: a heading threshold tells sway from turning).

footnav's additions. (1) The leg length ``l`` is fitted to the walk when not given: theta comes
from the foot's attitude, whose swing is smaller than the leg's, so ``l`` = leg length
underestimates S (simulator: 0.31 m for 0.70 m steps); ``leg_length_m=None`` takes the median of
(half the foot's stride) / (2 sin(theta/2)) over the non-turning steps of the single-foot
solutions. (2) The heading of the rear foot is its sensor's yaw minus the yaw it had at the first
step, so a sensor mounted askew on the shoe does not turn the step vector.
"""

from __future__ import annotations

from typing import ClassVar

import numpy as np

from footnav.core import quaternion as quat
from footnav.core.component import (
    MAX_DURATION_S,
    MAX_LENGTH_M,
    Fusion,
    is_number,
    require,
    require_in_range,
    require_non_negative,
    require_positive,
)
from footnav.core.errors import CompositionError
from footnav.core.types import FusionResult, ImuData, StanceResult
from footnav.fusion.joint import LEFT, RIGHT, finish_joint, fuse_on_common_span, start_joint

__all__ = ["StepVectorFusion", "pendulum_step_length"]


def pendulum_step_length(q1: np.ndarray, q2: np.ndarray, leg_length_m: float) -> float:
    """Seed 001 eq. 5-6: S = 2 l sin(theta/2) with theta the rotation from q1 to q2 (m)."""
    q = quat.multiply(q1, quat.conjugate(q2))
    theta = 2.0 * np.arccos(np.clip(abs(float(q[0])), 0.0, 1.0))
    return 2.0 * leg_length_m * np.sin(0.5 * theta)


def _wrap(angle: float) -> float:
    return float((angle + np.pi) % (2 * np.pi) - np.pi)


class StepVectorFusion(Fusion):
    """Relative position of the feet at every step in one joint filter (seed 001 eq. 5-7).

    Parameters
    ----------
    leg_length_m : float or None
        Pendulum length l of eq. 6, m; None fits it to the walk (module docstring).
    step_width_m : float
        Lateral distance between the feet's sensors, m (seed 001 takes the shoulder width; the
        simulator's default walker has 0.2 m).
    step_elevation_m : float
        Height of the front foot over the rear one, m (0 on level ground).
    step_length_std_m : float
        Standard deviation of the step length measurement, m.
    step_width_std_m : float
        Standard deviation of the lateral component, m.
    step_elevation_std_m : float
        Standard deviation of the vertical component, m.
    turn_threshold_deg : float
        Suspend the update when the rear foot's heading changed more than this since its
        previous step, deg (seed 001 Sec. V-C).
    heel_strike_before_stance_s : float
        Where the detector gives no heel strikes, the heel strike is taken this long before the
        stance starts, s.

    Examples
    --------
    >>> pipe = footnav.make_pipeline("dual-gait", "ekf", "step-vector")  # doctest: +SKIP
    """

    name = "step-vector"
    needs_two_feet: ClassVar[bool] = True
    needs_stepable_estimator: ClassVar[bool] = True

    def __init__(
        self,
        *,
        leg_length_m: float | None = None,
        step_width_m: float = 0.2,
        step_elevation_m: float = 0.0,
        step_length_std_m: float = 0.05,
        step_width_std_m: float = 0.05,
        step_elevation_std_m: float = 0.02,
        turn_threshold_deg: float = 10.0,
        heel_strike_before_stance_s: float = 0.1,
    ) -> None:
        self.leg_length_m = leg_length_m
        self.step_width_m = step_width_m
        self.step_elevation_m = step_elevation_m
        self.step_length_std_m = step_length_std_m
        self.step_width_std_m = step_width_std_m
        self.step_elevation_std_m = step_elevation_std_m
        self.turn_threshold_deg = turn_threshold_deg
        self.heel_strike_before_stance_s = heel_strike_before_stance_s

    def validate_params(self) -> None:
        # Upper bounds (footnav.core.component): lengths and their stds are squared into the
        # step update's covariance (overflow at 1e308); a turn threshold above a full turn
        # never fires.
        require(
            self.leg_length_m is None or (is_number(self.leg_length_m) and 0 < self.leg_length_m <= MAX_LENGTH_M),
            self,
            "leg_length_m",
            f"None (fit to the walk) or a number in (0, {MAX_LENGTH_M:g}] m",
        )
        require_positive(self, "step_length_std_m", "step_width_std_m", "step_elevation_std_m", high=MAX_LENGTH_M)
        require_positive(self, "turn_threshold_deg", high=360.0)
        require_non_negative(self, "step_width_m", high=MAX_LENGTH_M)
        require_non_negative(self, "heel_strike_before_stance_s", high=MAX_DURATION_S)
        require_in_range(self, "step_elevation_m", low=-MAX_LENGTH_M, high=MAX_LENGTH_M)

    # -- the steps ------------------------------------------------------------------------------
    def _heel_strike(self, imu: ImuData, stance: StanceResult, start: int) -> int:
        """Heel strike that opened the stance run starting at ``start`` (sample index)."""
        hs = np.asarray(stance.events.get("heel_strike", []), dtype=np.int64)
        window = int(round(0.5 * imu.rate_hz))
        earlier = hs[(hs <= start) & (hs >= start - window)]
        if len(earlier):
            return int(earlier[-1])
        return max(0, start - int(round(self.heel_strike_before_stance_s * imu.rate_hz)))

    def _landings(self, imus, stances) -> list[tuple[float, int, int, int]]:
        """(time of the heel strike, front foot, its sample, stance-run index) of every landing
        after the first stance of each foot, in time order: the step ends at the front foot's heel
        strike, both feet on the ground."""
        out = []
        for foot, (imu, stance) in enumerate(zip(imus, stances)):
            runs = stance.intervals
            for j in range(1, len(runs)):
                hs = self._heel_strike(imu, stance, int(runs[j, 0]))
                out.append((float(imu.t[hs]), foot, hs, j))
        out.sort()
        return out

    def _support(self, imu_r: ImuData, stance_r: StanceResult, t: float, runs: np.ndarray) -> tuple[int, int] | None:
        """(heel strike, sample at time t) of the rear foot if it supported the step ending at t
        (its last stance ended at most ``heel_strike_before_stance_s`` + 0.1 s before t);
        ``runs`` its stance intervals."""
        k = int(np.searchsorted(imu_r.t, t, side="right")) - 1
        j = int(np.searchsorted(runs[:, 0], k, side="right")) - 1
        if k < 0 or j < 0 or imu_r.t[runs[j, 1] - 1] < t - self.heel_strike_before_stance_s - 0.1:
            return None
        hs = self._heel_strike(imu_r, stance_r, int(runs[j, 0]))
        return hs, max(hs, k)

    def _fit_leg_length(self, imus, stances, singles) -> float:
        """Median of (half the front foot's stride) / (2 sin(theta/2)) over the straight steps,
        theta measured exactly as :meth:`fuse` does (module docstring)."""
        ratios = []
        turn = np.radians(self.turn_threshold_deg)
        runs = [st.intervals for st in stances]
        for t, front, hs_front, j in self._landings(imus, stances):
            rear = 1 - front
            support = self._support(imus[rear], stances[rear], t, runs[rear])
            if support is None:
                continue
            runs_f, traj_f = runs[front], singles[front]
            a0, a1 = runs_f[j - 1, 0], runs_f[j, 0]
            stride = np.linalg.norm(traj_f.position[a1, :2] - traj_f.position[a0, :2])
            if stride < 0.2 or abs(_wrap(quat.yaw(traj_f.quaternion[a1]) - quat.yaw(traj_f.quaternion[a0]))) > turn:
                continue
            q_r = singles[rear].quaternion
            s1 = pendulum_step_length(q_r[support[0]], q_r[support[1]], 1.0)
            if s1 > 1e-3:
                ratios.append(0.5 * stride / s1)
        if not ratios:
            raise CompositionError(
                f"fusion {self.name!r}: no straight steps to fit the leg length to; give leg_length_m"
            )
        return float(np.median(ratios))

    # -- the fusion -----------------------------------------------------------------------------
    def fuse(self, estimator, left, stance_left, right=None, stance_right=None) -> FusionResult:
        """Both feet in one filter with a relative-position update at every straight step.

        On the feet's common time span; outside it each foot alone
        (:func:`footnav.fusion.joint.fuse_on_common_span`).
        """
        return fuse_on_common_span(self, estimator, left, stance_left, right, stance_right, self._fuse_span)

    def _fuse_span(self, estimator, left, stance_left, right, stance_right) -> FusionResult:
        """:meth:`fuse` on feet that share their whole time span."""
        imus, stances = (left, right), (stance_left, stance_right)
        filt, singles = start_joint(estimator, left, stance_left, right, stance_right, self.step_width_m, return_singles=True)
        leg = self.leg_length_m if self.leg_length_m is not None else self._fit_leg_length(imus, stances, singles)
        # the yaw each sensor has when its foot faces the walking direction (+x at the start)
        yaw0 = [float(quat.yaw(filt.quaternion(f))) for f in (LEFT, RIGHT)]
        big = filt.covariance.shape[0]
        turn = np.radians(self.turn_threshold_deg)
        r = np.array([self.step_length_std_m, self.step_width_std_m, self.step_elevation_std_m]) ** 2
        last_stance_yaw: dict[int, float] = {}
        runs = [st.intervals for st in stances]
        applied = suspended = skipped = 0
        lengths = []
        for t, front, _, _ in self._landings(imus, stances):
            rear = 1 - front
            filt.run_until(t)
            support = self._support(imus[rear], stances[rear], t, runs[rear])
            if support is None:
                skipped += 1  # the rear foot was not on the ground: no pendulum to read
                continue
            hs_rear, k_q2 = support
            q_out = filt.outputs(rear)[0]
            yaw_r = float(quat.yaw(q_out[hs_rear])) - yaw0[rear]
            prev = last_stance_yaw.get(rear)
            last_stance_yaw[rear] = yaw_r  # heading of the rear foot's footprint
            if prev is not None and abs(_wrap(yaw_r - prev)) > turn:
                suspended += 1
                continue
            s = pendulum_step_length(q_out[hs_rear], q_out[k_q2], leg)
            lengths.append(s)
            side = 1.0 if front == LEFT else -1.0
            c, sn = np.cos(yaw_r), np.sin(yaw_r)
            rot = np.array([[c, -sn, 0.0], [sn, c, 0.0], [0.0, 0.0, 1.0]])  # rear-heading frame -> nav
            dp_n = rot @ np.array([s, side * self.step_width_m, self.step_elevation_m])
            h = np.zeros((3, big))
            h[:, filt.block(front, "pos")] = np.eye(3)
            h[:, filt.block(rear, "pos")] = -np.eye(3)
            y = (filt.position(front) - filt.position(rear)) - dp_n
            # in the rear foot's heading frame the three components are independent
            filt.update(rot.T @ h, rot.T @ y, r)
            applied += 1
        meta = {
            "fusion": self.describe(),
            "leg_length_m": leg,
            "updates": applied,
            "suspended_turning": suspended,
            "skipped_rear_foot_moving": skipped,
            "step_length_m": {"median": float(np.median(lengths)) if lengths else None, "n": len(lengths)},
        }
        return finish_joint(estimator, filt, stance_left, stance_right, meta)
