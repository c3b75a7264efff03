"""Error-state ZUPT-aided INS estimator: closed-loop 9- or 15-state EKF with RTS smoothing.

Zhao et al. (2019), eq. 1-3, and Chistyakov et al. (2021), Alg. 1: the filter of
:mod:`footnav.estimators.ekf.filter` (error state [attitude, velocity, position] and optionally the
accelerometer and gyro biases; ZUPT in stance, optional zero angular rate; closed-loop feedback),
initial roll, pitch and gyro bias from the first standstill, and the smoother of
:mod:`footnav.estimators.ekf.smoother` (step-wise or over the whole walk). When the walk returns to its
start (``closed_loop=True``), the final standstill gets the start position as a measurement and
the whole-walk smoother spreads that correction back over the trajectory (Chistyakov et al. (2021)).
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from typing import Any, Literal, cast

import numpy as np
from numpy.typing import NDArray

from footnav.core.component import FootEstimator
from footnav.core.errors import InvalidParameterError
from footnav.core.parameters import (
    MAX_ACC_MPS2,
    MAX_ANGLE_RAD,
    MAX_DURATION_S,
    MAX_LENGTH_M,
    MAX_RATE_RADPS,
    MAX_SCALE_STD,
    MAX_SPEED_MPS,
    require,
    require_non_negative,
    require_positive,
)
from footnav.core.types import FULL_SCALE_RATIO, FootTrajectory, ImuData, StanceResult, clipped_acc
from footnav.estimators.ekf._records import FilterNoise, Smoothed
from footnav.estimators.ekf.filter import InsFilter
from footnav.estimators.ekf.online import OnlineInsFilter
from footnav.estimators.ekf.smoother import KEEP_RECORD_MB, SMOOTHERS, SegmentRecords, StepSmoother, smooth
from footnav.nav import quaternion as quat
from footnav.nav.floors import LEVEL_RISE_MAX_M, stance_swing_rises, swing_rises
from footnav.nav.heading import turn_to_first_step
from footnav.nav.heading_drift import GYRO_SCALE_STD, TURN_ON_BIAS_STD_RADPS, standstill_rate_std, with_heading_drift
from footnav.nav.initial_alignment import align_first_stance
from footnav.nav.stance_edges import settled_mask
from footnav.nav.stride_hold import runs_of

__all__ = ["EkfEstimator", "GYRO_BIAS_STD_FLOOR_RADPS"]

#: Least initial std of the gyro bias states, rad/s (2 deg/h, below any MEMS gyro's in-run bias
#: stability): a standstill of quantised or noise-free samples has a zero standard error, and a
#: zero prior would freeze the bias states.
GYRO_BIAS_STD_FLOOR_RADPS = 1e-5


class EkfEstimator(FootEstimator):
    """Closed-loop error-state ZUPT EKF, 9 or 15 states, with RTS smoothing.

    Zhao et al. (2019), eq. 1-3, and Chistyakov et al. (2021), Alg. 1. Initial
    roll, pitch and gyro bias come from the first stance phase; heading starts at zero. Noise
    parameters are densities, so results do not depend on the sampling rate.

    Parameters
    ----------
    acc_noise_mps2_sqrthz : float
        Accelerometer white-noise density driving the velocity error, m/s^2/sqrt(Hz).
    gyr_noise_radps_sqrthz : float
        Gyroscope white-noise density driving the attitude error, rad/s/sqrt(Hz).
    zupt_std_mps : float
        Standard deviation of the zero-velocity pseudo-measurement, m/s.
    init_attitude_std_rad : float
        Initial roll/pitch/heading uncertainty, rad.
    init_velocity_std_mps : float
        Initial velocity uncertainty, m/s.
    heading : {"first-step", "sensor"}
        Nav frame heading: "first-step" turns the result so the first step points along +x;
        "sensor" keeps the sensor's initial heading as x.
    gyro_bias : {"initial-standstill", "none"}
        Start from the mean angular rate of the still samples of the first stance phase, or zero.
    still_gyr_max_radps : float
        Samples of the first stance used for levelling and gyro bias must turn slower than this,
        rad/s (a detected stance is not always a true standstill).
    bias_states : bool
        Estimate accelerometer and gyro biases as six more error states (15 in all). The vertical
        gyro bias is nearly unobservable from zero-velocity updates, so the heading std grows
        with the gyro bias priors, and with loose priors the forward estimate re-places heading
        and position at every stance sample (the per-sample track of ``smoother="none"`` then
        lengthens: docs/changes.md). The defaults are the data's and the library's own: the
        initial std from the standstill (``init_gyr_bias_std_radps=None``) and the bias walk of
        the heading-drift model (``yaw_bias_walk_radps2_sqrthz``'s default).
    acc_bias_walk_mps3_sqrthz : float
        Accelerometer bias random walk, m/s^3/sqrt(Hz) (15 states only).
    gyr_bias_walk_radps2_sqrthz : float
        Gyroscope bias random walk, rad/s^2/sqrt(Hz) (15 states only): a consumer MEMS gyro's,
        as ``yaw_bias_walk_radps2_sqrthz``; raise it for a gyro whose bias wanders faster.
    init_acc_bias_std_mps2 : float
        Initial accelerometer bias uncertainty, m/s^2 (15 states only).
    init_gyr_bias_std_radps : float or None
        Initial gyro bias uncertainty after the initial-standstill estimate, rad/s (15 states
        only). None: from the data, the standard error of that estimate (the still samples' mean
        rate, each foot its own, at least ``GYRO_BIAS_STD_FLOOR_RADPS``); with
        ``gyro_bias="none"``, a consumer gyro's turn-on bias (``TURN_ON_BIAS_STD_RADPS``).
        The value used is in ``meta["init_gyr_bias_std_radps"]``.
    zaru_std_radps : float
        Standard deviation of the zero-angular-rate update in stance, rad/s; 0 turns it off
        (15 states only: it observes the gyro bias). Only for stances that are truly still: a
        walking foot twists about the leg through its stance at 1-17 deg/s on every shared
        recording (docs/heading.md), which this update takes for gyro bias.
    smoother : {"whole", "step", "none"}
        RTS smoothing over the whole walk (Chistyakov et al. (2021), Alg. 1), within each step during the forward
        pass (memory independent of the recording's length), or none.
    smoother_cache_mb : float
        Memory the whole-walk smoother may keep of the forward run's record, MB per foot (a joint
        filter of two feet keeps twice as much, as two filters of one foot do): segments beyond
        it (the oldest) are re-run from their checkpoints, which costs a second forward pass over
        them. With 9 states a sample takes 56 bytes, 336 with a ZUPT: about 175 on a walk with
        42 % of its samples in stance, so the default holds about an hour at 100 Hz; 0 keeps
        nothing (least memory, every segment re-run).
    closed_loop : bool
        The walk ends where it started: the final standstill gets the start position as a
        measurement (Chistyakov et al. (2021)); needs ``smoother="whole"`` to correct the whole trajectory.
    closed_loop_std_m : float
        Standard deviation of that start-equals-end measurement, m.
    heading_drift_in_std : bool
        Add the heading drift the filter does not estimate to ``position_std``
        (:mod:`footnav.nav.heading_drift`): a gyro scale-factor error of ``gyro_scale_std`` on
        every turn and, with 9 states (the 15-state filter carries its gyro bias itself), a
        constant yaw-rate error with the std of the initial-standstill bias estimate (the
        standard error of the still samples' mean rate; ``init_gyr_bias_std_radps`` with
        ``gyro_bias="none"``) and a bias random walk of ``yaw_bias_walk_radps2_sqrthz``.
        Changes ``position_std`` only, never the estimate. False: the filter's covariance alone,
        overconfident beyond a few minutes (docs/concepts.md, "What position_std means").
    gyro_scale_std : float
        Std of the gyro's scale-factor error, a fraction (0.005 is 0.5 %, a factory-trimmed
        consumer MEMS gyro; 0 for a sensor calibrated for scale), which no zero-velocity update
        observes: the heading error is this times the turns walked.
    yaw_bias_walk_radps2_sqrthz : float
        Random walk of the gyro bias about the vertical, which no zero-velocity update observes,
        rad/s^2/sqrt(Hz): the consumer MEMS grade of the simulator's default sensor.
    zupt_start_delay_s, zupt_end_advance_s : float
        The zero-velocity update begins this long after each detected stance's start and ends
        this long before its end, s (0: none, the default; with ``zupt_edges="settled"`` the
        later start and the earlier end of the two; offline only). Not the first stance,
        which aligns the filter. A detector declares stance while the foot still settles (on the
        shared recordings the VICON foot still descends at 0.02-0.05 m/s at the detected start of a
        walking stance) and keeps it while the heel already rises; the filter takes that real
        motion for an error grown over the whole swing and moves the footprint by about
        v T_swing / 2: the height drift of flat walks (docs/height.md). The stance's outputs
        (``steps``) are the detector's still.
    zupt_edges : {"settled", "detected"}
        "settled" (the default): each stance's update (not the first stance's) starts where the
        foot's vertical velocity relative to mid-stance, integrated from its accelerometer's
        magnitude, has fallen within ``zupt_std_mps``, and ends where it leaves it again
        (:func:`footnav.nav.stance_edges.settled_mask`): the update asserts no more than the
        data allow, so a landing's last motion is not taken for an error grown over the swing
        (docs/height.md, section 8). "detected": the whole detected stance. Online, a stance's
        samples reach the filter once it has ended.
    zupt_edge_max_fraction : float
        Neither edge takes more than this fraction of a stance (short running stances keep their
        middle), in (0, 0.5].
    vertical : {"floors", "free"}
        "floors": a stride whose stance-to-stance rise is under ``level_rise_max_m`` is held
        level, a larger rise (stairs) is kept, and the floors changed are counted
        (:func:`footnav.nav.floors.hold_floors`; ``meta["vertical"]``). "free": the filter's
        height as it is, which climbs a few cm per stride on flat walks (docs/height.md). The
        :class:`footnav.Pipeline` applies it to its final trajectories (after the fusion,
        offline and online alike); :meth:`estimate` called alone returns the filter's height.
    level_rise_max_m : float
        A stride rising or falling less than this is level, m (0.075: below one stair riser,
        above the drift of 95 % of the shared walking strides; a ramp flatter than that per
        stride is flattened).
    clip_excess_mps2 : float
        Std of the specific force beyond the range at a sample whose accelerometer axis is at
        its range, m/s^2 (0: off, the default; offline only). Where the input records clipping
        (``meta["clipped"]``, :func:`footnav.core.types.clipped_acc` with the recorded full scale,
        an axis within ``FULL_SCALE_RATIO[0]`` of it), that sample's transition gets the extra
        velocity variance (clip_excess_mps2 dt)^2 along each clipped body axis, so the next ZUPT
        puts the velocity it finds into the clipped samples rather than over the whole swing.
        ``meta["clipped_samples"]`` counts them. Not the default: on gaitmap's stairs the feet
        agree within 0.4 / 6.5 % (up / down) instead of 18 / 15 %, but the right foot's height
        RMSE of gaitmap's level walk rises 0.151 -> 0.177 m (docs/height.md, section 7).

    Examples
    --------
    >>> est = EkfEstimator(bias_states=True, smoother="whole")
    >>> traj = est.estimate(imu, make_detector("threshold").detect(imu))  # doctest: +SKIP
    """

    name = "ekf"

    def __init__(
        self,
        *,
        acc_noise_mps2_sqrthz: float = 0.05,
        gyr_noise_radps_sqrthz: float = 2e-3,
        zupt_std_mps: float = 0.01,
        init_attitude_std_rad: float = 0.01,
        init_velocity_std_mps: float = 0.01,
        heading: Literal["first-step", "sensor"] = "first-step",
        gyro_bias: Literal["initial-standstill", "none"] = "initial-standstill",
        still_gyr_max_radps: float = 0.05,
        bias_states: bool = False,
        acc_bias_walk_mps3_sqrthz: float = 1e-3,
        gyr_bias_walk_radps2_sqrthz: float = 1e-5,
        init_acc_bias_std_mps2: float = 0.05,
        init_gyr_bias_std_radps: float | None = None,
        zaru_std_radps: float = 0.0,
        smoother: Literal["whole", "step", "none"] = "whole",
        smoother_cache_mb: float = KEEP_RECORD_MB,
        closed_loop: bool = False,
        closed_loop_std_m: float = 0.01,
        heading_drift_in_std: bool = True,
        yaw_bias_walk_radps2_sqrthz: float = 1e-5,
        gyro_scale_std: float = GYRO_SCALE_STD,
        zupt_start_delay_s: float = 0.0,
        zupt_end_advance_s: float = 0.0,
        zupt_edge_max_fraction: float = 0.25,
        zupt_edges: Literal["detected", "settled"] = "settled",
        vertical: Literal["floors", "free"] = "floors",
        level_rise_max_m: float = LEVEL_RISE_MAX_M,
        clip_excess_mps2: float = 0.0,
    ) -> None:
        self.acc_noise_mps2_sqrthz = acc_noise_mps2_sqrthz
        self.gyr_noise_radps_sqrthz = gyr_noise_radps_sqrthz
        self.zupt_std_mps = zupt_std_mps
        self.init_attitude_std_rad = init_attitude_std_rad
        self.init_velocity_std_mps = init_velocity_std_mps
        self.heading = heading
        self.gyro_bias = gyro_bias
        self.still_gyr_max_radps = still_gyr_max_radps
        self.bias_states = bias_states
        self.acc_bias_walk_mps3_sqrthz = acc_bias_walk_mps3_sqrthz
        self.gyr_bias_walk_radps2_sqrthz = gyr_bias_walk_radps2_sqrthz
        self.init_acc_bias_std_mps2 = init_acc_bias_std_mps2
        self.init_gyr_bias_std_radps = init_gyr_bias_std_radps
        self.zaru_std_radps = zaru_std_radps
        self.smoother = smoother
        self.smoother_cache_mb = smoother_cache_mb
        self.closed_loop = closed_loop
        self.closed_loop_std_m = closed_loop_std_m
        self.heading_drift_in_std = heading_drift_in_std
        self.yaw_bias_walk_radps2_sqrthz = yaw_bias_walk_radps2_sqrthz
        self.gyro_scale_std = gyro_scale_std
        self.zupt_start_delay_s = zupt_start_delay_s
        self.zupt_end_advance_s = zupt_end_advance_s
        self.zupt_edge_max_fraction = zupt_edge_max_fraction
        self.zupt_edges = zupt_edges
        self.vertical = vertical
        self.level_rise_max_m = level_rise_max_m
        self.clip_excess_mps2 = clip_excess_mps2

    def validate_params(self) -> None:
        """Check every parameter (:meth:`footnav.core.component.Component.validate_params`); raises
        InvalidParameterError."""
        # Upper bounds (footnav.core.component): every std and noise density is squared into the
        # filter's covariance, where 1e308 overflows to inf and turns the estimate into NaN.
        require_positive(
            self, "acc_noise_mps2_sqrthz", "acc_bias_walk_mps3_sqrthz", "init_acc_bias_std_mps2", high=MAX_ACC_MPS2
        )
        require_positive(
            self, "gyr_noise_radps_sqrthz", "still_gyr_max_radps", "gyr_bias_walk_radps2_sqrthz", high=MAX_RATE_RADPS
        )
        if self.init_gyr_bias_std_radps is not None:
            require_positive(self, "init_gyr_bias_std_radps", high=MAX_RATE_RADPS)
        require_positive(self, "zupt_std_mps", "init_velocity_std_mps", high=MAX_SPEED_MPS)
        require_positive(self, "init_attitude_std_rad", high=MAX_ANGLE_RAD)
        require_positive(self, "closed_loop_std_m", high=MAX_LENGTH_M)
        require_non_negative(self, "zaru_std_radps", "yaw_bias_walk_radps2_sqrthz", high=MAX_RATE_RADPS)
        require_non_negative(self, "gyro_scale_std", high=MAX_SCALE_STD)
        # a cap, not an allocation; 1 TB keeps the MB -> bytes conversion far from overflow
        require_non_negative(self, "smoother_cache_mb", high=1e6)
        require_non_negative(self, "zupt_start_delay_s", "zupt_end_advance_s", high=MAX_DURATION_S)
        require(0.0 < self.zupt_edge_max_fraction <= 0.5, self, "zupt_edge_max_fraction", "in (0, 0.5]")
        require(self.zupt_edges in ("detected", "settled"), self, "zupt_edges", "'detected' or 'settled'")
        require_positive(self, "level_rise_max_m", high=MAX_LENGTH_M)
        require_non_negative(self, "clip_excess_mps2", high=MAX_ACC_MPS2)
        require(self.vertical in ("floors", "free"), self, "vertical", "'floors' or 'free'")
        require(self.heading in ("first-step", "sensor"), self, "heading", "'first-step' or 'sensor'")
        require(self.gyro_bias in ("initial-standstill", "none"), self, "gyro_bias", "'initial-standstill' or 'none'")
        require(isinstance(self.bias_states, (bool, np.bool_)), self, "bias_states", "True or False")
        require(isinstance(self.closed_loop, (bool, np.bool_)), self, "closed_loop", "True or False")
        require(isinstance(self.heading_drift_in_std, (bool, np.bool_)), self, "heading_drift_in_std", "True or False")
        require(self.smoother in SMOOTHERS, self, "smoother", " or ".join(repr(m) for m in SMOOTHERS))
        if self.closed_loop and self.smoother != "whole":
            raise InvalidParameterError(
                f"{self.name}: closed_loop=True needs smoother='whole' (got {self.smoother!r}): only the "
                "whole-walk smoother carries the start-equals-end correction back over the trajectory"
            )
        if self.zaru_std_radps > 0 and not self.bias_states:
            raise InvalidParameterError(
                f"{self.name}: zaru_std_radps > 0 needs bias_states=True: the zero-angular-rate update "
                "observes the gyro bias, which the 9-state filter does not estimate"
            )

    @property
    def n_states(self) -> int:
        """Error states per foot: 15 with bias states, else 9."""
        return 15 if self.bias_states else 9

    # -- the step-able filter ---------------------------------------------------------------------
    def start(
        self,
        imus: Sequence[ImuData],
        stances: Sequence[StanceResult],
        *,
        initial_yaw_rad: Sequence[float] | None = None,
        initial_position_m: Sequence[NDArray[np.float64]] | None = None,
    ) -> OnlineInsFilter:
        """Align each foot at its first standstill and return the filter, ready to run (an
        :class:`InsFilter` a stream can run in segments, :class:`footnav.core.component.OnlineFilter`).

        Parameters
        ----------
        imus, stances
            One or two feet (two share one joint filter, on one clock).
        initial_yaw_rad
            Heading of each foot's nav frame at the start (rad about z); default 0, the
            sensor's own heading.
        initial_position_m
            Start position of each foot in nav, m; default the origin.

        Returns
        -------
        OnlineInsFilter
            Its ``meta`` holds the alignment of each foot.
        """
        self.validate_params()
        n_feet = len(imus)
        yaws = [0.0] * n_feet if initial_yaw_rad is None else list(initial_yaw_rad)
        p0 = (
            [np.zeros(3)] * n_feet if initial_position_m is None else [np.asarray(x, float) for x in initial_position_m]
        )
        starts, q0, bg0, metas = [], [], [], []
        for imu, stance, yaw in zip(imus, stances, yaws):
            s0, align, meta = self._align(imu, stance)
            starts.append(s0)
            q0.append(quat.multiply(quat.from_yaw(yaw), align.quaternion))
            bg0.append(align.gyro_bias_radps if self.gyro_bias == "initial-standstill" else np.zeros(3))
            metas.append(meta)
        var_att, var_vel = self.init_attitude_std_rad**2, self.init_velocity_std_mps**2
        cov0 = [[var_att] * 3 + [var_vel] * 3 + [0.0] * 3 for _ in metas]
        if self.bias_states:
            for row, meta in zip(cov0, metas):
                meta["init_gyr_bias_std_radps"] = gyr0 = self._gyro_bias_prior(meta)
                row += [self.init_acc_bias_std_mps2**2] * 3 + [gyr0**2] * 3
        noise = FilterNoise(
            acc_mps2_sqrthz=float(self.acc_noise_mps2_sqrthz),
            gyr_radps_sqrthz=float(self.gyr_noise_radps_sqrthz),
            zupt_std_mps=float(self.zupt_std_mps),
            acc_bias_walk_mps3_sqrthz=float(self.acc_bias_walk_mps3_sqrthz),
            gyr_bias_walk_radps2_sqrthz=float(self.gyr_bias_walk_radps2_sqrthz),
            zaru_std_radps=float(self.zaru_std_radps),
        )
        filt = OnlineInsFilter(
            [imu.t for imu in imus],
            [imu.acc for imu in imus],
            [imu.gyr for imu in imus],
            [np.asarray(st.mask, dtype=bool) for st in stances],
            starts,
            q0,
            p0,
            bg0,
            np.array(cov0),
            noise,
            self.n_states,
            clip_var=[self._clip_var(imu, m) for imu, m in zip(imus, metas)],
            zupt=[self._zupt(imu, st) for imu, st in zip(imus, stances)],
        )
        filt.meta = metas
        if self.smoother == "step":
            filt.step_smoother = StepSmoother(filt)
        elif self.smoother == "whole":
            filt.segment_records = SegmentRecords(filt, float(self.smoother_cache_mb) * n_feet)
        return filt

    def _clip_var(self, imu: ImuData, meta: dict) -> NDArray[np.float64] | None:
        """Extra velocity variance (m^2/s^2) of each sample's transition, (N, 3): (``clip_excess_mps2``
        dt)^2 per accelerometer axis at its range (:func:`footnav.core.types.clipped_acc`, with the
        full scale the input records), None when nothing is clipped."""
        found = imu.meta.get("clipped")
        if not self.clip_excess_mps2 or not found or not found.get("acc"):
            return None
        # within FULL_SCALE_RATIO of the range: a calibrated axis saturates a few percent either
        # side of its raw full scale (gaitmap's NilsPod: 15.2-15.97 g on a 16 g range)
        fs = found.get("acc_full_scale_mps2")
        hit = clipped_acc(imu.acc, acc_full_scale_mps2=fs, fraction=FULL_SCALE_RATIO[0])
        dt = np.diff(imu.t, prepend=imu.t[0])
        meta["clipped_samples"] = int(np.count_nonzero(hit.any(axis=1)))
        return hit * ((float(self.clip_excess_mps2) * dt) ** 2)[:, None]

    def _gyro_bias_prior(self, meta: dict) -> float:
        """A foot's gyro bias states' initial std, rad/s: the parameter, or what its data say
        (``init_gyr_bias_std_radps``)."""
        if self.init_gyr_bias_std_radps is not None:
            return float(self.init_gyr_bias_std_radps)
        if self.gyro_bias != "initial-standstill":
            return TURN_ON_BIAS_STD_RADPS
        return max(GYRO_BIAS_STD_FLOOR_RADPS, float(meta["gyro_bias_sem_radps"]))

    def _zupt(self, imu: ImuData, stance: StanceResult) -> NDArray[np.bool_]:
        mask = np.asarray(stance.mask, dtype=bool)
        rows = self.zupt_rows(imu.t, imu.acc, mask, first_whole=True)
        return mask if rows is None else rows

    @property
    def trims_stances(self) -> bool:
        """The zero-velocity update is not the whole stance: :meth:`zupt_rows` needs each stance
        whole (a stream gives its filter a stance's samples once it has ended)."""
        return self.zupt_edges == "settled" or bool(self.zupt_start_delay_s or self.zupt_end_advance_s)

    def zupt_rows(
        self, t: NDArray[np.float64], acc: NDArray[np.float64], stance: NDArray[np.bool_], *, first_whole: bool
    ) -> NDArray[np.bool_] | None:
        """The samples that get a zero-velocity update, of consecutive samples whose stances are
        all whole (each ends within them, or the recording ends): each stance without its edges
        (``zupt_edges``, ``zupt_start_delay_s``, ``zupt_end_advance_s``), the first one whole
        when ``first_whole`` (it aligns the filter); None when the update is the whole stance.
        The same rows give the same mask in any chunks of whole stances (a stream's, or the
        whole recording)."""
        if not self.trims_stances:
            return None
        mask = np.asarray(stance, dtype=bool)
        runs = runs_of(np.array(mask))  # compiled (a stream asks on every push); a copy: one signature
        trim = runs[1:] if first_whole else runs
        if len(trim) == 0 or len(t) < 2:
            return mask.copy()
        if self.zupt_edges == "settled":
            out = settled_mask(t, acc, trim, float(self.zupt_std_mps), float(self.zupt_edge_max_fraction))
            if first_whole and len(runs):
                out[runs[0, 0] : runs[0, 1]] = True
        else:
            out = mask.copy()
        if self.zupt_start_delay_s or self.zupt_end_advance_s:
            rate = 1.0 / float(np.median(np.diff(t)))
            n0, n1 = round(self.zupt_start_delay_s * rate), round(self.zupt_end_advance_s * rate)
            for a, b in trim:
                cap = int(self.zupt_edge_max_fraction * (b - a))
                out[a : a + min(n0, cap)] = False
                out[b - min(n1, cap) : b] = False
        return out

    def _align(self, imu: ImuData, stance: StanceResult):
        """First stance phase -> (start index, Alignment, meta), checks and warnings included."""
        s0, align, meta = align_first_stance(imu, stance, still_gyr_max_radps=self.still_gyr_max_radps, stacklevel=4)
        if self.gyro_bias == "initial-standstill":
            meta["gyro_bias_radps"] = align.gyro_bias_radps.tolist()
            # the bias estimate's standard error: the yaw-rate error the 9-state filter keeps
            meta["gyro_bias_sem_radps"] = standstill_rate_std(
                imu.gyr, align.start, align.stop, self.still_gyr_max_radps
            )
        return s0, align, meta

    def finish(self, filt: InsFilter, stances: Sequence[StanceResult]) -> list[FootTrajectory]:
        """Run ``filt`` (from :meth:`start`) to the end, smooth it as ``smoother`` says and return
        each foot's trajectory (:class:`footnav.core.component.StepableEstimator`)."""
        filt.run_until()
        smoothed = None if self.smoother == "none" else smooth(filt, self.smoother)
        return [self.trajectory(filt, foot, stance, smoothed) for foot, stance in enumerate(stances)]

    def trajectory(
        self,
        filt: InsFilter,
        foot: int,
        stance: StanceResult,
        smoothed: Smoothed | None = None,
        *,
        copy: bool = True,
        heading: bool = False,
    ) -> FootTrajectory:
        """Foot ``foot``'s result of a finished filter run.

        ``smoothed``: the output of :func:`footnav.estimators.ekf.smoother.smooth` for the run, or None for
        the forward filter. ``copy=False`` hands over the filter's (or smoother's) arrays, when
        the filter is not used again. ``heading``: turn the result so that its first step points
        along +x (:func:`footnav.nav.heading.turn_to_first_step`; in place when not copied).
        """
        q_out, vel, pos, pos_cov = filt.outputs(foot)
        fed = filt.samples(foot)
        # the swing's own rise (the floors' check of a stair): one foot's filter only, where the
        # forward height between two stances is the strapdown's (a joint filter's carries the
        # coupling's updates, and a coupled fusion's result has none, offline and online)
        swing = stance_swing_rises(swing_rises(pos[:, 2], fed.zupt)[0], stance.intervals) if filt.n_feet == 1 else None
        if smoothed is not None:
            sl = slice(filt.global_index(foot, 0), filt.global_index(foot, len(q_out) - 1) + 1)
            q_out, vel, pos = (x[sl] for x in smoothed)
        if copy:
            pos, vel, q_out = pos.copy(), vel.copy(), q_out.copy()
            pos_cov = pos_cov if self.heading_drift_in_std else pos_cov.copy()
        return self.package(
            fed.t,
            q_out,
            vel,
            pos,
            pos_cov,
            filt.start_index(foot),
            filt.meta[foot],
            stance.intervals,
            smoothed=smoothed is not None,
            heading=heading,
            biases=self.final_biases(filt, foot),
            swing_rise=swing,
        )

    def final_biases(self, filt: InsFilter, foot: int) -> tuple | None:
        """With bias states, the foot's accelerometer (m/s^2) and gyro (rad/s) biases now and
        their stds, for :meth:`package`; else None."""
        if not self.bias_states:
            return None
        cov = np.diag(filt.covariance)
        return (
            *filt.biases(foot),
            np.sqrt(cov[filt.block(foot, "acc_bias")]),
            np.sqrt(cov[filt.block(foot, "gyr_bias")]),
        )

    def package(
        self,
        t: NDArray[np.float64],
        q: NDArray[np.float64],
        vel: NDArray[np.float64],
        pos: NDArray[np.float64],
        pos_cov: NDArray[np.float64],
        start_index: int,
        filter_meta: dict,
        steps: NDArray[np.int64],
        *,
        smoothed: bool,
        heading: bool,
        biases: tuple | None = None,
        swing_rise: NDArray[np.float64] | None = None,
    ) -> FootTrajectory:
        """A foot's :class:`FootTrajectory` from its per-sample estimate (the arrays are taken,
        turned in place with ``heading``): ``pos_cov`` the forward filter's position covariance
        (xx, xy, yy, zz, m^2), ``start_index`` where the filter started, ``filter_meta`` the
        alignment's notes, ``steps`` the stance intervals, ``biases`` (15 states) the final
        accelerometer and gyro biases and their stds, ``swing_rise`` the swing's own rise before
        each stance (:func:`footnav.nav.floors.stance_swing_rises`). Used by :meth:`trajectory` and by online
        mode (:mod:`footnav.pipeline.online`), which keeps the arrays itself."""
        meta = {"estimator": self.describe(), **filter_meta, "smoother": self.smoother if smoothed else "none"}
        if biases is not None:
            ba, bg, ba_std, bg_std = biases
            meta["acc_bias_mps2"], meta["gyr_bias_radps"] = np.asarray(ba).tolist(), np.asarray(bg).tolist()
            meta["acc_bias_std_mps2"], meta["gyr_bias_std_radps"] = (
                np.asarray(ba_std).tolist(),
                np.asarray(bg_std).tolist(),
            )
        # the smoothed covariance is at most the filtered one: std is the forward filter's, plus
        # the heading drift it does not model (a new array: the filter's own stays as it is)
        if self.heading_drift_in_std:
            nine = self.n_states == 9  # 15 states carry their gyro bias: the scale error only
            bias_std = self.init_gyr_bias_std_radps or TURN_ON_BIAS_STD_RADPS
            rate_std = filter_meta.get("gyro_bias_sem_radps", bias_std) if nine else 0.0
            walk = self.yaw_bias_walk_radps2_sqrthz if nine else 0.0
            pos_cov = with_heading_drift(pos_cov, t, vel, q, start_index, rate_std, walk, self.gyro_scale_std, meta)
        if heading:
            pos, vel, q, std = turn_to_first_step(pos, vel, q, pos_cov, steps, meta)
        else:
            std = np.sqrt(np.maximum(pos_cov[:, [0, 2, 3]], 0.0))
        return FootTrajectory(
            t=t,
            position=pos,
            velocity=vel,
            quaternion=q,
            position_std=std,
            steps=steps,
            meta=meta,
            swing_rise_m=swing_rise,
        )

    # -- the estimator ---------------------------------------------------------------------------
    def estimate(self, imu: ImuData, stance: StanceResult) -> FootTrajectory:
        """Estimate the foot's trajectory from its IMU data and stance phases.

        Parameters
        ----------
        imu
            The foot's recording (body frame, SI).
        stance
            Stance mask aligned with ``imu``; its first stance phase aligns the filter.

        Returns
        -------
        FootTrajectory
            Nav-frame (z up) trajectory, starting at the origin.
        """
        t0 = time.perf_counter()
        filt = self.start([imu], [stance])
        if self.closed_loop:
            steps = stance.intervals
            last = int(steps[-1, 1]) - 1  # last sample of the final standstill
            filt.run_until(imu.t[last])
            filt.update_position(0, np.zeros(3), self.closed_loop_std_m)
        filt.run_until()
        smoothed = None if self.smoother == "none" else smooth(filt, self.smoother)
        traj = self.trajectory(filt, 0, stance, smoothed, copy=False, heading=self.heading == "first-step")
        meta = cast("dict[str, Any]", traj.meta)  # FootTrajectory holds its meta as a dict
        if self.closed_loop:
            meta["closed_loop"] = {"index": last, "std_m": self.closed_loop_std_m}
        meta["runtime_s"] = time.perf_counter() - t0
        return traj
