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

import difflib
import math
from dataclasses import dataclass, replace
from numbers import Real
from typing import Any, Mapping, Sequence

import numpy as np
from numpy.typing import NDArray

from footnav.core import quaternion as quat
from footnav.core.errors import InvalidParameterError
from footnav.core.types import GRAVITY_MPS2, FootTruth, ImuData, Recording

__all__ = ["simulate", "SCENARIOS", "PHASE_NAMES"]

#: Scenario names accepted by :func:`simulate`.
SCENARIOS = ("straight", "rectangle", "path")

#: Names of the per-sample gait phase labels in ``FootTruth.meta["phases"]``.
PHASE_NAMES = ("stance", "heel_off", "swing", "foot_flat")
_STANCE, _HEEL_OFF, _SWING, _FOOT_FLAT = range(len(PHASE_NAMES))

# Foot geometry in the foot frame (origin at the sensor on the instep, x forward, z up): the heel
# contact point and the toe pivot (metatarsal heads), about 0.22 m apart as on an adult foot.
_SENSOR_HEIGHT_M = 0.06
_HEEL_B = np.array([-0.10, 0.0, -_SENSOR_HEIGHT_M])
_TOE_B = np.array([0.12, 0.0, -_SENSOR_HEIGHT_M])

# Pitch rate at toe-off and at heel strike as a fraction of the mean rate of the neighbouring
# pivot phase: the foot is still rotating toe-down when it leaves the ground and already rotating
# toe-down when the heel lands, so no instant of the swing has zero velocity.
_TOE_OFF_RATE_FRACTION = 0.5
_HEEL_STRIKE_RATE_FRACTION = 0.5

# The lift bump 64 u^3 (1-u)^3 peaks at 1 for u = 1/2 and is flat to second order at both ends.
_BUMP_GAIN = 64.0

# Samples this close to heel-off or foot-flat are taken as stance: the profiles are at rest there
# to second order, so the motion this ignores is ~1e-15 m/s.
_EVENT_TIME_TOL_S = 1e-9

# The heel-strike impact wavelet is cut this many sigma from its centre.
_IMPACT_CUT = 6.0

# A closed walk ends within this distance of its start (m); the geometry is exact up to rounding.
_CLOSED_LOOP_TOL_M = 1e-6

# Stairs: a tread deep enough for the whole foot (heel 0.10 m behind the sensor, toe 0.12 m ahead
# of it) with the footprint in the middle of the tread, up to 10 m (a landing); risers up to
# 0.5 m, above any building code's 0.15-0.22 m but still one step.
_TREAD_DEFAULT_M = 0.3
_TREAD_RANGE_M = (0.25, 10.0)
_MAX_RISE_M = 0.5
_MAX_STAIRS = 10_000

_COMMON_DEFAULTS: dict[str, Any] = {
    "stride_length_m": 1.4,
    "stride_period_s": 1.1,
    "step_width_m": 0.2,
    "standstill_s": 2.0,
    "turn_radius_m": 1.5,
    "foot_lift_m": 0.12,
    "heel_off_s": 0.1,
    "swing_s": 0.45,
    "foot_flat_s": 0.1,
    "toe_off_pitch_deg": 30.0,
    "heel_strike_pitch_deg": 20.0,
    # Heel-strike impact: 4 g peak, sigma 10 ms (a 20-40 ms transient), so the sole compresses by
    # A sigma^2 = 4 mm. Heel- and instep-mounted IMUs read 3-5 g spikes at initial contact
    # (gaitmap example at 204.8 Hz), above the 3-4 g of the foot's deceleration late in swing.
    "heel_strike_impact_mps2": 40.0,
    "heel_strike_impact_s": 0.01,
    "mounting_rpy_deg": (0.0, 0.0, 0.0),
    "noise": True,
    # The right sensor's own clock against true time (the left's is true time), and the
    # message exchanges a master would log for Chistyakov et al. (2021)'s clock synchronisation.
    "clock_offset_s": 0.0,
    "clock_drift_ppm": 0.0,
    "clock_exchanges": 0,
    "exchange_delay_s": 0.02,
    "exchange_jitter_s": 0.02,
    # Consumer/industrial MEMS grade (BMI160 / MPU-9250 / MTi-3 class): ~0.01 deg/s/sqrt(Hz) and
    # ~100 ug/sqrt(Hz) white noise, ~0.1 deg/s and ~2 mg turn-on bias after factory calibration.
    "gyr_noise_density_radps_sqrthz": 1.7e-4,
    "acc_noise_density_mps2_sqrthz": 1.0e-3,
    "gyr_bias_std_radps": 2.0e-3,
    "acc_bias_std_mps2": 2.0e-2,
    "gyr_bias_walk_radps2_sqrthz": 1.0e-5,
    "acc_bias_walk_mps3_sqrthz": 1.0e-4,
    # The left/right mirror-symmetric heading drift of Lee, Cho & Park (2022), Sec. 2.1 (off).
    "mirrored_yaw_rate_radps": 0.0,
    # Per-swing factors on the pitch angles and the lift, cycled over each foot's swings (off).
    "swing_scale": None,
}

_NOISE_KEYS = (
    "gyr_noise_density_radps_sqrthz",
    "acc_noise_density_mps2_sqrthz",
    "gyr_bias_std_radps",
    "acc_bias_std_mps2",
    "gyr_bias_walk_radps2_sqrthz",
    "acc_bias_walk_mps3_sqrthz",
)

_SCENARIO_DEFAULTS: dict[str, dict[str, Any]] = {
    "straight": {"distance_m": 100.0},
    "rectangle": {"width_m": 105.0, "height_m": 68.0, "direction": "ccw"},
    "path": {"segments": None},
}

_DIRECTIONS = ("ccw", "cw")


# -- option handling ----------------------------------------------------------------------------


# Upper bounds of the options (docs/reliability.md): far above any walk or sensor that makes sense,
# far below where a value exhausts memory or time or overflows. The simulator holds about 1 KB
# per sample of both feet at its peak (truth, sensor errors and their intermediates), so
# _MAX_SAMPLES (5.5 h at 100 Hz, 33 min at 1 kHz) peaks near 2 GB; rate_hz=2e5 with the default
# 100 m asked for 17 million samples per foot.
_MAX_RATE_HZ = 10_000.0
_MAX_SAMPLES = 2_000_000
_MAX_LENGTH_M = 1e6  # distance_m, width_m, height_m, segment lengths: before the sample budget
_MAX_DURATION_S = 60.0  # stride_period_s and its phases, exchange delays
_MAX_NOISE = 1e3  # noise densities, bias stds and walks in their units: squared, 1e308 overflows


def _fail(name: str, value: Any, expected: str) -> InvalidParameterError:
    return InvalidParameterError(f"simulate(): option {name}={value!r} is invalid; expected {expected}")


def _number(opts: dict[str, Any], name: str) -> float:
    value = opts[name]
    if isinstance(value, bool) or not isinstance(value, Real) or not math.isfinite(float(value)):
        raise _fail(name, value, "a finite number")
    return float(value)


def _positive(opts: dict[str, Any], name: str, high: float = math.inf) -> float:
    value = _number(opts, name)
    if not 0 < value <= high:
        raise _fail(name, opts[name], "a number > 0" if high == math.inf else f"a number in (0, {high:g}]")
    return value


def _non_negative(opts: dict[str, Any], name: str, high: float = math.inf) -> float:
    value = _number(opts, name)
    if not 0 <= value <= high:
        raise _fail(name, opts[name], "a number >= 0" if high == math.inf else f"a number in [0, {high:g}]")
    return value


def _walk_length_m(scenario: str, opts: Mapping[str, Any]) -> float:
    """Length of the centre line, m (turns as arcs of turn_radius_m), for the sample budget."""
    if scenario == "straight":
        return opts["distance_m"]
    if scenario == "rectangle":
        return 2 * (opts["width_m"] + opts["height_m"])
    total = 0.0
    for seg in opts["segments"]:
        if seg[0] == "stairs":
            total += seg[1] * seg[3]
        else:
            total += seg[0] + math.radians(abs(seg[1])) * opts["turn_radius_m"]
    return total


def _resolve_options(scenario: Any, rate_hz: Any, options: Mapping[str, Any]) -> dict[str, Any]:
    """Defaults merged with ``options``, every value checked; raises InvalidParameterError."""
    if scenario not in _SCENARIO_DEFAULTS:
        raise InvalidParameterError(
            f"simulate(): unknown scenario {scenario!r}; valid scenarios: {', '.join(SCENARIOS)}"
        )
    if isinstance(rate_hz, bool) or not isinstance(rate_hz, Real) or not (0 < rate_hz <= _MAX_RATE_HZ):
        raise _fail("rate_hz", rate_hz, f"a number in (0, {_MAX_RATE_HZ:g}] Hz: above any foot-mounted IMU's rate")
    valid = {**_SCENARIO_DEFAULTS[scenario], **_COMMON_DEFAULTS}
    unknown = [k for k in options if k not in valid]
    if unknown:
        hints = []
        for k in unknown:
            close = difflib.get_close_matches(k, list(valid), n=1)
            hints.append(f"{k!r}" + (f" (did you mean {close[0]!r}?)" if close else ""))
        raise InvalidParameterError(
            f"simulate(): scenario {scenario!r} has no option {', '.join(hints)}; "
            f"valid options: {', '.join(sorted(valid))}"
        )
    opts = {**valid, **options}

    for name in ("stride_period_s", "heel_off_s", "swing_s", "foot_flat_s", "heel_strike_impact_s"):
        opts[name] = _positive(opts, name, _MAX_DURATION_S)
    opts["stride_length_m"] = _positive(opts, "stride_length_m", 10.0)
    opts["foot_lift_m"] = _positive(opts, "foot_lift_m", 10.0)
    opts["turn_radius_m"] = _positive(opts, "turn_radius_m", 1e4)
    opts["clock_offset_s"] = _number(opts, "clock_offset_s")
    if not abs(opts["clock_offset_s"]) <= 1e10:  # Unix times (1.7e9 s) fit; beyond, t loses its ms
        raise _fail("clock_offset_s", opts["clock_offset_s"], "an offset in [-1e10, 1e10] s")
    drift = _number(opts, "clock_drift_ppm")
    if not -1e5 < drift < 1e5:
        raise _fail("clock_drift_ppm", opts["clock_drift_ppm"], "a rate error in (-1e5, 1e5) ppm")
    opts["clock_drift_ppm"] = drift
    n_ex = opts["clock_exchanges"]
    if isinstance(n_ex, bool) or not isinstance(n_ex, (int, np.integer)) or n_ex < 0 or n_ex == 1 or n_ex > 1_000_000:
        raise _fail("clock_exchanges", n_ex, "0 (none) or an integer >= 2 and <= 1000000")
    opts["exchange_delay_s"] = _non_negative(opts, "exchange_delay_s", _MAX_DURATION_S)
    opts["exchange_jitter_s"] = _non_negative(opts, "exchange_jitter_s", _MAX_DURATION_S)
    opts["step_width_m"] = _non_negative(opts, "step_width_m", 10.0)
    opts["standstill_s"] = _non_negative(opts, "standstill_s", 3600.0)
    opts["heel_strike_impact_mps2"] = _non_negative(opts, "heel_strike_impact_mps2", 1e3)
    opts["mirrored_yaw_rate_radps"] = _number(opts, "mirrored_yaw_rate_radps")
    if not abs(opts["mirrored_yaw_rate_radps"]) <= 1.0:
        raise _fail("mirrored_yaw_rate_radps", opts["mirrored_yaw_rate_radps"], "a rate in [-1, 1] rad/s")
    for name in _NOISE_KEYS:
        opts[name] = _non_negative(opts, name, _MAX_NOISE)
    for name in ("toe_off_pitch_deg", "heel_strike_pitch_deg"):
        value = _number(opts, name)
        if not 0 < value < 90:
            raise _fail(name, opts[name], "a pitch angle in (0, 90) deg")
        opts[name] = value
    if not isinstance(opts["noise"], (bool, np.bool_)):
        raise _fail("noise", opts["noise"], "True or False")
    opts["noise"] = bool(opts["noise"])
    if opts["swing_scale"] is not None:
        try:
            factors = () if isinstance(opts["swing_scale"], str) else tuple(float(f) for f in opts["swing_scale"])
        except (TypeError, ValueError):
            factors = ()
        # 0.05-3: a swing that still pitches and lifts, up to pitch angles below 90 deg
        if not factors or len(factors) > 10_000 or not all(0.05 <= f <= 3.0 for f in factors):
            raise _fail("swing_scale", opts["swing_scale"], "None or a non-empty sequence of factors in [0.05, 3]")
        if max(factors) * max(opts["toe_off_pitch_deg"], opts["heel_strike_pitch_deg"]) >= 90:
            raise _fail("swing_scale", opts["swing_scale"], "factors that keep the pitch angles below 90 deg")
        opts["swing_scale"] = factors
    try:
        rpy = tuple(float(a) for a in opts["mounting_rpy_deg"])
    except (TypeError, ValueError):
        rpy = ()
    if len(rpy) != 3 or not all(abs(a) <= 360 for a in rpy):  # also refuses NaN
        raise _fail("mounting_rpy_deg", opts["mounting_rpy_deg"], "three angles (roll, pitch, yaw) in [-360, 360] deg")
    opts["mounting_rpy_deg"] = rpy

    # Walking, not running: while one foot is airborne the other must be flat on the ground, which
    # with the half-stride offset between the feet needs both of these.
    half = opts["stride_period_s"] / 2
    if opts["swing_s"] + max(opts["heel_off_s"], opts["foot_flat_s"]) > half:
        raise _fail(
            "swing_s",
            opts["swing_s"],
            f"swing_s + max(heel_off_s, foot_flat_s) <= stride_period_s / 2 = {half:g} s so that one foot is "
            "flat while the other swings",
        )
    if opts["heel_strike_impact_mps2"] > 0 and _IMPACT_CUT * opts["heel_strike_impact_s"] > min(opts["swing_s"], opts["foot_flat_s"]):
        raise _fail(
            "heel_strike_impact_s",
            opts["heel_strike_impact_s"],
            f"<= min(swing_s, foot_flat_s) / {_IMPACT_CUT:g} = "
            f"{min(opts['swing_s'], opts['foot_flat_s']) / _IMPACT_CUT:g} s so the impact ends before the foot is flat",
        )
    if opts["turn_radius_m"] <= opts["step_width_m"] / 2:
        raise _fail("turn_radius_m", opts["turn_radius_m"], f"> step_width_m / 2 = {opts['step_width_m'] / 2:g} m")

    if scenario == "straight":
        opts["distance_m"] = _positive(opts, "distance_m", _MAX_LENGTH_M)
    elif scenario == "rectangle":
        for name in ("width_m", "height_m"):
            value = _positive(opts, name, _MAX_LENGTH_M)
            if value <= 2 * opts["turn_radius_m"]:
                raise _fail(name, opts[name], f"> 2 * turn_radius_m = {2 * opts['turn_radius_m']:g} m")
            opts[name] = value
        if opts["direction"] not in _DIRECTIONS:
            raise _fail("direction", opts["direction"], f"one of {', '.join(map(repr, _DIRECTIONS))}")
    else:
        opts["segments"] = _check_segments(opts["segments"])
    # The walk's samples, from the options alone (before anything is allocated): the standstills
    # and one stride per stride_length_m of centre line, plus one for the half-stride stagger.
    strides = _walk_length_m(scenario, opts) / opts["stride_length_m"] + 2
    duration_s = 2 * opts["standstill_s"] + strides * opts["stride_period_s"]
    if rate_hz * duration_s > _MAX_SAMPLES:
        raise InvalidParameterError(
            f"simulate(): rate_hz={rate_hz!r} over a walk of about {duration_s:,.0f} s makes about "
            f"{rate_hz * duration_s:,.0f} samples per foot; at most {_MAX_SAMPLES:,} are simulated (about 1 KB "
            "each while simulating): lower rate_hz or shorten the walk (distance, stride_length_m, standstill_s)"
        )
    return opts


def _check_segments(segments: Any) -> list[tuple[Any, ...]]:
    """``(distance_m, turn_deg)`` pairs as floats and ``("stairs", n_steps, rise_m, tread_m)``."""
    expected = (
        "a non-empty sequence of (distance_m in [0, 1e6], turn_deg in [-36000, 36000]) pairs with some walking, "
        f"or ('stairs', n_steps in [1, {_MAX_STAIRS}], rise_m in [-{_MAX_RISE_M:g}, {_MAX_RISE_M:g}] and not 0"
        f"[, tread_m in [{_TREAD_RANGE_M[0]:g}, {_TREAD_RANGE_M[1]:g}]])"
    )
    if segments is None:
        raise InvalidParameterError(
            "simulate(): scenario 'path' needs option segments=[(distance_m, turn_deg), ...]"
        )
    out: list[tuple[Any, ...]] = []
    try:
        for seg in segments:
            if isinstance(seg, (tuple, list)) and len(seg) in (3, 4) and isinstance(seg[0], str) and seg[0] == "stairs":
                n_steps = seg[1]
                if isinstance(n_steps, bool) or not isinstance(n_steps, (int, np.integer)) or not 1 <= n_steps <= _MAX_STAIRS:
                    raise ValueError
                rise = float(seg[2])
                tread = float(seg[3]) if len(seg) == 4 else _TREAD_DEFAULT_M
                if not (0 < abs(rise) <= _MAX_RISE_M and _TREAD_RANGE_M[0] <= tread <= _TREAD_RANGE_M[1]):
                    raise ValueError
                out.append(("stairs", int(n_steps), rise, tread))
            else:
                d, a = seg
                out.append((float(d), float(a)))
    except (TypeError, ValueError):
        raise _fail("segments", segments, expected) from None
    walks = [seg for seg in out if seg[0] != "stairs"]
    # bounded so that the walk's length stays finite for the sample budget
    if not out or any(not (0 <= d <= _MAX_LENGTH_M and abs(a) <= 36_000) for d, a in walks):
        raise _fail("segments", segments, expected)
    if len(walks) == len(out) and all(d == 0 and a == 0 for d, a in walks):
        raise _fail("segments", segments, expected)
    return out


# -- centre line --------------------------------------------------------------------------------


@dataclass(frozen=True)
class _CentreLine:
    """Straight lines and circular arcs joined end to end, starting at the origin heading +x.

    Each piece ``i`` starts at arc length ``start[i]`` (m), point ``xy[i]`` (m) and heading
    ``heading[i]`` (rad, unwrapped) and has curvature ``curvature[i]`` (1/m, + = left, 0 = line).
    """

    start: NDArray[np.float64]
    xy: NDArray[np.float64]
    heading: NDArray[np.float64]
    curvature: NDArray[np.float64]
    length_m: float

    @classmethod
    def build(cls, pieces: Sequence[tuple[float, float]]) -> "_CentreLine":
        """From ``(length_m, curvature_per_m)`` pieces; zero-length pieces are dropped."""
        pieces = [(l, k) for l, k in pieces if l > 0]
        start, xy, heading, curvature = [], [], [], []
        s, p, h = 0.0, np.zeros(2), 0.0
        for length, k in pieces:
            start.append(s)
            xy.append(p)
            heading.append(h)
            curvature.append(k)
            p, h = cls._advance(p, h, k, length)
            s += length
        return cls(np.array(start), np.array(xy), np.array(heading), np.array(curvature), s)

    @staticmethod
    def _advance(p: NDArray, h: Any, k: Any, ds: Any) -> tuple[NDArray, Any]:
        """Point and heading after ``ds`` along a piece of curvature ``k`` (vectorised)."""
        h1 = h + k * ds
        arc = np.abs(k) > 0
        safe_k = np.where(arc, k, 1.0)
        dx = np.where(arc, (np.sin(h1) - np.sin(h)) / safe_k, ds * np.cos(h))
        dy = np.where(arc, (np.cos(h) - np.cos(h1)) / safe_k, ds * np.sin(h))
        return p + np.stack([dx, dy], axis=-1), h1

    def __call__(self, s: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Point (M, 2) in m and heading (M,) in rad at arc lengths ``s`` (M,) in m."""
        i = np.clip(np.searchsorted(self.start, s, side="right") - 1, 0, len(self.start) - 1)
        return self._advance(self.xy[i], self.heading[i], self.curvature[i], s - self.start[i])


def _centre_line(scenario: str, opts: dict[str, Any]) -> tuple[_CentreLine, dict[str, Any]]:
    """The scenario's centre line and a description of it for the truth's meta."""
    r = opts["turn_radius_m"]
    if scenario == "straight":
        pieces = [(opts["distance_m"], 0.0)]
        return _CentreLine.build(pieces), {"waypoints_m": _waypoints(pieces)}
    if scenario == "rectangle":
        w, h = opts["width_m"], opts["height_m"]
        sign = 1.0 if opts["direction"] == "ccw" else -1.0
        quarter = np.pi / 2 * r
        # Start in the middle of a long side so the walk ends exactly where and as it started
        # (same heading, same footprints) after four corners rounded with the turn radius.
        pieces = [(w / 2 - r, 0.0)]
        for side in (h, w, h):
            pieces += [(quarter, sign / r), (side - 2 * r, 0.0)]
        pieces += [(quarter, sign / r), (w / 2 - r, 0.0)]
        y0, y1 = (0.0, h) if sign > 0 else (-h, 0.0)
        corners = np.array([[-w / 2, y0], [w / 2, y0], [w / 2, y1], [-w / 2, y1]])
        return _CentreLine.build(pieces), {"rectangle_corners_m": corners, "waypoints_m": _waypoints(pieces)}
    pieces = []
    # flights of stairs: (arc length where the flight starts, n_steps, rise_m, tread_m)
    flights: list[tuple[float, int, float, float]] = []
    s = 0.0
    for seg in opts["segments"]:
        if seg[0] == "stairs":
            _, n_steps, rise, tread = seg
            flights.append((s, n_steps, rise, tread))
            pieces.append((n_steps * tread, 0.0))
            s += n_steps * tread
            continue
        distance, turn_deg = seg
        pieces.append((distance, 0.0))
        s += distance
        if turn_deg != 0:
            pieces.append((abs(math.radians(turn_deg)) * r, math.copysign(1.0 / r, turn_deg)))
            s += pieces[-1][0]
    info: dict[str, Any] = {"waypoints_m": _waypoints(pieces)}
    if flights:  # only then: a walk without stairs keeps its meta as it was
        info["stairs"] = [
            {"start_m": s0, "n_steps": n_steps, "rise_m": rise, "tread_m": tread, "height_m": n_steps * rise}
            for s0, n_steps, rise, tread in flights
        ]
    return _CentreLine.build(pieces), info


def _waypoints(pieces: list[tuple[float, float]]) -> NDArray[np.float64]:
    """Centre-line points a surveyor would mark: the apex of every turn and the end, (K, 2) m
    (for :func:`footnav.core.metrics.waypoint_errors`, Lee, Cho & Park 2022, Table 3)."""
    line = _CentreLine.build(pieces)
    s, marks = 0.0, []
    for length, curvature in pieces:
        if curvature != 0.0:
            marks.append(s + 0.5 * length)
        s += length
    marks.append(s)
    xy, _ = line(np.asarray(marks, dtype=float))
    return np.asarray(xy, dtype=float)


# -- gait plan ----------------------------------------------------------------------------------


@dataclass(frozen=True)
class _Swings:
    """One foot's swings: event times (K,) in s and the footprints it leaves and reaches."""

    t_heel_off: NDArray[np.float64]
    t_toe_off: NDArray[np.float64]
    t_heel_strike: NDArray[np.float64]
    t_foot_flat: NDArray[np.float64]
    xy_from: NDArray[np.float64]
    heading_from: NDArray[np.float64]
    xy_to: NDArray[np.float64]
    heading_to: NDArray[np.float64]
    # heights (m) of the footprints left and reached: zero but on stairs
    z_from: NDArray[np.float64]
    z_to: NDArray[np.float64]
    # each swing's factor on its pitch angles and lift (``swing_scale``); None: all 1
    scale: NDArray[np.float64] | None = None


def _plan(
    line: _CentreLine, opts: dict[str, Any], flights: Sequence[Mapping[str, Any]] = ()
) -> tuple[dict[str, _Swings], dict[str, Any]]:
    """Footprints and swing timing of both feet along ``line``.

    The walk starts with the feet side by side. With ``n`` steps of length ``l = length / n``
    (``l`` close to half the stride) footfalls land at arc lengths ``l, 2 l, ..., n l``, alternating
    right, left, ...; swing ``j`` (j = 0..n) takes its foot from arc length ``(j-1) l`` (0 for the
    first two) to ``min(j+1, n) l``, so the first and the last swing are half strides and the feet
    end side by side. Swing ``j`` starts (heel-off) ``j`` half stride periods after the standstill.

    With ``flights`` of stairs (``_centre_line``'s ``"stairs"``) the level stretches between them
    are stepped as above, each on its own, and a flight of ``N`` stairs takes ``N`` footfalls, one
    per tread (step over step: each swing climbs two risers), at ``tread_m`` apart and ``rise_m``
    higher each; swing ``j`` still goes from footfall ``j-1`` to footfall ``j+1``.
    """
    if flights:
        s_fall, z_fall = _footfalls(line, opts, flights)
        n = len(s_fall) - 1
        j = np.arange(n + 1)
        s_from, s_to = s_fall[np.maximum(j - 1, 0)], s_fall[np.minimum(j + 1, n)]
        z_from, z_to = z_fall[np.maximum(j - 1, 0)], z_fall[np.minimum(j + 1, n)]
        step = line.length_m / n  # the mean step, for the meta
    else:
        n = max(1, int(round(line.length_m / (opts["stride_length_m"] / 2))))
        step = line.length_m / n
        j = np.arange(n + 1)
        s_from = np.maximum(j - 1, 0) * step
        s_to = np.minimum(j + 1, n) * step
        z_from = z_to = np.zeros(n + 1)
    t_ho = opts["standstill_s"] + j * opts["stride_period_s"] / 2
    t_to = t_ho + opts["heel_off_s"]
    t_hs = t_to + opts["swing_s"]
    t_ff = t_hs + opts["foot_flat_s"]
    swings = {}
    for foot, side, first in (("right", -1.0, 0), ("left", 1.0, 1)):
        sel = j % 2 == first
        xy_from, h_from = _footprint(line, s_from[sel], side * opts["step_width_m"] / 2)
        xy_to, h_to = _footprint(line, s_to[sel], side * opts["step_width_m"] / 2)
        scale = None
        if opts["swing_scale"] is not None:  # the foot's own swings in order: 1st, 2nd, ...
            factors = np.asarray(opts["swing_scale"])
            scale = factors[np.arange(int(sel.sum())) % len(factors)]
        swings[foot] = _Swings(
            t_ho[sel], t_to[sel], t_hs[sel], t_ff[sel], xy_from, h_from, xy_to, h_to, z_from[sel], z_to[sel], scale
        )
    duration = float(t_ff[-1] + opts["standstill_s"])
    info = {
        "path_length_m": line.length_m,
        "n_steps": n,
        "step_length_m": step,
        "stride_length_m_actual": 2 * step,
        "duration_s": duration,
        "first_foot": "right",
    }
    if flights:
        info["height_change_m"] = float(z_to[-1])
    return swings, info


def _footfalls(
    line: _CentreLine, opts: dict[str, Any], flights: Sequence[Mapping[str, Any]]
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Arc lengths (m) and heights (m) of footfalls 0..n of a walk with stairs, (n+1,) each.

    Footfall 0 is the start. A level stretch of length ``L`` takes ``max(1, round(L / (stride / 2)))``
    equal steps; a flight of ``N`` stairs ``N`` footfalls ``tread_m`` apart, the i-th ``i rise_m``
    above the flight's foot, so after it the height has changed by exactly ``N rise_m``.
    """
    s_fall, z_fall = [0.0], [0.0]
    s, z = 0.0, 0.0
    for flight in [*flights, None]:
        s_next = line.length_m if flight is None else flight["start_m"]
        level = s_next - s
        if level > 0:
            n = max(1, int(round(level / (opts["stride_length_m"] / 2))))
            step = level / n
            s_fall += [s + i * step for i in range(1, n)] + [s_next]
            z_fall += [z] * n
        if flight is None:
            break
        n_steps, rise, tread = flight["n_steps"], flight["rise_m"], flight["tread_m"]
        s_fall += [s_next + i * tread for i in range(1, n_steps + 1)]
        z_fall += [z + i * rise for i in range(1, n_steps + 1)]
        s, z = s_next + n_steps * tread, z + n_steps * rise
    return np.asarray(s_fall), np.asarray(z_fall)


def _footprint(line: _CentreLine, s: NDArray, offset_left_m: float) -> tuple[NDArray, NDArray]:
    xy, heading = line(s)
    normal = np.stack([-np.sin(heading), np.cos(heading)], axis=-1)
    return xy + offset_left_m * normal, heading


# -- analytic profiles --------------------------------------------------------------------------


def _quintic_coefficients(p0: float, v0: float, p1: float, v1: float, duration: float) -> NDArray[np.float64]:
    """Coefficients c0..c5 in normalised time u in [0, 1] of the quintic from (p0, v0, 0) to (p1, v1, 0).

    Values in the unit of p, rates v in unit/s; zero acceleration at both ends keeps the profile
    second-order continuous with a rest or another such segment.
    """
    d0, d1 = v0 * duration, v1 * duration
    big_p = p1 - p0 - d0
    big_v = d1 - d0
    return np.array([p0, d0, 0.0, 10 * big_p - 4 * big_v, -15 * big_p + 7 * big_v, 6 * big_p - 3 * big_v])


def _polyval(c: NDArray, u: NDArray, duration: NDArray) -> tuple[NDArray, NDArray, NDArray]:
    """Value and first two time derivatives of per-sample quintics ``c`` (N, 6) at ``u`` (N,)."""
    c0, c1, c2, c3, c4, c5 = c.T
    val = c0 + u * (c1 + u * (c2 + u * (c3 + u * (c4 + u * c5))))
    d1 = c1 + u * (2 * c2 + u * (3 * c3 + u * (4 * c4 + u * 5 * c5)))
    d2 = 2 * c2 + u * (6 * c3 + u * (12 * c4 + u * 20 * c5))
    return val, d1 / duration, d2 / duration**2


def _smoothstep(u: NDArray, duration: float) -> tuple[NDArray, NDArray, NDArray]:
    """Minimum-jerk 0 -> 1 blend and its time derivatives; rest (zero rate and acceleration) at both ends."""
    w = 1.0 - u
    return (
        u**3 * (10.0 - 15.0 * u + 6.0 * u**2),
        30.0 * u**2 * w**2 / duration,
        60.0 * u * w * (w - u) / duration**2,
    )


def _bump(u: NDArray, duration: float) -> tuple[NDArray, NDArray, NDArray]:
    """0 -> 1 -> 0 lift profile 64 u^3 (1-u)^3 and its time derivatives, flat to second order at the ends."""
    g = u * (1.0 - u)
    dg = 1.0 - 2.0 * u
    return (
        _BUMP_GAIN * g**3,
        3 * _BUMP_GAIN * g**2 * dg / duration,
        3 * _BUMP_GAIN * g * (2 * dg**2 - 2 * g) / duration**2,
    )


# -- one foot -----------------------------------------------------------------------------------


@dataclass(frozen=True)
class _FootMotion:
    """Noise-free motion of one foot's sensor at the sample times (sensor frame = foot frame)."""

    position: NDArray[np.float64]
    velocity: NDArray[np.float64]
    quaternion: NDArray[np.float64]
    gyr: NDArray[np.float64]
    acc: NDArray[np.float64]
    phase: NDArray[np.int8]


def _foot_motion(t: NDArray[np.float64], sw: _Swings, opts: dict[str, Any]) -> _FootMotion:
    """Evaluate the gait model of one foot at times ``t`` (N,), fully vectorised."""
    n = len(t)
    # k: the latest swing that has started (heel-off before t); -1 before the first. A sample at
    # heel-off or foot-flat (up to the rounding of the event times) has zero velocity and rate,
    # so it counts as stance.
    k = np.searchsorted(sw.t_heel_off, t - _EVENT_TIME_TOL_S, side="left") - 1
    started = k >= 0
    kk = np.maximum(k, 0)
    phase = np.full(n, _STANCE, dtype=np.int8)
    phase[started & (t < sw.t_foot_flat[kk] - _EVENT_TIME_TOL_S)] = _FOOT_FLAT
    phase[started & (t < sw.t_heel_strike[kk])] = _SWING
    phase[started & (t < sw.t_toe_off[kk])] = _HEEL_OFF

    # Stance: flat on the footprint reached by the last swing (or the initial one), nothing
    # moves, so velocity and angular rate are exactly zero and the sensor reads +g up.
    still = np.flatnonzero(phase == _STANCE)
    ks = k[still]
    stand_xy = np.where((ks >= 0)[:, None], sw.xy_to[np.maximum(ks, 0)], sw.xy_from[0])
    stand_h = np.where(ks >= 0, sw.heading_to[np.maximum(ks, 0)], sw.heading_from[0])
    pos = np.zeros((n, 3))
    vel = np.zeros((n, 3))
    gyr = np.zeros((n, 3))
    acc = np.zeros((n, 3))
    q = np.empty((n, 4))
    pos[still, :2] = stand_xy
    pos[still, 2] = np.where(ks >= 0, sw.z_to[np.maximum(ks, 0)], sw.z_from[0])
    q[still] = quat.from_yaw(stand_h)
    acc[still, 2] = GRAVITY_MPS2

    moving = np.flatnonzero(phase != _STANCE)
    m = _moving_motion(t[moving], phase[moving], k[moving], sw, opts)
    pos[moving], vel[moving], q[moving], gyr[moving], acc[moving] = m
    return _FootMotion(pos, vel, q, gyr, acc, phase)


def _moving_motion(
    t: NDArray[np.float64], phase: NDArray[np.int8], k: NDArray[np.int64], sw: _Swings, opts: dict[str, Any]
) -> tuple[NDArray, NDArray, NDArray, NDArray, NDArray]:
    """Position, velocity, quaternion, body rate and specific force in heel-off, swing and foot-flat.

    ``k`` (M,) is the swing each sample belongs to.
    """
    n = len(t)
    t_start = np.select(
        [phase == _HEEL_OFF, phase == _SWING],
        [sw.t_heel_off[k], sw.t_toe_off[k]],
        default=sw.t_heel_strike[k],
    )
    durations = np.array([1.0, opts["heel_off_s"], opts["swing_s"], opts["foot_flat_s"]])
    dur = durations[phase]
    u = np.clip((t - t_start) / dur, 0.0, 1.0)

    # Pitch (toe-down positive: a rotation about the foot's y axis, which points left) through
    # heel-off, swing and foot-flat: one quintic per phase, matched in value, rate and
    # acceleration at toe-off and heel strike and at rest at both ends.
    th_to = math.radians(opts["toe_off_pitch_deg"])
    th_hs = -math.radians(opts["heel_strike_pitch_deg"])
    w_to = _TOE_OFF_RATE_FRACTION * th_to / opts["heel_off_s"]
    w_hs = _HEEL_STRIKE_RATE_FRACTION * (-th_hs) / opts["foot_flat_s"]
    pitch_coef = np.stack(
        [
            np.zeros(6),
            _quintic_coefficients(0.0, 0.0, th_to, w_to, opts["heel_off_s"]),
            _quintic_coefficients(th_to, w_to, th_hs, w_hs, opts["swing_s"]),
            _quintic_coefficients(th_hs, w_hs, 0.0, 0.0, opts["foot_flat_s"]),
        ]
    )
    th, th_d, th_dd = _polyval(pitch_coef[phase], u, dur)
    if sw.scale is not None:
        # the quintics are linear in their end values and rates: a swing's factor scales its
        # whole pitch profile (heel-off, swing, foot-flat), still at rest at both ends
        f = sw.scale[k]
        th, th_d, th_dd = f * th, f * th_d, f * th_dd

    # Blend g from the old footprint to the new one: 0 through heel-off, min-jerk while
    # airborne, 1 through foot-flat. Heading, contact point and its position all follow it.
    swing = phase == _SWING
    g_s, g_d_s, g_dd_s = _smoothstep(u, opts["swing_s"])
    g = np.where(swing, g_s, (phase == _FOOT_FLAT).astype(float))
    g_d = np.where(swing, g_d_s, 0.0)
    g_dd = np.where(swing, g_dd_s, 0.0)
    b_s, b_d_s, b_dd_s = _bump(u, opts["swing_s"])
    lift = opts["foot_lift_m"] if sw.scale is None else opts["foot_lift_m"] * sw.scale[k]

    h_from, h_to = sw.heading_from[k], sw.heading_to[k]
    dpsi = h_to - h_from
    psi = h_from + dpsi * g
    psi_d = dpsi * g_d
    psi_dd = dpsi * g_dd

    # Contact point X (nav): the toe where the foot leaves the ground, the heel where it lands.
    toe_from = _horizontal_point(sw.xy_from[k], h_from, _TOE_B)
    heel_to = _horizontal_point(sw.xy_to[k], h_to, _HEEL_B)
    # On stairs the footprints' heights differ and the contact point climbs with the same
    # blend (adding the level walk's zeros leaves its values as they were).
    toe_from[:, 2] += sw.z_from[k]
    heel_to[:, 2] += sw.z_to[k]
    dx = heel_to - toe_from
    x_pos = toe_from + dx * g[:, None]
    x_vel = dx * g_d[:, None]
    x_acc = dx * g_dd[:, None]
    x_pos[:, 2] += np.where(swing, lift * b_s, 0.0)
    x_vel[:, 2] += np.where(swing, lift * b_d_s, 0.0)
    x_acc[:, 2] += np.where(swing, lift * b_dd_s, 0.0)
    # Body-frame contact point c: toe -> heel with the same blend.
    toe_to_heel = _HEEL_B - _TOE_B
    c = _TOE_B + np.outer(g, toe_to_heel)
    c_d = np.outer(g_d, toe_to_heel)
    c_dd = np.outer(g_dd, toe_to_heel)

    # Orientation C = Rz(psi) Ry(th); body angular rate and its derivative follow analytically.
    q = quat.from_euler(np.zeros(n), th, psi)
    cmat = quat.as_matrix(q)
    s_th, c_th = np.sin(th), np.cos(th)
    omega = np.stack([-s_th * psi_d, th_d, c_th * psi_d], axis=-1)
    omega_d = np.stack(
        [-c_th * th_d * psi_d - s_th * psi_dd, th_dd, -s_th * th_d * psi_d + c_th * psi_dd], axis=-1
    )

    # p = X - C c:  v = X' - C (w x c + c'),  a = X'' - C (w' x c + w x (w x c) + 2 w x c' + c'').
    w_c = np.cross(omega, c)
    vel = x_vel - np.einsum("nij,nj->ni", cmat, w_c + c_d)
    body_terms = np.cross(omega_d, c) + np.cross(omega, w_c) + 2.0 * np.cross(omega, c_d) + c_dd
    up = np.array([0.0, 0.0, GRAVITY_MPS2])
    # f_b = C^T (a_n - g_n) with g_n = -up.
    acc = np.einsum("nji,nj->ni", cmat, x_acc + up) - body_terms
    pos = x_pos - np.einsum("nij,nj->ni", cmat, c)
    return pos, vel, q, omega, acc


def _heel_strike_impact(
    t: NDArray[np.float64], t_heel_strike: NDArray[np.float64], opts: dict[str, Any]
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """Vertical (nav z) displacement, velocity and acceleration of the heel-strike impact, (N,) each.

    The acceleration is a Ricker wavelet ``A (1 - u^2) exp(-u^2/2)``, ``u = (t - t_hs) / sigma``:
    minus sigma^2 times the second derivative of ``G = exp(-u^2/2)``, so the displacement is
    ``-A sigma^2 G`` (the sole compresses by A sigma^2, 4 mm by default, and springs back) and the
    velocity ``A sigma u G``; both vanish outside the pulse. Cut at 6 sigma (G < 1.6e-8).
    """
    disp, vel, acc = np.zeros(len(t)), np.zeros(len(t)), np.zeros(len(t))
    amp, sigma = opts["heel_strike_impact_mps2"], opts["heel_strike_impact_s"]
    if amp == 0:
        return disp, vel, acc
    for t_hs in t_heel_strike:
        sl = slice(*np.searchsorted(t, [t_hs - _IMPACT_CUT * sigma, t_hs + _IMPACT_CUT * sigma]))
        u = (t[sl] - t_hs) / sigma
        g = np.exp(-0.5 * u * u)
        disp[sl] -= amp * sigma * sigma * g
        vel[sl] += amp * sigma * u * g
        acc[sl] += amp * (1.0 - u * u) * g
    return disp, vel, acc


def _horizontal_point(xy: NDArray, heading: NDArray, point_b: NDArray) -> NDArray:
    """Nav position of foot point ``point_b`` when the foot stands flat at ``xy`` (sensor z = 0)."""
    ch, sh = np.cos(heading), np.sin(heading)
    return np.column_stack(
        [
            xy[:, 0] + ch * point_b[0] - sh * point_b[1],
            xy[:, 1] + sh * point_b[0] + ch * point_b[1],
            np.full(len(xy), point_b[2]),
        ]
    )


def _mirrored_yaw_rate(motion: _FootMotion, rate_radps: float) -> NDArray[np.float64]:
    """Foot-frame rate (N, 3) of ``rate_radps`` about the nav vertical, ``C^T e_z``, while the foot
    is off the ground (zero in stance): the mirrored drift of ``mirrored_yaw_rate_radps``."""
    up_foot = quat.as_matrix(motion.quaternion)[:, 2, :]  # row 2 of C (foot -> nav) = C^T e_z
    return np.where((motion.phase != _STANCE)[:, None], rate_radps * up_foot, 0.0)


def _nearest_index(times: NDArray, rate_hz: float, n: int) -> NDArray[np.int64]:
    return np.clip(np.rint(times * rate_hz), 0, n - 1).astype(np.int64)


def _sensor_errors(
    rng: np.random.Generator, n: int, rate_hz: float, opts: dict[str, Any]
) -> dict[str, NDArray[np.float64]]:
    """Turn-on bias, bias random walk and white noise of one IMU (all zero without noise)."""
    zeros3 = np.zeros(3)
    if not opts["noise"]:
        return {
            "gyr_turn_on_radps": zeros3,
            "acc_turn_on_mps2": zeros3,
            "gyr_radps": np.zeros((n, 3)),
            "acc_mps2": np.zeros((n, 3)),
            "gyr_white": np.zeros((n, 3)),
            "acc_white": np.zeros((n, 3)),
        }
    dt = 1.0 / rate_hz
    sqrt_rate = math.sqrt(rate_hz)
    out: dict[str, NDArray[np.float64]] = {}
    for sensor, unit in (("gyr", "radps"), ("acc", "mps2")):
        b0 = rng.normal(0.0, opts[f"{sensor}_bias_std_{unit}"], 3)
        walk_key = "gyr_bias_walk_radps2_sqrthz" if sensor == "gyr" else "acc_bias_walk_mps3_sqrthz"
        steps = rng.normal(0.0, opts[walk_key] * math.sqrt(dt), (n, 3))
        steps[0] = 0.0  # the bias at the first sample is the turn-on bias
        out[f"{sensor}_turn_on_{unit}"] = b0
        out[f"{sensor}_{unit}"] = b0 + np.cumsum(steps, axis=0)
        out[f"{sensor}_white"] = rng.normal(0.0, opts[f"{sensor}_noise_density_{unit}_sqrthz"] * sqrt_rate, (n, 3))
    return out


# -- public API ---------------------------------------------------------------------------------


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

    Returns
    -------
    Recording
        ``left`` / ``right``: :class:`ImuData` in the sensor frame (specific force in m/s^2, +g
        up at rest; angular rate in rad/s). ``truth_left`` / ``truth_right``: :class:`FootTruth` in
        footnav's nav frame (z up, x the initial walking direction, origin midway between the
        feet at the start, the sensors at z = 0 when flat): the sensor's position, velocity and
        orientation (body -> nav) at the IMU's times, the stance mask (True exactly where the
        foot's velocity and angular rate are zero), gait events (sample indices nearest to each
        stride's ``heel_strike``, ``foot_flat``, ``heel_off``, ``toe_off``) and ``closed_loop``.
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
        np.linalg.norm(end_xy[0]) < _CLOSED_LOOP_TOL_M and abs(plan_info.get("height_change_m", 0.0)) < _CLOSED_LOOP_TOL_M
    )
    mount_q = quat.from_euler(*np.radians(opts["mounting_rpy_deg"]))
    mount_t = quat.as_matrix(mount_q).T  # foot -> sensor
    noise_params = {k: opts[k] for k in _NOISE_KEYS} | {"noise": opts["noise"]}
    common_meta = {"scenario": scenario, "options": dict(opts), "seed": seed, "rate_hz": rate_hz}

    rng_left, rng_right = np.random.default_rng(seed).spawn(2)
    imus: dict[str, ImuData] = {}
    truths: dict[str, FootTruth] = {}
    biases_all: dict[str, dict[str, Any]] = {}
    for foot, rng in (("left", rng_left), ("right", rng_right)):
        sw = swings[foot]
        motion = _foot_motion(t, sw, opts)
        errors = _sensor_errors(rng, n, rate_hz, opts)
        # The impact moves the sensor along nav z; the foot frame sees it through C^T e_z.
        imp_p, imp_v, imp_a = _heel_strike_impact(t, sw.t_heel_strike, opts)
        impact_foot = imp_a[:, None] * quat.as_matrix(motion.quaternion)[:, 2, :]
        motion.position[:, 2] += imp_p
        motion.velocity[:, 2] += imp_v
        impact = impact_foot @ mount_t.T
        gyr_true = motion.gyr @ mount_t.T
        acc_true = (motion.acc + impact_foot) @ mount_t.T
        gyr = gyr_true + errors["gyr_radps"] + errors["gyr_white"]
        mirrored = _mirrored_yaw_rate(motion, opts["mirrored_yaw_rate_radps"] * (1.0 if foot == "left" else -1.0)) @ mount_t.T
        if opts["mirrored_yaw_rate_radps"] != 0.0:  # off: the signals stay bit-identical
            gyr = gyr + mirrored
        acc = acc_true + errors["acc_mps2"] + errors["acc_white"]
        biases = {k: errors[k] for k in ("gyr_turn_on_radps", "acc_turn_on_mps2", "gyr_radps", "acc_mps2")}
        biases_all[foot] = {k: biases[k] for k in ("gyr_turn_on_radps", "acc_turn_on_mps2")}
        imus[foot] = ImuData(
            t=t,
            acc=acc,
            gyr=gyr,
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
            quaternion=quat.multiply(motion.quaternion, mount_q),
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
                **plan_info,
                **line_info,
            },
        )
    clock_meta = {}
    if opts["clock_offset_s"] or opts["clock_drift_ppm"] or opts["clock_exchanges"]:
        rate = 1.0 + opts["clock_drift_ppm"] * 1e-6
        offset = opts["clock_offset_s"]
        # t_imu = (t - b) / a with a = 1 / rate, b = -offset / rate: the sensor's own clock
        imus["right"] = ImuData(
            t=rate * t + offset,
            acc=imus["right"].acc,
            gyr=imus["right"].gyr,
            meta={**imus["right"].meta, "time_base": "sensor clock (offset and drift: the recording's meta['clock'])"},
        )
        clock_meta["clock"] = {
            "foot": "right",
            "offset_s": offset,
            "drift_ppm": opts["clock_drift_ppm"],
            "a": 1.0 / rate,
            "b": -offset / rate,
        }
        truths["right"] = replace(truths["right"], meta={**truths["right"].meta, "clock": clock_meta["clock"]})
        n_ex = opts["clock_exchanges"]
        if n_ex:
            # a third child of the seed: the feet's two streams are the same with or without it
            rng_ex = np.random.default_rng(seed).spawn(3)[2]
            half = n_ex // 2
            duration = float(t[-1])
            tm1 = np.concatenate([np.linspace(0.0, min(10.0, duration / 3), half),
                                  np.linspace(max(duration - 10.0, 2 * duration / 3), duration, n_ex - half)])
            delay, jitter = opts["exchange_delay_s"], opts["exchange_jitter_s"]
            d_up = delay + rng_ex.exponential(jitter, n_ex)
            d_down = delay + rng_ex.exponential(jitter, n_ex)
            # stamped on the sensor at true time tm1 + d_up, received at tm1 + d_up + d_down
            clock_meta["clock_exchanges"] = {"tm1": tm1, "ti": rate * (tm1 + d_up) + offset, "tm2": tm1 + d_up + d_down}
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
