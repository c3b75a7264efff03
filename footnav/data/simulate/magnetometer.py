"""The simulated magnetometer: Earth's field seen through the sensor's attitude, a hard-iron
offset, white noise and local disturbances (steel, electronics)."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import NDArray

from footnav.nav import quaternion as quat


def earth_field_nav(opts: dict[str, Any]) -> NDArray[np.float64]:
    """Earth's field in the nav frame (x, y, z up), uT: ``mag_field_ut`` strong, dipping
    ``mag_dip_deg`` below the horizontal, its horizontal part ``mag_north_deg`` from +x."""
    f, dip, north = opts["mag_field_ut"], math.radians(opts["mag_dip_deg"]), math.radians(opts["mag_north_deg"])
    return f * np.array([math.cos(dip) * math.cos(north), math.cos(dip) * math.sin(north), -math.sin(dip)])


def disturbance_nav(position: NDArray[np.float64], zones: tuple) -> NDArray[np.float64]:
    """The disturbances' field (N, 3, uT, nav) at ``position`` (N, 3, m): each zone
    ``(x_m, y_m, radius_m, bx_ut, by_ut, bz_ut)`` adds its field within ``radius_m`` (horizontal)."""
    out = np.zeros((len(position), 3))
    for x, y, radius, bx, by, bz in zones:
        inside = np.hypot(position[:, 0] - x, position[:, 1] - y) <= radius
        out[inside] += (bx, by, bz)
    return out


def magnetometer(
    rng: np.random.Generator, position: NDArray[np.float64], q_sensor: NDArray[np.float64], opts: dict[str, Any]
) -> tuple[NDArray[np.float64], dict[str, Any]]:
    """The sensor-frame field (N, 3, uT) and what was drawn (``hard_iron_ut``).

    ``q_sensor`` is the sensor's attitude (sensor -> nav, [w, x, y, z]); the reading is
    ``C^T (m_earth + m_disturbance) + hard_iron + white noise`` (``mag_noise_ut`` per sample,
    ``mag_hard_iron_ut`` per axis, both zero without ``noise``).
    """
    field = earth_field_nav(opts) + disturbance_nav(position, opts["mag_disturbances"])
    c = quat.as_matrix(q_sensor)  # (N, 3, 3), sensor -> nav
    body = np.einsum("nji,nj->ni", c, field)  # C^T m
    hard_iron = np.zeros(3)
    if opts["noise"]:
        hard_iron = rng.normal(0.0, opts["mag_hard_iron_ut"], 3)
        body = body + hard_iron + rng.normal(0.0, opts["mag_noise_ut"], body.shape)
    return body, {"hard_iron_ut": hard_iron, "field_nav_ut": earth_field_nav(opts)}
