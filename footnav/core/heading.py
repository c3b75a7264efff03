"""The nav frame's heading: turn a one-foot solution so that its first step points along +x.

A foot-mounted IMU cannot observe its initial heading; footnav's nav frame takes x along the
first step. Turning a whole solution about z is exact for the error-state filters (gravity lies
along z, so the solution is symmetric under it): positions, velocities, attitude and the
horizontal position covariance all turn together.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray


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
    horizontal position covariance stored as xx, xy, yy, zz). Element-wise: only x, y (and the
    quaternion's left product with a yaw) change, and small matrix products are slow in numpy."""
    c, s = np.cos(angle), np.sin(angle)

    def turn(v):
        out = v.copy()
        out[:, 0] = c * v[:, 0] - s * v[:, 1]
        out[:, 1] = s * v[:, 0] + c * v[:, 1]
        return out

    xx, xy, yy = pos_cov[:, 0], pos_cov[:, 1], pos_cov[:, 2]
    cov = np.empty_like(pos_cov)
    cov[:, 0] = c * c * xx - 2 * c * s * xy + s * s * yy
    cov[:, 1] = c * s * (xx - yy) + (c * c - s * s) * xy
    cov[:, 2] = s * s * xx + 2 * c * s * xy + c * c * yy
    cov[:, 3] = pos_cov[:, 3]
    # [w, 0, 0, z] (x) q for the yaw quaternion [cos(a/2), 0, 0, sin(a/2)]
    w, z = np.cos(0.5 * angle), np.sin(0.5 * angle)
    q = np.empty_like(q_out)
    q[:, 0] = w * q_out[:, 0] - z * q_out[:, 3]
    q[:, 1] = w * q_out[:, 1] - z * q_out[:, 2]
    q[:, 2] = w * q_out[:, 2] + z * q_out[:, 1]
    q[:, 3] = w * q_out[:, 3] + z * q_out[:, 0]
    return turn(pos), turn(vel), q, cov


def turn_to_first_step(pos, vel, q_out, pos_cov, steps, meta: dict):
    """The solution turned so its first step points along +x (``meta["heading_rotation_rad"]``
    records the turn); unchanged when the foot never made a step. Returns pos, vel, q, std."""
    psi = heading_of_first_step(pos, steps)
    if psi is not None:
        pos, vel, q_out, pos_cov = rotate_about_z(-psi, pos, vel, q_out, pos_cov)
        meta["heading_rotation_rad"] = -psi
    return pos, vel, q_out, np.sqrt(np.maximum(pos_cov[:, [0, 2, 3]], 0.0))
