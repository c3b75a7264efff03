"""A two-foot walking simulator: foot-mounted IMU signals with exact truth.

The walker follows a centre line made of straight lines and circular arcs. Footprints are placed
alternately on both sides of it (``step_width_m`` apart, heading along the line), and each foot
moves from one footprint to its next through a smooth analytic gait cycle:

``stance`` (foot flat, zero velocity and angular rate) -> ``heel_off`` (the heel rises, the foot
pitches toe-down about the toe) -> ``swing`` (airborne: the foot moves forward, lifts and pitches
from toe-down to toe-up while turning to its new heading) -> ``foot_flat`` (the heel has struck
with the toe up; the foot rotates flat about the heel) -> ``stance``.

The foot is a rigid body. Its pose is written ``p(t) = X(t) - C(t) c(t)``: ``c`` is a body-frame
contact point (the toe during heel-off, the heel during foot-flat, moving smoothly from toe to heel
while airborne) and ``X`` its nav-frame position (fixed while the foot pivots on it). ``X``, ``c``,
the pitch and the heading are quintic polynomials in time with matched position, rate and
acceleration at every phase boundary, so position, velocity, acceleration, orientation and
angular rate are continuous, and the IMU signals follow analytically from them (no numerical
differentiation).

Frames: nav is footnav's (z up, x the initial walking direction, origin midway between the feet at
the start); the foot frame is x forward, y left, z up, its origin at the sensor, which sits
``_SENSOR_HEIGHT_M`` above the ground so that the sensor's nav z is 0 in stance.
"""

from __future__ import annotations

import math
from dataclasses import replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from footnav.core.types import FootTruth, ImuData, Recording
from footnav.data.simulate.foot import _HEEL_B, _SENSOR_HEIGHT_M, _TOE_B, _foot_motion, _heel_strike_impact
from footnav.data.simulate.gait import _STANCE, PHASE_NAMES, _plan
from footnav.data.simulate.magnetometer import magnetometer
from footnav.data.simulate.options import _COMMON_DEFAULTS as _COMMON_DEFAULTS  # read by tests/faults
from footnav.data.simulate.options import _NOISE_KEYS, SCENARIOS, _fail, _resolve_options
from footnav.data.simulate.options import _SCENARIO_DEFAULTS as _SCENARIO_DEFAULTS  # read by tests/faults
from footnav.data.simulate.path import _centre_line
from footnav.data.simulate.sensor import _mirrored_yaw_rate, _sensor_clock, _sensor_errors
from footnav.nav import quaternion as quat

__all__ = ["simulate", "SCENARIOS", "PHASE_NAMES"]

# A closed walk ends within this distance of its start (m); the geometry is exact up to rounding.
_CLOSED_LOOP_TOL_M = 1e-6


def _nearest_index(times: NDArray, rate_hz: float, n: int) -> NDArray[np.int64]:
    return np.clip(np.rint(times * rate_hz), 0, n - 1).astype(np.int64)


def _scaled(signal: NDArray[np.float64], error: tuple[float, float, float]) -> NDArray[np.float64]:
    """``signal`` (N, 3) read by axes with scale-factor errors ``error``; unchanged when all are 0."""
    return signal * (1.0 + np.asarray(error)) if any(error) else signal


def simulate(scenario: str = "straight", *, seed: int = 0, rate_hz: float = 100.0, **options: Any) -> Recording:
    """Simulate a walk with a foot-mounted IMU on each foot, with exact truth.

    Parameters
    ----------
    scenario
        ``"straight"``, ``"rectangle"`` or ``"path"`` (see Other Parameters for their options).
    seed
        Seed of ``numpy.random.default_rng``; each foot's sensor draws from its own child
        generator, so the same seed gives identical recordings. Only the sensor errors are
        random; the walk itself depends on the options alone.
    rate_hz
        Sampling rate of IMU and truth in Hz; samples at ``t = k / rate_hz`` s from 0.
    **options
        Scenario and walker options below; an unknown name raises InvalidParameterError.

    Other Parameters
    ----------------
    distance_m : float, default 100.0
        ``"straight"``: distance walked along +x in m.
    width_m : float, default 105.0
        ``"rectangle"``: side along x in m. The walk starts in the middle of this side (the
        feet side by side at x = 0), goes round the rectangle and stops where it started, with
        the same heading and footprints; the corners are arcs of ``turn_radius_m``.
    height_m : float, default 68.0
        ``"rectangle"``: side along y in m.
    direction : {"ccw", "cw"}, default "ccw"
        ``"rectangle"``: counter-clockwise (left turns, rectangle at y >= 0) or clockwise (right
        turns, rectangle at y <= 0).
    segments : sequence of (float, float) or ("stairs", int, float[, float])
        ``"path"`` (required): ``(distance_m, turn_deg)`` pairs: walk ``distance_m`` m straight,
        then turn by ``turn_deg`` deg (positive = left/CCW) along an arc of ``turn_radius_m``.
        ``("stairs", n_steps, rise_m)`` or ``("stairs", n_steps, rise_m, tread_m)``: a straight
        flight of ``n_steps`` stairs (1-10000), each ``rise_m`` higher (negative: down; at most
        0.5 m) and ``tread_m`` deep (default 0.3 m, 0.25-10 m: the whole foot fits, the
        footprint in the middle of the tread). Both feet climb step over step, one tread per
        footfall, so each swing between treads climbs two risers; the swing is the level
        swing's profile with the contact point's height blended from tread to tread (not a
        model of stair gait). The truth's z follows: after the flight the height has changed by
        exactly ``n_steps * rise_m`` (``meta["height_change_m"]``, the flights in
        ``meta["stairs"]``); level walking between flights is stepped as without stairs. A walk
        with stairs is closed only if it ends at its start height.
    stride_length_m : float, default 1.4
        Nominal distance between successive footprints of one foot in m (twice the step
        length). Adjusted slightly so a whole number of steps covers the path (the value used
        is in ``meta["stride_length_m_actual"]``).
    stride_period_s : float, default 1.1
        Duration of one stride (one foot's full gait cycle) in s; the feet are half a period
        apart. Cadence is ``2 / stride_period_s`` steps/s.
    step_width_m : float, default 0.2
        Lateral distance between the feet in m; the left foot walks ``step_width_m / 2`` left of
        the centre line.
    standstill_s : float, default 2.0
        Standstill with both feet flat before the first and after the last step, in s.
    turn_radius_m : float, default 1.5
        Radius of the centre line in turns in m; a 90 deg turn takes about three steps.
    foot_lift_m : float, default 0.12
        Peak lift of the foot's moving contact point (toe to heel) above the ground in swing,
        in m; the sensor rises about as high.
    heel_off_s, swing_s, foot_flat_s : float, default 0.1, 0.45, 0.1
        Durations in s of heel-off (heel rises, foot pivots on the toe), swing (airborne, toe-off
        to heel strike) and foot-flat (foot rotates flat about the heel). The rest of the stride
        is flat-foot stance. Needs ``swing_s + max(heel_off_s, foot_flat_s) <= stride_period_s/2``.
        With the defaults ``heel_off_s + swing_s = stride_period_s / 2``: the rear foot's heel
        rises as the front foot's heel strikes (Zhao et al. (2019), Sec. III-A), swing is 41 % of the
        stride and each double support 0.1 s (9 %), as in normal walking.
    swing_scale : sequence of float or None, default None
        Per-swing variability (None: off, every swing alike): factors in [0.05, 3], cycled over
        each foot's swings in order (the foot's 1st swing takes the 1st factor, ...), each
        scaling that swing's whole pitch profile (heel-off, swing and foot-flat, so its angular
        rate) and its ``foot_lift_m``; footprints and timing do not change. ``(1.0, 0.2)``
        gives each foot a normal swing, then a flat shuffle, and so on.
    toe_off_pitch_deg : float, default 30.0
        Toe-down pitch of the foot at toe-off in deg.
    heel_strike_pitch_deg : float, default 20.0
        Toe-up pitch of the foot at heel strike in deg.
    heel_strike_impact_mps2 : float, default 40.0
        Peak of the heel-strike impact transient in m/s^2 (0 turns it off): a Ricker wavelet
        ``A (1 - u^2) exp(-u^2 / 2)``, ``u = (t - t_hs) / heel_strike_impact_s``, added to the
        specific force along the foot's z axis (sole normal) at each heel strike. It models the
        shoe and soft-tissue vibration the sensor feels, not a motion of the rigid foot: its
        integral and that of its integral are zero, so it leaves velocity and position unchanged
        after the pulse (the truth includes the 4 mm dip; ``truth.meta["acc_impact_mps2"]``
        holds the transient's specific force, sensor frame). Needs ``6 heel_strike_impact_s <=
        min(swing_s, foot_flat_s)``: the pulse stays between toe-off and stance.
    heel_strike_impact_s : float, default 0.01
        Width (sigma) of the impact wavelet in s; the transient lasts about 6 sigma (+-3 sigma).
    clock_offset_s : float, default 0.0
        Offset of the right sensor's clock in s: its time stamps are
        ``t_imu = (1 + clock_drift_ppm 1e-6) t + clock_offset_s`` for true time t. The left
        sensor's clock and both truths stay on true time. With any clock option set, the
        recording's ``meta["clock"]`` (and ``truth_right.meta["clock"]``) holds the map back,
        ``t = a t_imu + b`` (``a = 1 / (1 + drift 1e-6)``, ``b = -offset a``), with ``foot``,
        ``offset_s`` and ``drift_ppm``; ``right.meta["time_base"]`` says the times are the
        sensor's own.
    clock_drift_ppm : float, default 0.0
        Rate error of the right sensor's clock in ppm, in (-1e5, 1e5); positive: it runs fast.
        Here it is constant; Chistyakov et al. (2021), Sec. 5B notes that a cheap IMU's clock rate changes
        during a recording, which is why it synchronises at both ends rather than once.
    clock_exchanges : int, default 0
        Number of message exchanges between a master on true time and the right sensor, as
        Chistyakov et al. (2021), Sec. 5B logs them (0: none, else >= 2): half evenly spread over the first
        10 s and half over the last 10 s of the walk (thirds of shorter walks). Each is
        ``[TM1, TI, TM2]``: request sent at TM1 (master), stamped at TI (sensor clock) after the
        up delay, reply received at TM2 after the down delay; in ``meta["clock_exchanges"]`` as
        ``{"tm1", "ti", "tm2"}`` arrays (s). The delays come from their own child generator of
        ``seed``, so the sensor data are the same with and without exchanges.
    exchange_delay_s : float, default 0.02
        Fixed part of each one-way delay of the exchanges, s (the same up and down: the
        symmetric latency the midpoint of Chistyakov et al. (2021)'s LPs cancels).
    exchange_jitter_s : float, default 0.02
        Mean of the exponential random part added to each one-way delay, s (0: none).
        Exchanges pin the clock map through their shortest delays: with the defaults, 200
        exchanges give < 1 ms over a 10 min walk, 60 exchanges 0.4 ms typically but > 1 ms in
        about one walk in ten.
    mounting_rpy_deg : (float, float, float), default (0, 0, 0)
        Orientation of the sensor on the foot as ZYX roll, pitch, yaw in deg (sensor -> foot);
        zero: sensor axes = foot axes (x forward, y left, z up).
    noise : bool, default True
        Add sensor errors. False gives the exact noise-free signals.
    gyr_noise_density_radps_sqrthz : float, default 1.7e-4
        Gyroscope white-noise density in rad/s/sqrt(Hz); per-sample std is density * sqrt(rate_hz).
    acc_noise_density_mps2_sqrthz : float, default 1.0e-3
        Accelerometer white-noise density in m/s^2/sqrt(Hz).
    gyr_bias_std_radps : float, default 2.0e-3
        Std of the gyroscope turn-on bias per axis in rad/s.
    acc_bias_std_mps2 : float, default 2.0e-2
        Std of the accelerometer turn-on bias per axis in m/s^2.
    gyr_bias_walk_radps2_sqrthz : float, default 1.0e-5
        Gyroscope bias random walk in rad/s^2/sqrt(Hz) (rad/s per sqrt(s)).
    acc_bias_walk_mps3_sqrthz : float, default 1.0e-4
        Accelerometer bias random walk in m/s^3/sqrt(Hz) (m/s^2 per sqrt(s)).
    magnetometer : bool, default False
        Record a magnetometer on each foot (``ImuData.mag``, uT, sensor frame): Earth's field
        through the sensor's true attitude, plus the disturbances, a hard-iron offset and white
        noise (both only with ``noise``), from their own child generator of ``seed`` (the other
        signals are the same with or without it). Drawn values in
        ``truth.meta["magnetometer"]``.
    mag_field_ut : float, default 50.0
        Earth's field strength, uT.
    mag_dip_deg : float, default 60.0
        Inclination below the horizontal, deg in [-90, 90] (mid latitudes north: 60-70).
    mag_north_deg : float, default 30.0
        Direction of the field's horizontal part in the nav frame, deg from +x (the nav frame's
        x is the first step's direction, not north).
    mag_noise_ut : float, default 0.5
        White noise per sample and axis, uT.
    mag_hard_iron_ut : float, default 1.0
        Std per axis of a constant sensor-frame offset (hard iron left after calibration), uT.
    mag_disturbances : sequence of (x_m, y_m, radius_m, bx_ut, by_ut, bz_ut), default ()
        Local disturbances (steel, electronics): within ``radius_m`` (horizontal) of ``(x_m,
        y_m)`` the nav-frame field ``(bx, by, bz)`` uT adds to Earth's.
    gyr_scale_error, acc_scale_error : float or (3,) floats, default 0.0
        Scale-factor error of the gyroscope / accelerometer, a fraction per sensor axis (one value
        for all three, or three), each in [-0.2, 0.2]: the sensor reads ``(1 + k)`` times the true
        rate / specific force on that axis, before bias and noise. A gyro's ``k`` turns every turn
        of the walk by ``k`` of its angle (0.01: 1.8 deg per U-turn); an accelerometer's scales the
        specific force, gravity included. Consumer MEMS: up to 0.01-0.03 uncalibrated.
    mirrored_yaw_rate_radps : float, default 0.0
        The systematic, mirror-symmetric heading drift of the two feet (Lee, Cho & Park (2022),
        Sec. 2.1; Nilsson et al. 2012's "systematic drift"), in rad/s, within [-1, 1]: while a
        foot is off the ground (any sample outside flat-foot stance) its gyroscope reads an extra
        rate ``+b`` (left foot) or ``-b`` (right foot) about the nav vertical, ``b`` this value,
        expressed in the sensor frame (``b C^T e_z``, through the mounting); stance samples read
        exactly as without it. Integrated, each foot's attitude is the truth turned about the
        vertical by ``+-b`` times the time it has spent moving, so its heading (and with it the
        direction of every stride) drifts at ``b (1 - stance fraction)`` on average, the left
        foot's one way and the right's the other: positive ``b`` turns the left foot's track left
        and the right foot's right (the tracks diverge), negative ``b`` the reverse (they cross);
        the midpoint's heading does not drift. Typical: 2e-4 to 1e-3 rad/s; 4.4e-4 gives about
        0.5 m of lateral error per foot after 70 m straight, the paper's standalone figure
        (Table 2).

        Why this form. Sec. 2.1 finds that both shoes' position errors "drift symmetrically in
        the lateral direction", the left shoe to -Y and the right to +Y of the walking
        direction (Fig. 1), after the gyro bias was estimated and removed at a standstill. It
        attributes the cause, after Lee, Cho & Park (2020), to the IMU's sampling frequency
        during the motion: "yaw and lateral velocity errors occur due to low sampling
        frequency, and this has a symmetrical characteristic" (the swing's rotations, not
        commuting, are integrated at 100 Hz; the two feet's swings are mirror images, so are
        their errors). A yaw-rate error that exists only while the foot moves is that error in
        its simplest form: a standstill's bias estimate does not see it (footnav's estimators,
        like the paper, take the gyro bias from the first standstill), ZUPTs do not observe
        it, and it is mirrored between the feet. The paper does not say which side Y is on, so
        the sign is left to the caller. It is deterministic (the same in every stride); the
        spread around it (Fig. 2) comes from the sensor noise options. The exact IMU signals
        without it are ``truth.meta["gyr_true_radps"]``; the added rate is
        ``truth.meta["gyr_mirrored_yaw_radps"]``.
    stance_twist_deg : float, default 0.0
        The shoe's twist about the leg in stance, deg within [-20, 20]: through each flat-foot
        stance that lies between two swings the foot turns by ``+a`` (left) or ``-a`` (right)
        about the vertical through its sensor (min-jerk, from foot-flat to heel-off), and the
        next swing turns it back to its next footprint's heading; the standstills at both ends
        stay still. The gyro reads the turn and the truth's orientation follows it; position and
        specific force do not change. Real feet twist at a median 1-17 deg/s through the part of
        the stance a ZUPT filter updates, left and right in opposite senses (docs/heading.md),
        about 0.5-3 deg a stance: a zero-angular-rate update in walking stances takes it for
        gyro bias.

    Returns
    -------
    Recording
        ``left`` / ``right``: :class:`ImuData` in the sensor frame (specific force in m/s^2, +g
        up at rest; angular rate in rad/s). ``truth_left`` / ``truth_right``: :class:`FootTruth` in
        footnav's nav frame (z up, x the initial walking direction, origin midway between the
        feet at the start, the sensors at z = 0 when flat): the sensor's position, velocity and
        orientation (body -> nav) at the IMU's times, the stance mask (True exactly where the
        foot is flat: its velocity is zero, and its angular rate but for ``stance_twist_deg``),
        gait events (sample indices nearest to each stride's ``heel_strike``, ``foot_flat``,
        ``heel_off``, ``toe_off``) and ``closed_loop``.
        Truth ``meta`` holds the scenario, the options used, the seed, the noise parameters, the
        sensor errors drawn (``"biases"``: turn-on biases and the bias time series), per-sample
        gait ``"phases"`` (names in ``"phase_names"``) and ``stance_source="simulator"``.

    Raises
    ------
    InvalidParameterError
        Unknown scenario or option, or an invalid value; the message names the option and lists
        the valid ones or the expected range.

    Examples
    --------
    >>> rec = simulate("rectangle", width_m=20.0, height_m=10.0, noise=False)
    >>> rec.truth_left.closed_loop
    True
    """
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        # numpy's generators refuse negative seeds with a message that does not name the option
        raise _fail("seed", seed, "an integer >= 0")
    opts = _resolve_options(scenario, rate_hz, options)
    rate_hz = float(rate_hz)
    line, line_info = _centre_line(scenario, opts)
    swings, plan_info = _plan(line, opts, line_info.get("stairs", ()))
    # the last sample at or before the end; 1e-9 keeps 8.7 s x 400 Hz = 3479.9999... from losing it
    n = int(math.floor(plan_info["duration_s"] * rate_hz + 1e-9)) + 1
    t = np.arange(n) / rate_hz

    end_xy, _ = line(np.array([line.length_m]))
    closed = scenario == "rectangle" or bool(
        np.linalg.norm(end_xy[0]) < _CLOSED_LOOP_TOL_M
        and abs(plan_info.get("height_change_m", 0.0)) < _CLOSED_LOOP_TOL_M
    )
    mount_q = quat.from_euler(*np.radians(opts["mounting_rpy_deg"]))
    mount_t = quat.as_matrix(mount_q).T  # foot -> sensor
    noise_params = {k: opts[k] for k in _NOISE_KEYS} | {"noise": opts["noise"]}
    common_meta = {"scenario": scenario, "options": dict(opts), "seed": seed, "rate_hz": rate_hz}

    rng_left, rng_right = np.random.default_rng(seed).spawn(2)
    # the magnetometer's own children of the seed: the other signals are the same with or without it
    rng_mag = dict(zip(("left", "right"), np.random.default_rng(seed).spawn(4)[3].spawn(2)))
    imus: dict[str, ImuData] = {}
    truths: dict[str, FootTruth] = {}
    biases_all: dict[str, dict[str, Any]] = {}
    for foot, rng in (("left", rng_left), ("right", rng_right)):
        sw = swings[foot]
        motion = _foot_motion(t, sw, opts, math.radians(opts["stance_twist_deg"]) * (1.0 if foot == "left" else -1.0))
        errors = _sensor_errors(rng, n, rate_hz, opts)
        # The impact moves the sensor along nav z; the foot frame sees it through C^T e_z.
        imp_p, imp_v, imp_a = _heel_strike_impact(t, sw.t_heel_strike, opts)
        impact_foot = imp_a[:, None] * quat.as_matrix(motion.quaternion)[:, 2, :]
        motion.position[:, 2] += imp_p
        motion.velocity[:, 2] += imp_v
        impact = impact_foot @ mount_t.T
        gyr_true = motion.gyr @ mount_t.T
        acc_true = (motion.acc + impact_foot) @ mount_t.T
        gyr = _scaled(gyr_true, opts["gyr_scale_error"]) + errors["gyr_radps"] + errors["gyr_white"]
        mirrored = (
            _mirrored_yaw_rate(motion, opts["mirrored_yaw_rate_radps"] * (1.0 if foot == "left" else -1.0)) @ mount_t.T
        )
        if opts["mirrored_yaw_rate_radps"] != 0.0:  # off: the signals stay bit-identical
            gyr = gyr + mirrored
        acc = _scaled(acc_true, opts["acc_scale_error"]) + errors["acc_mps2"] + errors["acc_white"]
        biases = {k: errors[k] for k in ("gyr_turn_on_radps", "acc_turn_on_mps2", "gyr_radps", "acc_mps2")}
        biases_all[foot] = {k: biases[k] for k in ("gyr_turn_on_radps", "acc_turn_on_mps2")}
        q_sensor = quat.multiply(motion.quaternion, mount_q)
        mag, mag_meta = (
            magnetometer(rng_mag[foot], motion.position, q_sensor, opts) if opts["magnetometer"] else (None, {})
        )
        imus[foot] = ImuData(
            t=t,
            acc=acc,
            gyr=gyr,
            mag=mag,
            meta={"source": "simulator", "scenario": scenario, "foot": foot, "seed": seed, "rate_hz": rate_hz},
        )
        events = {
            "heel_strike": _nearest_index(sw.t_heel_strike, rate_hz, n),
            "foot_flat": _nearest_index(sw.t_foot_flat, rate_hz, n),
            "heel_off": _nearest_index(sw.t_heel_off, rate_hz, n),
            "toe_off": _nearest_index(sw.t_toe_off, rate_hz, n),
        }
        truths[foot] = FootTruth(
            t=t,
            position=motion.position,
            quaternion=q_sensor,
            velocity=motion.velocity,
            stance=motion.phase == _STANCE,
            events=events,
            closed_loop=closed,
            frame="nav",
            meta={
                **common_meta,
                "foot": foot,
                "noise_params": noise_params,
                "biases": biases,
                "stance_source": "simulator",
                "phases": motion.phase,
                "phase_names": PHASE_NAMES,
                "event_times_s": {
                    "heel_strike": sw.t_heel_strike,
                    "foot_flat": sw.t_foot_flat,
                    "heel_off": sw.t_heel_off,
                    "toe_off": sw.t_toe_off,
                },
                "foot_geometry_m": {"heel": _HEEL_B.copy(), "toe": _TOE_B.copy(), "sensor_height": _SENSOR_HEIGHT_M},
                "gyr_true_radps": gyr_true,
                "acc_true_mps2": acc_true,
                "acc_impact_mps2": impact,
                "gyr_mirrored_yaw_radps": mirrored,
                **({"magnetometer": mag_meta} if mag_meta else {}),
                **plan_info,
                **line_info,
            },
        )
    t_right, clock_meta = _sensor_clock(t, seed, opts)
    if t_right is not None:
        imus["right"] = ImuData(
            t=t_right,
            acc=imus["right"].acc,
            gyr=imus["right"].gyr,
            mag=imus["right"].mag,
            meta={**imus["right"].meta, "time_base": "sensor clock (offset and drift: the recording's meta['clock'])"},
        )
        truths["right"] = replace(truths["right"], meta={**truths["right"].meta, "clock": clock_meta["clock"]})
    return Recording(
        left=imus["left"],
        right=imus["right"],
        truth_left=truths["left"],
        truth_right=truths["right"],
        name=f"sim-{scenario}",
        meta={
            **common_meta,
            "source": "simulator",
            "noise_params": noise_params,
            "biases": biases_all,
            "stance_source": "simulator",
            **plan_info,
            **line_info,
            **clock_meta,
        },
    )
