"""The nav frame's heading: turn a one-foot solution so that its first step points along +x.

A foot-mounted IMU cannot observe its initial heading; footnav's nav frame takes x along the
first step. Turning a whole solution about z is exact for the error-state filters (gravity lies
along z, so the solution is symmetric under it): positions, velocities, attitude and the
horizontal position covariance all turn together.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from footnav.core import quaternion as quat

__all__ = ["MIN_FIRST_STEP_M", "heading_of_first_step", "rotate_about_z", "turn_to_first_step"]

#: Footprints closer than this (m) do not define a walking direction.
MIN_FIRST_STEP_M = 0.2


def heading_of_first_step(position: NDArray[np.float64], steps: NDArray[np.int64]) -> float | None:
    """Heading (rad, about nav z) of the first footprint-to-footprint displacement longer than
    ``MIN_FIRST_STEP_M``, or None when the foot never moved that far."""
    if len(steps) < 2:
        return None
    first = position[steps[0, 0] : steps[0, 1]].mean(axis=0)
    for a, b in steps[1:]:
        d = position[a:b].mean(axis=0) - first
        if np.hypot(d[0], d[1]) > MIN_FIRST_STEP_M:
            return float(np.arctan2(d[1], d[0]))
    return None


def rotate_about_z(angle: float, pos, vel, q_out, pos_cov):
    """Turn a nav-frame solution by ``angle`` rad about z (positions, velocities, attitude, and the
    horizontal position covariance stored as xx, xy, yy, zz)."""
    c, s = np.cos(angle), np.sin(angle)
    rot = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
    xx, xy, yy = pos_cov[:, 0], pos_cov[:, 1], pos_cov[:, 2]
    cov = np.stack(
        [c * c * xx - 2 * c * s * xy + s * s * yy, c * s * (xx - yy) + (c * c - s * s) * xy, s * s * xx + 2 * c * s * xy + c * c * yy, pos_cov[:, 3]],
        axis=1,
    )
    # r (x) q for every row q is q @ L(r)' with L(r) the left-multiplication matrix of r
    w, _, _, z = quat.from_yaw(angle)
    left = np.array([[w, 0.0, 0.0, -z], [0.0, w, -z, 0.0], [0.0, z, w, 0.0], [z, 0.0, 0.0, w]])
    return pos @ rot.T, vel @ rot.T, q_out @ left.T, cov


def turn_to_first_step(pos, vel, q_out, pos_cov, steps, meta: dict):
    """The solution turned so its first step points along +x (``meta["heading_rotation_rad"]``
    records the turn); unchanged when the foot never made a step. Returns pos, vel, q, std."""
    psi = heading_of_first_step(pos, steps)
    if psi is not None:
        pos, vel, q_out, pos_cov = rotate_about_z(-psi, pos, vel, q_out, pos_cov)
        meta["heading_rotation_rad"] = -psi
    return pos, vel, q_out, np.sqrt(np.maximum(pos_cov[:, [0, 2, 3]], 0.0))
