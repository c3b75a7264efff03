"""The simulated IMUs' errors (turn-on bias, bias random walk, white noise, mirrored yaw drift)
and the right sensor's own clock."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import NDArray

from footnav.data.simulate.foot import _FootMotion
from footnav.data.simulate.gait import _STANCE
from footnav.nav import quaternion as quat


def _mirrored_yaw_rate(motion: _FootMotion, rate_radps: float) -> NDArray[np.float64]:
    """Foot-frame rate (N, 3) of ``rate_radps`` about the nav vertical, ``C^T e_z``, while the foot
    is off the ground (zero in stance): the mirrored drift of ``mirrored_yaw_rate_radps``."""
    up_foot = quat.as_matrix(motion.quaternion)[:, 2, :]  # row 2 of C (foot -> nav) = C^T e_z
    return np.where((motion.phase != _STANCE)[:, None], rate_radps * up_foot, 0.0)


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


def _sensor_clock(
    t: NDArray[np.float64], seed: int, opts: dict[str, Any]
) -> tuple[NDArray[np.float64] | None, dict[str, Any]]:
    """The right sensor's time stamps at true times ``t`` (N,) and the recording's clock meta.

    Returns ``(None, {})`` without clock options, else the sensor clock's times and
    ``{"clock": ...}`` (with ``"clock_exchanges"`` when ``clock_exchanges`` asks for them); see
    ``clock_offset_s``, ``clock_drift_ppm`` and ``clock_exchanges`` in :func:`footnav.simulate`.
    """
    clock_meta: dict[str, Any] = {}
    if not (opts["clock_offset_s"] or opts["clock_drift_ppm"] or opts["clock_exchanges"]):
        return None, clock_meta
    rate = 1.0 + opts["clock_drift_ppm"] * 1e-6
    offset = opts["clock_offset_s"]
    # t_imu = (t - b) / a with a = 1 / rate, b = -offset / rate: the sensor's own clock
    t_imu = rate * t + offset
    clock_meta["clock"] = {
        "foot": "right",
        "offset_s": offset,
        "drift_ppm": opts["clock_drift_ppm"],
        "a": 1.0 / rate,
        "b": -offset / rate,
    }
    n_ex = opts["clock_exchanges"]
    if n_ex:
        # a third child of the seed: the feet's two streams are the same with or without it
        rng_ex = np.random.default_rng(seed).spawn(3)[2]
        half = n_ex // 2
        duration = float(t[-1])
        tm1 = np.concatenate(
            [
                np.linspace(0.0, min(10.0, duration / 3), half),
                np.linspace(max(duration - 10.0, 2 * duration / 3), duration, n_ex - half),
            ]
        )
        delay, jitter = opts["exchange_delay_s"], opts["exchange_jitter_s"]
        d_up = delay + rng_ex.exponential(jitter, n_ex)
        d_down = delay + rng_ex.exponential(jitter, n_ex)
        # stamped on the sensor at true time tm1 + d_up, received at tm1 + d_up + d_down
        clock_meta["clock_exchanges"] = {"tm1": tm1, "ti": rate * (tm1 + d_up) + offset, "tm2": tm1 + d_up + d_down}
    return t_imu, clock_meta
