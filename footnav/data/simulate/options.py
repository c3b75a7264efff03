"""The simulator's options: defaults, and every value checked against its range before a walk."""

from __future__ import annotations

import difflib
import math
from collections.abc import Mapping
from numbers import Real
from typing import Any

import numpy as np

from footnav.core.errors import InvalidParameterError
from footnav.data.simulate.foot import _IMPACT_CUT

#: Scenario names accepted by :func:`simulate`.
SCENARIOS = ("straight", "rectangle", "path")

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
    # A magnetometer (off: the recordings have none, and every other signal is the same either way).
    "magnetometer": False,
    "mag_field_ut": 50.0,
    "mag_dip_deg": 60.0,
    "mag_north_deg": 30.0,
    "mag_noise_ut": 0.5,
    "mag_hard_iron_ut": 1.0,
    "mag_disturbances": (),
    # Scale-factor errors per sensor axis, fractions (off: the signals stay bit-identical).
    "gyr_scale_error": 0.0,
    "acc_scale_error": 0.0,
    # The left/right mirror-symmetric heading drift of Lee, Cho & Park (2022), Sec. 2.1 (off).
    "mirrored_yaw_rate_radps": 0.0,
    "stance_twist_deg": 0.0,
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


def _scale_error(opts: dict[str, Any], name: str) -> tuple[float, float, float]:
    """A scale-factor error: one fraction for every axis or one per sensor axis, each in [-0.2, 0.2]."""
    value = opts[name]
    try:
        per_axis = np.broadcast_to(np.asarray(value, dtype=float), (3,))
    except (TypeError, ValueError):
        raise _fail(name, value, "a fraction or three (one per sensor axis), each in [-0.2, 0.2]") from None
    if not np.all(np.abs(per_axis) <= 0.2):  # also rejects NaN
        raise _fail(name, value, "a fraction or three (one per sensor axis), each in [-0.2, 0.2]")
    return (float(per_axis[0]), float(per_axis[1]), float(per_axis[2]))


def _magnetometer_options(opts: dict[str, Any]) -> None:
    """Check (and normalise in ``opts``) the magnetometer's options."""
    if not isinstance(opts["magnetometer"], (bool, np.bool_)):
        raise _fail("magnetometer", opts["magnetometer"], "True or False")
    opts["magnetometer"] = bool(opts["magnetometer"])
    opts["mag_field_ut"] = _positive(opts, "mag_field_ut", 1e4)
    opts["mag_dip_deg"] = _number(opts, "mag_dip_deg")
    if not -90.0 <= opts["mag_dip_deg"] <= 90.0:
        raise _fail("mag_dip_deg", opts["mag_dip_deg"], "an inclination in [-90, 90] deg")
    opts["mag_north_deg"] = _number(opts, "mag_north_deg")
    if not abs(opts["mag_north_deg"]) <= 360.0:
        raise _fail("mag_north_deg", opts["mag_north_deg"], "an angle in [-360, 360] deg")
    opts["mag_noise_ut"] = _non_negative(opts, "mag_noise_ut", 1e4)
    opts["mag_hard_iron_ut"] = _non_negative(opts, "mag_hard_iron_ut", 1e4)
    try:
        zones = tuple(tuple(float(v) for v in zone) for zone in opts["mag_disturbances"])
    except (TypeError, ValueError):
        zones = ((),)
    if not all(len(z) == 6 and all(math.isfinite(v) and abs(v) <= 1e6 for v in z) and z[2] > 0 for z in zones):
        raise _fail(
            "mag_disturbances",
            opts["mag_disturbances"],
            "a sequence of (x_m, y_m, radius_m > 0, bx_ut, by_ut, bz_ut) zones, finite numbers",
        )
    opts["mag_disturbances"] = zones


# complexity: one check per simulator option
def _resolve_options(scenario: Any, rate_hz: Any, options: Mapping[str, Any]) -> dict[str, Any]:  # noqa: C901
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
    opts["stance_twist_deg"] = _number(opts, "stance_twist_deg")
    if not abs(opts["stance_twist_deg"]) <= 20.0:
        raise _fail("stance_twist_deg", opts["stance_twist_deg"], "an angle in [-20, 20] deg")
    for name in _NOISE_KEYS:
        opts[name] = _non_negative(opts, name, _MAX_NOISE)
    for name in ("gyr_scale_error", "acc_scale_error"):
        opts[name] = _scale_error(opts, name)
    for name in ("toe_off_pitch_deg", "heel_strike_pitch_deg"):
        value = _number(opts, name)
        if not 0 < value < 90:
            raise _fail(name, opts[name], "a pitch angle in (0, 90) deg")
        opts[name] = value
    _magnetometer_options(opts)
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
    if opts["heel_strike_impact_mps2"] > 0 and _IMPACT_CUT * opts["heel_strike_impact_s"] > min(
        opts["swing_s"], opts["foot_flat_s"]
    ):
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
        raise InvalidParameterError("simulate(): scenario 'path' needs option segments=[(distance_m, turn_deg), ...]")
    out: list[tuple[Any, ...]] = []
    try:
        for seg in segments:
            if isinstance(seg, (tuple, list)) and len(seg) in (3, 4) and isinstance(seg[0], str) and seg[0] == "stairs":
                n_steps = seg[1]
                if (
                    isinstance(n_steps, bool)
                    or not isinstance(n_steps, (int, np.integer))
                    or not 1 <= n_steps <= _MAX_STAIRS
                ):
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
