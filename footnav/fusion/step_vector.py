"""Step-vector fusion: the relative position of the feet at every step, Zhao et al. (2019).

At each step the front foot lands while the rear foot supports the body. The inverted-pendulum
model (Zhao et al. (2019), Sec. III-B) gives the step length from the supporting foot's attitude
change between its own heel strike (q1) and the front foot's heel strike (q2)::

    q = q1 (x) q2*,   theta = 2 acos(q[1])      (eq. 5)
    S = 2 l sin(theta / 2)                      (eq. 6)

``l`` is "the pendulum length approximated by user's leg length" (eq. 6). The relative position
``dp^b = [S, +-step_width, step_elevation]`` (+ when the front foot is the left one) "is derived in
the b-frame that determined by the rear foot. To perform the position updates in n-frame, a
rotation must be applied" (Sec. IV-B): ``dp^n = C_b^n(rear) dp^b``. Both feet share one
error-state filter with one time update and two measurement updates (ZUPT per foot, eq. 3, and
this relative position, eq. 7)::

    z = (p^_front - p^_rear) - dp^n,   H = [0 0 I]_front - [0 0 I]_rear

The update is suspended while turning (Sec. V-C: "a simple heading threshold").

What the paper fixes and what footnav lets you choose (parameters of :class:`StepVectorFusion`;
``step_length="pendulum", relative_frame="attitude", calibration="standstill"`` is the paper as
published; the defaults are what measured better on the shared recordings, azure_fgo and gaitmap,
and stays right with a sensor mounted askew on the shoe):

``step_length``
    ``"pendulum"`` (the paper): eq. 6 with ``l = leg_length_m``. ``"fitted"`` (default):
    ``l`` fitted to the walk as the median of (half the front foot's
    stride) / (2 sin(theta/2)) over the straight steps of the feet's single-foot solutions; it
    absorbs that the *foot* turns less than the *leg* between the two heel strikes (the foot lies
    flat through mid-stance), which makes eq. 6 with the true leg length short. On the simulator,
    whose rear foot is still flat at the contralateral heel strike, theta is exactly the
    heel-strike pitch (20 deg) and eq. 6 with l = 0.9 m gives 0.313 m for 0.70 m steps;
    ``"fitted"`` gives 0.70 m (the class docstring has the figures).
``relative_frame``
    ``"attitude"`` (the paper): ``dp^n = C_b^n dp^b`` with the rear sensor's full
    attitude at the update. ``"heading"`` (default): rotated about z by the
    rear foot's footprint heading (its yaw at its heel strike) minus the yaw its sensor had at the
    first step, so neither the rear foot's pitch in heel-off nor a sensor mounted askew on the
    shoe turns the step vector.
``calibration``
    ``"standstill"``: the accelerometer scale of Sec. II-A
    (:func:`footnav.nav.calibration.calibrate_at_rest`) from each foot's first stance, applied
    before the fusion; the gyro bias of Sec. II-A is the estimator's (``ekf``'s
    ``gyro_bias="initial-standstill"``). ``"none"`` (default): the data as given.

References
----------
.. [1] H. Zhao, Z. Wang, S. Qiu, Y. Shen, L. Zhang, K. Tang and G. Fortino, "Heading drift
   reduction for foot-mounted inertial navigation system via multi-sensor fusion and dual-gait
   analysis", IEEE Sensors J., 2019, doi:10.1109/JSEN.2018.2866802.
.. [2] D. A. Winter, "Biomechanics and Motor Control of Human Movement", 4th ed., Wiley, 2009,
   Fig. 4.1 (segment lengths as fractions of body height H, after Drillis and Contini 1966).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any, ClassVar

import numpy as np

from footnav.core.component import FootEstimator, Fusion
from footnav.core.errors import CompositionError, DataQualityWarning, InvalidInputError
from footnav.core.parameters import (
    MAX_DURATION_S,
    MAX_LENGTH_M,
    require,
    require_in_range,
    require_non_negative,
    require_positive,
)
from footnav.core.types import FootTrajectory, FusionResult, ImuData, StanceResult
from footnav.core.warning_log import warn
from footnav.fusion.joint import (
    LEFT,
    RIGHT,
    EventQueue,
    FeetView,
    check_two_feet,
    closing_time,
    finish_joint,
    fuse_on_common_span,
    start_joint,
)
from footnav.fusion.pendulum import (
    LEG_LENGTH_PER_HEIGHT,
    LegLengthFit,
    leg_length_from_height,
    leg_ratio,
    pendulum_step_length,
)
from footnav.nav import quaternion as quat
from footnav.nav.calibration import StandstillCalibration, calibrate_at_rest

__all__ = [
    "LEG_LENGTH_PER_HEIGHT",
    "StepVectorFusion",
    "StepVectorSession",
    "leg_length_from_height",
    "pendulum_step_length",
]
# (the pendulum model and the fitted leg length live in footnav.fusion.pendulum)

#: Shortest first stance ``calibration="standstill"`` calibrates on, s (Zhao et al. (2019) kept the
#: sensors still for about 8 s).
MIN_STANDSTILL_S = 1.0

STEP_LENGTHS = ("pendulum", "fitted")
RELATIVE_FRAMES = ("attitude", "heading")
CALIBRATIONS = ("none", "standstill")


class StepVectorFusion(Fusion):
    """Relative position of the feet at every step in one joint filter, Zhao et al. (2019), eq. 4-7.

    Parameters
    ----------
    step_length : str
        ``"pendulum"``: eq. 6 with ``l = leg_length_m`` (the paper). ``"fitted"`` (default): ``l``
        fitted to the walk's own strides; ``leg_length_m`` is then unused (module docstring).
    leg_length_m : float
        Pendulum length l of eq. 6, m: the walker's leg length. The default 0.9 m is
        ``leg_length_from_height(1.70)`` (0.530 x body height, Winter 2009).
    relative_frame : str
        ``"attitude"``: the step vector is rotated into the nav frame by the rear foot's full
        attitude at the update (Sec. IV-B). ``"heading"`` (default): by the rear foot's footprint
        heading relative to its sensor's yaw at the first step.
    calibration : str
        ``"standstill"``: accelerometer scale from each foot's first stance (Sec. II-A), which
        must last ``MIN_STANDSTILL_S``; otherwise that foot is left uncalibrated with a warning.
        ``"none"``: the data as given.
    step_width_m : float
        Lateral distance between the feet's sensors, m (Zhao et al. take the shoulder width; the
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
        previous step, deg (Sec. V-C).
    heel_strike_before_stance_s : float
        Where the detector gives no heel strikes, the heel strike is taken this long before the
        stance starts, s.

    Notes
    -----
    Measured by ``python tests/fusion/test_step_vector_paper.py`` (simulator: 5 seeds, gyro
    bias walk 1e-4 rad/s^2/sqrt(Hz), threshold detector, ekf; E_s and E_p of eq. 8; the true
    E_s is 0.2 m; recordings: ``footnav.evaluate`` as in docs/accuracy.md).

    Simulator, |E_s - 0.2| / E_p (m), in the order independent; paper (pendulum + attitude);
    ``relative_frame="heading"``; ``step_length="fitted"``; fitted + heading (the defaults):

    - straight 100 m: 1.25 / 1.15; 0.010 / 1.10; 0.011 / 1.09; 0.021 / 1.00; 0.021 / 0.98
    - rectangle 105 x 68 m cw: 13.2 / 9.22; 0.021 / 6.25; 0.021 / 6.21; 0.023 / 6.25; 0.022 / 6.17
    - rectangle ccw: 14.3 / 9.79; 0.021 / 6.79; 0.021 / 6.75; 0.028 / 6.85; 0.026 / 6.76
    - straight, sensor yawed 10 deg on the shoe: 1.25 / 1.15; 0.006 / 10.6; 0.010 / 1.17;
      0.015 / 25.4; 0.021 / 1.21

    Recordings, 2-D ATE left / right (m), detector dual-gait (adaptive in brackets), paper;
    heading; fitted; fitted + heading:

    - azure_fgo: 0.112 / 0.117 (0.120 / 0.105); 0.114 / 0.111 (0.120 / 0.098);
      0.085 / 0.113 (0.101 / 0.088); 0.083 / 0.096 (0.099 / 0.073)
    - gaitmap: 0.207 / 0.173 (0.245 / 0.210); 0.198 / 0.208 (0.231 / 0.229);
      0.211 / 0.165 (0.267 / 0.193); 0.198 / 0.205 (0.252 / 0.235)

    * Eq. 6 with the true leg length is short: the simulator's rear foot is flat at the
      contralateral heel strike, so theta is the heel-strike pitch alone (20 deg) and S = 0.29 m
      (fusion) / 0.313 m (truth quaternions) for 0.70 m steps; on the recordings S = 0.09-0.11 m
      (azure_fgo) and 0.42-0.50 m (gaitmap) against 0.40 / 0.66 m from the INS strides. The
      foot turns less than the leg. The fused walk suffers less than S suggests (E_p within
      1-12 % on the simulator, ATE about 0.03 m worse on azure_fgo): the relative-position update
      mostly corrects heading, which the step *length* hardly affects.
    * ``relative_frame="attitude"`` turns the step vector with the sensor: a sensor yawed 10 deg
      on the shoe made E_p 10.6 m instead of 1.17 m with ``"heading"``. Use ``"heading"``
      unless the sensor's axes are the foot's.
    * ``calibration="standstill"`` on a walk with a 2 % accelerometer scale error injected:
      E_p 1.85 -> 1.05 m (straight); without one, 1.10 -> 1.05 m straight but 6.25 -> 6.41
      and 6.79 -> 6.96 m on the rectangles (the standstill reads the accelerometer's bias along
      gravity as a scale); on the recordings it changes ATE by under 0.004 m. Hence off by
      default.

    Examples
    --------
    >>> pipe = footnav.make_pipeline("dual-gait", "ekf", "step-vector")  # doctest: +SKIP
    >>> fitted = footnav.make_pipeline("dual-gait", "ekf", "step-vector",
    ...     fusion_params={"step_length": "fitted", "relative_frame": "heading"})  # doctest: +SKIP
    """

    name = "step-vector"
    needs_two_feet: ClassVar[bool] = True
    needs_stepable_estimator: ClassVar[bool] = True

    def __init__(
        self,
        *,
        step_length: str = "fitted",
        leg_length_m: float = 0.9,
        relative_frame: str = "heading",
        calibration: str = "none",
        step_width_m: float = 0.2,
        step_elevation_m: float = 0.0,
        step_length_std_m: float = 0.05,
        step_width_std_m: float = 0.05,
        step_elevation_std_m: float = 0.02,
        turn_threshold_deg: float = 10.0,
        heel_strike_before_stance_s: float = 0.1,
    ) -> None:
        self.step_length = step_length
        self.leg_length_m = leg_length_m
        self.relative_frame = relative_frame
        self.calibration = calibration
        self.step_width_m = step_width_m
        self.step_elevation_m = step_elevation_m
        self.step_length_std_m = step_length_std_m
        self.step_width_std_m = step_width_std_m
        self.step_elevation_std_m = step_elevation_std_m
        self.turn_threshold_deg = turn_threshold_deg
        self.heel_strike_before_stance_s = heel_strike_before_stance_s

    def validate_params(self) -> None:
        """Check every parameter (:meth:`footnav.core.component.Component.validate_params`); raises
        InvalidParameterError."""
        # Upper bounds (footnav.core.component): lengths and their stds are squared into the
        # step update's covariance (overflow at 1e308); a turn threshold above a full turn
        # never fires.
        for name, choices in (
            ("step_length", STEP_LENGTHS),
            ("relative_frame", RELATIVE_FRAMES),
            ("calibration", CALIBRATIONS),
        ):
            require(getattr(self, name) in choices, self, name, " or ".join(repr(c) for c in choices))
        require_positive(self, "leg_length_m", high=MAX_LENGTH_M)
        require_positive(self, "step_length_std_m", "step_width_std_m", "step_elevation_std_m", high=MAX_LENGTH_M)
        require_positive(self, "turn_threshold_deg", high=360.0)
        require_non_negative(self, "step_width_m", high=MAX_LENGTH_M)
        require_non_negative(self, "heel_strike_before_stance_s", high=MAX_DURATION_S)
        require_in_range(self, "step_elevation_m", low=-MAX_LENGTH_M, high=MAX_LENGTH_M)

    # -- the steps ------------------------------------------------------------------------------
    def _heel_strikes(self, view: FeetView, foot: int, starts: np.ndarray) -> np.ndarray:
        """Heel strikes that opened the foot's stance runs starting at samples ``starts`` (the
        view's indexing): the detector's latest within 0.5 s before each, else
        ``heel_strike_before_stance_s`` before it."""
        starts = np.asarray(starts, dtype=np.int64)
        hs = np.sort(np.asarray(view.heel_strikes[foot], dtype=np.int64))
        rate = view.rates[foot]
        window = int(round(0.5 * rate))
        j = np.searchsorted(hs, starts, side="right") - 1  # the latest at or before each start
        latest = hs[np.maximum(j, 0)] if len(hs) else np.zeros_like(starts)
        found = (j >= 0) & (latest >= starts - window)
        return np.where(found, latest, np.maximum(0, starts - int(round(self.heel_strike_before_stance_s * rate))))

    def _landings(self, view: FeetView) -> list[tuple[float, int, int, int]]:
        """(time of the heel strike, front foot, its sample, stance-run index) of every landing
        after the first stance of each foot, in time order: the step ends at the front foot's heel
        strike, both feet on the ground."""
        out: list[tuple[float, int, int, int]] = []
        for foot in (LEFT, RIGHT):
            runs = view.runs(foot)
            hs = self._heel_strikes(view, foot, runs[1:, 0])
            times = view.times[foot][hs]
            out.extend((float(t), foot, int(h), j) for j, (t, h) in enumerate(zip(times, hs), start=1))
        out.sort()
        return out

    def _supports(self, view: FeetView, rear: np.ndarray, t: np.ndarray) -> list[tuple[int, int] | None]:
        """For each step ending at ``t[i]`` (s), (heel strike, sample at t[i]) of the rear foot
        ``rear[i]`` if it supported the step (its last stance ended at most
        ``heel_strike_before_stance_s`` + 0.1 s before t[i]), else None."""
        rear, t = np.asarray(rear, dtype=np.int64), np.asarray(t, dtype=float)
        out: list[tuple[int, int] | None] = [None] * len(t)
        for foot in (LEFT, RIGHT):
            idx = np.flatnonzero(rear == foot)
            if not len(idx):
                continue
            times, runs = view.times[foot], view.runs(foot)
            k = np.searchsorted(times, t[idx], side="right") - 1
            j = np.searchsorted(runs[:, 0], k, side="right") - 1
            ok = (k >= 0) & (j >= 0)
            last = runs[np.maximum(j, 0), 1] - 1 if len(runs) else np.zeros_like(j)
            ok[ok] = ~(times[last[ok]] < t[idx[ok]] - self.heel_strike_before_stance_s - 0.1)
            hs = self._heel_strikes(view, foot, runs[j[ok], 0]) if len(runs) else np.zeros(0, dtype=np.int64)
            for i, h, kk in zip(idx[ok], hs, k[ok]):
                out[i] = (int(h), max(int(h), int(kk)))
        return out

    def _fit_leg_length(self, view: FeetView, singles) -> float:
        """Median of :meth:`step_ratios` over the whole walk (module docstring)."""
        ratios = [r for _, r in self.step_ratios(view, singles)]
        if not ratios:
            raise CompositionError(
                f"fusion {self.name!r}: no straight steps to fit the leg length to; give leg_length_m"
            )
        return float(np.median(ratios))

    def step_ratios(self, view: FeetView, singles: Sequence[FootTrajectory]) -> list[tuple[float, float]]:
        """(start of the stance the landing opened, s; :func:`leg_ratio`, m) of every straight
        step, theta measured exactly as :meth:`fuse` does, on each foot's single-foot solution
        ``singles`` (FootTrajectory per foot, the view's indexing)."""
        out: list[tuple[float, float]] = []
        turn = np.radians(self.turn_threshold_deg)
        landings = self._landings(view)
        supports = self._supports(
            view, np.array([1 - front for _, front, _, _ in landings]), np.array([t for t, _, _, _ in landings])
        )
        for (_, front, _, j), support in zip(landings, supports):
            if support is None:
                continue
            runs_f, traj_f = view.runs(front), singles[front]
            a0, a1 = runs_f[j - 1, 0], runs_f[j, 0]
            q_f, q_r = traj_f.quaternion, singles[1 - front].quaternion
            ratio = leg_ratio(
                traj_f.position[a0],
                traj_f.position[a1],
                quat.yaw_of(q_f[a0]),
                quat.yaw_of(q_f[a1]),
                pendulum_step_length(q_r[support[0]], q_r[support[1]], 1.0),
                turn,
            )
            if ratio is not None:
                out.append((float(view.times[front][a1]), ratio))
        return out

    # -- the fusion -----------------------------------------------------------------------------
    @property
    def online_exact(self) -> bool:  # type: ignore[override]
        """Whether the live session gives the offline result: only with the pendulum step length."""
        # online, the fitted leg length is that of the strides so far, not the whole walk's
        return self.step_length == "pendulum"

    @property
    def reads_feet_alone(self) -> bool:  # type: ignore[override]
        """Whether the session reads each foot's own forward solution (the fitted leg length does)."""
        return self.step_length == "fitted"

    @property
    def calibrates_feet(self) -> bool:  # type: ignore[override]
        """Whether each foot is calibrated on its first stance before its filter starts."""
        return self.calibration != "none"

    def foot_calibration(self, imu: ImuData, stance: StanceResult, foot: str) -> StandstillCalibration | None:
        """With ``calibration="standstill"``, the accelerometer scale from the foot's first stance
        (Zhao et al. (2019), Sec. II-A; its gyro bias is not applied: that is the estimator's own,
        ekf's ``gyro_bias="initial-standstill"``, and subtracting it here too was measured to
        hurt); None with a warning when that stance is shorter than ``MIN_STANDSTILL_S`` or not
        still, and None with ``calibration="none"``."""
        if self.calibration == "none":
            return None
        runs = stance.intervals if len(stance.mask) == len(imu.t) else np.zeros((0, 2), dtype=np.int64)
        if len(runs) and imu.t[runs[0, 1] - 1] - imu.t[runs[0, 0]] >= MIN_STANDSTILL_S:
            try:
                return calibrate_at_rest(imu, int(runs[0, 0]), int(runs[0, 1]))
            except InvalidInputError as exc:
                reason = str(exc)
        else:
            reason = f"its first stance is shorter than {MIN_STANDSTILL_S:g} s"
        warn(
            f"fusion {self.name!r}: calibration='standstill' left the {foot} foot uncalibrated: {reason}",
            DataQualityWarning,
            stacklevel=4,
        )
        return None

    def _calibrated(self, imu: ImuData, stance: StanceResult, foot: str) -> tuple[ImuData, dict | None]:
        """``imu`` with :meth:`foot_calibration` applied, and its record (None: unchanged)."""
        cal = self.foot_calibration(imu, stance, foot)
        if cal is None:
            return imu, None
        return cal.apply(imu, gyro_bias=False), cal.as_meta(gyro_bias=False)

    def fuse(
        self,
        estimator: FootEstimator,
        left: ImuData,
        stance_left: StanceResult,
        right: ImuData | None = None,
        stance_right: StanceResult | None = None,
    ) -> FusionResult:
        """Both feet in one filter with a relative-position update at every straight step.

        Parameters
        ----------
        estimator : FootEstimator
            An estimator with a step-able filter (``ekf``).
        left, right : ImuData
            Each foot's recording.
        stance_left, stance_right : StanceResult
            Each foot's stance.

        Returns
        -------
        FusionResult
            Both feet and their midpoint path; ``meta`` has the updates applied, suspended
            (turning) and skipped (rear foot not on the ground), the leg length used, the median
            step length and, with ``calibration="standstill"``, each foot's calibration.

        Notes
        -----
        On the feet's common time span; outside it each foot alone
        (:func:`footnav.fusion.joint.fuse_on_common_span`).
        """
        if self.calibration == "none":
            return fuse_on_common_span(self, estimator, left, stance_left, right, stance_right, self._fuse_span)
        check_two_feet(self, estimator, right, stance_right)
        assert right is not None and stance_right is not None  # check_two_feet raised otherwise
        left, cal_left = self._calibrated(left, stance_left, "left")
        right, cal_right = self._calibrated(right, stance_right, "right")
        res = fuse_on_common_span(self, estimator, left, stance_left, right, stance_right, self._fuse_span)
        meta = {**res.meta, "calibration": {"left": cal_left, "right": cal_right}}
        return FusionResult(left=res.left, right=res.right, path=res.path, meta=meta)

    def session(self, estimator: Any, start_s: float) -> StepVectorSession:
        """The step updates on a joint filter that grows as samples arrive (online mode;
        :class:`footnav.core.component.FusionSession`), from the feet's common start ``start_s`` (s).

        With ``step_length="fitted"`` the leg length is fitted as the walk goes
        (:class:`~footnav.fusion.pendulum.LegLengthFit`: no update before ``LEG_FIT_MIN_STEPS``
        straight steps), on each
        foot's own solution given by ``session.feet_alone``; with ``calibration="standstill"``
        the stream calibrates each foot from its first stance (:meth:`foot_calibration`).
        """
        self.validate_params()
        if self.step_length == "fitted":
            return StepVectorSession(self, None)
        return StepVectorSession(self, float(self.leg_length_m))

    def _fuse_span(self, estimator, left, stance_left, right, stance_right) -> FusionResult:
        """:meth:`fuse` on feet that share their whole time span: one session over the whole walk."""
        imus, stances = (left, right), (stance_left, stance_right)
        view = FeetView.of(imus, stances)
        if self.step_length == "fitted":
            filt, singles = start_joint(
                estimator, left, stance_left, right, stance_right, self.step_width_m, return_singles=True
            )
            leg = self._fit_leg_length(view, singles)
        else:
            filt, leg = (
                start_joint(estimator, left, stance_left, right, stance_right, self.step_width_m),
                self.leg_length_m,
            )
        session = StepVectorSession(self, leg, closing_time(estimator, imus, stances))
        landings = [imu.t[stance.intervals[1:, 0]] for imu, stance in zip(imus, stances)]
        stop = min(left.t[-1], right.t[-1])
        session.advance(filt, stop, landings, view, stop_s=stop)
        return finish_joint(estimator, filt, stance_left, stance_right, session.finish(), imus)


class StepVectorSession:
    """The step-vector updates on one joint filter (:class:`StepVectorFusion`;
    :class:`footnav.core.component.FusionSession`): at every landing (the front foot's heel strike,
    in time order), the relative position of the feet from the rear foot's pendulum, unless the
    rear foot was not on the ground or is turning.

    Parameters
    ----------
    fusion
        The step-vector fusion (its parameters).
    leg_length_m
        The pendulum length l, m (eq. 6); None: fitted as the walk goes (:class:`~footnav.fusion.pendulum.LegLengthFit`,
        online ``step_length="fitted"``).
    closing_s
        No update after this time, s (the estimator's closed loop takes over there).
    """

    def __init__(self, fusion: StepVectorFusion, leg_length_m: float | None, closing_s: float = math.inf) -> None:
        self.fusion = fusion
        self.leg_length_m = None if leg_length_m is None else float(leg_length_m)
        #: the leg length fitted on the steps so far (None: ``leg_length_m`` is given)
        self.fit = LegLengthFit(math.radians(fusion.turn_threshold_deg)) if leg_length_m is None else None
        self.step_width_m = float(fusion.step_width_m)
        #: the rear foot's attitude at its own heel strike, before its latest stance
        self.history_s = float(fusion.heel_strike_before_stance_s) + 0.1
        self._events = EventQueue(closing_s)  # (heel strike time, front foot), known, not yet applied
        self._yaw0: list[float] | None = None
        self._h: dict[int, np.ndarray] = {}  # H of eq. 7 by front foot
        self._last_stance_yaw: dict[int, float] = {}
        self._r = np.array([fusion.step_length_std_m, fusion.step_width_std_m, fusion.step_elevation_std_m]) ** 2
        self._turn = np.radians(fusion.turn_threshold_deg)
        self.applied = self.suspended = self.skipped = 0
        self.lengths: list[float] = []

    def feet_alone(self, foot: int, starts: list[tuple[float, np.ndarray, np.ndarray]]) -> None:
        """Foot ``foot``'s own forward solution (``(time s, position m, quaternion)``, in its own
        frame) at its newest stance starts: what the fitted leg length reads (online mode)."""
        if self.fit is not None:
            self.fit.add_starts(foot, starts)

    def known_until(self, view: FeetView, final_s: float) -> float:
        """Up to (not at) the earliest heel strike a landing not yet known could have: a landing is
        known once its stance start is final, and its heel strike is some samples before that
        (counted in samples: time stamps may jitter or jump)."""
        until = final_s
        for foot, times in enumerate(view.times):
            back = max(int(round(self.fusion.heel_strike_before_stance_s * view.rates[foot])), 0)
            if len(view.heel_strikes[foot]):
                back = max(back, int(round(0.5 * view.rates[foot])))
            k = len(times) - back  # the first sample not final is a stance start at the earliest
            if k <= 0:
                return -math.inf
            until = min(until, float(np.nextafter(times[k], -np.inf)) if k < len(times) else until)
        return until

    def advance(self, filt, until_s: float, landings, view: FeetView, *, stop_s: float | None = None) -> None:
        """Apply the update of every landing with its heel strike at or before ``until_s`` (s; all
        of them with ``stop_s``, the feet's common end); ``landings``: each foot's newly known
        stance starts, s; ``view``: the feet in the filter's sample indexing."""
        fusion = self.fusion
        if self._yaw0 is None:  # the yaw each sensor has when its foot faces the walking direction (+x at the start)
            self._yaw0 = [quat.yaw_of(filt.quaternion(f)) for f in (LEFT, RIGHT)]
            self._big = filt.covariance.shape[0]
        for foot, new in enumerate(landings):
            times = view.times[foot]
            starts = np.searchsorted(times, np.asarray(new, dtype=float).ravel())
            for hs, start in zip(fusion._heel_strikes(view, foot, starts), starts):
                self._events.add(times[hs], foot)
                if self.fit is not None:
                    self.fit.stance_of[(foot, float(times[hs]))] = float(times[start])
        due = self._events.due(until_s, stop_s is not None)
        supports = fusion._supports(view, np.array([1 - front for _, front in due]), np.array([t for t, _ in due]))
        for (t, front), support in zip(due, supports):
            self._update(filt, t, front, support)

    def _update(self, filt, t: float, front: int, support: tuple[int, int] | None) -> None:
        """The step vector at the front foot's heel strike at ``t`` (s) (Zhao et al. (2019), Sec.
        III-B, IV-B); ``support``: the rear foot's heel strike and its sample at ``t``
        (:meth:`StepVectorFusion._supports`), None when it was not on the ground."""
        fusion = self.fusion
        rear = 1 - front
        filt.run_until(t)
        if support is None:
            self.skipped += 1  # the rear foot was not on the ground: no pendulum to read
            return
        hs_rear, k_q2 = support
        q_out = filt.outputs(rear)[0]
        leg = self.leg_length_m
        if self.fit is not None:
            self.fit.landing(front, t, pendulum_step_length(q_out[hs_rear], q_out[k_q2], 1.0))
            leg = self.fit.leg_at(t)
        assert self._yaw0 is not None  # set by advance before its first update
        yaw_r = quat.yaw_of(q_out[hs_rear]) - self._yaw0[rear]
        prev = self._last_stance_yaw.get(rear)
        self._last_stance_yaw[rear] = yaw_r  # heading of the rear foot's footprint
        if prev is not None and abs(quat.wrap_angle(yaw_r - prev)) > self._turn:
            self.suspended += 1  # Sec. V-C: no update while curving or turning
            return
        if leg is None:
            if self.fit is not None:
                self.fit.waiting += 1  # too few steps fitted yet
            return
        s = pendulum_step_length(q_out[hs_rear], q_out[k_q2], leg)  # S = 2 l sin(theta/2)  (eq. 5-6)
        self.lengths.append(s)
        if self.fit is not None:
            self.fit.used.append((t, leg))
        side = 1.0 if front == LEFT else -1.0
        if fusion.relative_frame == "attitude":
            rot = quat.as_matrix(q_out[k_q2])  # C_b^n of the rear foot at the update (Sec. IV-B)
        else:
            c, sn = np.cos(yaw_r), np.sin(yaw_r)
            rot = np.array([[c, -sn, 0.0], [sn, c, 0.0], [0.0, 0.0, 1.0]])  # rear-heading frame -> nav
        dp_n = rot @ np.array([s, side * fusion.step_width_m, fusion.step_elevation_m])  # dp^n = C dp^b
        h = self._h.get(front)
        if h is None:
            h = self._h[front] = np.zeros((3, self._big))
            h[:, filt.block(front, "pos")] = np.eye(3)  # H_p = [0 0 I]_front - [0 0 I]_rear  (eq. 7)
            h[:, filt.block(rear, "pos")] = -np.eye(3)
        y = (filt.position(front) - filt.position(rear)) - dp_n  # z_p = (p^_1 - p^_2) - dp^n  (eq. 7)
        # in the rear foot's frame the three components are independent
        filt.update(rot.T @ h, rot.T @ y, self._r)
        self.applied += 1

    def finish(self) -> dict:
        """The fusion's meta, after the last :meth:`advance`."""
        fusion = self.fusion
        meta = {
            "fusion": fusion.describe(),
            "step_length": fusion.step_length,
            "relative_frame": fusion.relative_frame,
            "leg_length_m": self.leg_length_m if self.fit is None else self.fit.latest(),
            "updates": self.applied,
            "suspended_turning": self.suspended,
            "skipped_rear_foot_moving": self.skipped,
            "step_length_m": {
                "median": float(np.median(self.lengths)) if self.lengths else None,
                "n": len(self.lengths),
            },
        }
        if self.fit is not None:
            meta["leg_length_fit"] = self.fit.as_meta()
        return meta
