"""The nav frame's heading: turn a one-foot solution so that its first step points along +x.

A foot-mounted IMU cannot observe its initial heading; footnav's nav frame takes x along the
first step. Turning a whole solution about z is exact for the error-state filters (gravity lies
along z, so the solution is symmetric under it): positions, velocities, attitude and the
horizontal position covariance all turn together. The turn is done in place, in one compiled
pass: the estimators hand over arrays nothing else holds.

A heading aid turns a finished solution by a heading error that changes along the walk:
:func:`turn_by` turns each sample's increment, velocity and attitude by its own angle, and
:func:`turn_result` does that to a fusion result's feet and path.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from footnav._numba import njit  # numba.njit that survives a read-only install
from footnav.core.types import FootTrajectory, FusionResult
from footnav.nav import quaternion as quat

__all__ = [
    "MIN_FIRST_STEP_M",
    "heading_of_first_step",
    "rotate_about_z",
    "turn_by",
    "turn_increments",
    "turn_result",
    "turn_to_first_step",
]

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


@njit(cache=True, error_model="numpy")
def _turn(angle, pos, vel, q_out, pos_cov, std):
    """One pass over the samples: positions, velocities, attitude and the horizontal position
    covariance (xx, xy, yy, zz) turned by ``angle`` about z in place; ``std`` (N, 3) from the
    turned covariance."""
    c, s = np.cos(angle), np.sin(angle)
    w, z = np.cos(0.5 * angle), np.sin(0.5 * angle)  # [w, 0, 0, z] (x) q: the yaw's left product
    for k in range(pos.shape[0]):
        x, y = pos[k, 0], pos[k, 1]
        pos[k, 0], pos[k, 1] = c * x - s * y, s * x + c * y
        x, y = vel[k, 0], vel[k, 1]
        vel[k, 0], vel[k, 1] = c * x - s * y, s * x + c * y
        q0, q1, q2, q3 = q_out[k, 0], q_out[k, 1], q_out[k, 2], q_out[k, 3]
        q_out[k, 0], q_out[k, 1] = w * q0 - z * q3, w * q1 - z * q2
        q_out[k, 2], q_out[k, 3] = w * q2 + z * q1, w * q3 + z * q0
        xx, xy, yy = pos_cov[k, 0], pos_cov[k, 1], pos_cov[k, 2]
        pos_cov[k, 0] = c * c * xx - 2 * c * s * xy + s * s * yy
        pos_cov[k, 1] = c * s * (xx - yy) + (c * c - s * s) * xy
        pos_cov[k, 2] = s * s * xx + 2 * c * s * xy + c * c * yy
        std[k, 0] = np.sqrt(max(pos_cov[k, 0], 0.0))
        std[k, 1] = np.sqrt(max(pos_cov[k, 2], 0.0))
        std[k, 2] = np.sqrt(max(pos_cov[k, 3], 0.0))


def rotate_about_z(angle: float, pos, vel, q_out, pos_cov):
    """Turn a nav-frame solution by ``angle`` rad about z, in place: positions, velocities (N, 3),
    attitude (N, 4) and the horizontal position covariance stored as xx, xy, yy, zz (N, 4); only
    x, y and the quaternion's left product with a yaw change. Returns the position std (N, 3)."""
    arrays = [np.asarray(a, dtype=np.float64) for a in (pos, vel, q_out, pos_cov)]
    if not all(a.flags.c_contiguous and a.flags.writeable for a in arrays):
        raise ValueError("rotate_about_z turns C-contiguous, writeable float64 arrays in place")
    std = np.empty((len(arrays[0]), 3))
    _turn(float(angle), *arrays, std)
    return std


def turn_to_first_step(pos, vel, q_out, pos_cov, steps, meta: dict):
    """The solution turned so its first step points along +x, **in place** (the caller's arrays
    change; ``meta["heading_rotation_rad"]`` records the turn); unchanged when the foot never
    made a step. Returns pos, vel, q, std (m, from the turned covariance)."""
    psi = heading_of_first_step(pos, steps)
    if psi is None:
        return pos, vel, q_out, np.sqrt(np.maximum(pos_cov[:, [0, 2, 3]], 0.0))
    meta["heading_rotation_rad"] = -psi
    return pos, vel, q_out, rotate_about_z(-psi, pos, vel, q_out, pos_cov)


def turn_increments(position: NDArray[np.float64], dpsi: NDArray[np.float64]) -> NDArray[np.float64]:
    """Positions (N, 3, m) whose increments are turned about z by ``-dpsi`` (rad, per sample,
    the increment into a sample turned by that sample's angle); the first stays where it is."""
    c, s = np.cos(-dpsi), np.sin(-dpsi)
    dp = np.diff(position, axis=0)
    turned = np.column_stack([c[1:] * dp[:, 0] - s[1:] * dp[:, 1], s[1:] * dp[:, 0] + c[1:] * dp[:, 1], dp[:, 2]])
    return np.vstack([position[:1], position[:1] + np.cumsum(turned, axis=0)])


def turn_by(traj: FootTrajectory, dpsi: NDArray[np.float64]) -> FootTrajectory:
    """``traj`` with each sample's heading turned by ``-dpsi`` (rad, per sample): its position
    increments, velocity and attitude about z; the first sample stays where it is."""
    pos = turn_increments(traj.position, dpsi)
    c, s = np.cos(-dpsi), np.sin(-dpsi)
    v = traj.velocity
    vel = np.column_stack([c * v[:, 0] - s * v[:, 1], s * v[:, 0] + c * v[:, 1], v[:, 2]])
    half = -0.5 * dpsi
    qz = np.column_stack([np.cos(half), np.zeros_like(half), np.zeros_like(half), np.sin(half)])
    return replace(traj, position=pos, velocity=vel, quaternion=quat.multiply(qz, traj.quaternion))


def turn_result(result: FusionResult, corrections: Sequence[Any], name: str) -> FusionResult:
    """A fusion result with each foot turned by its heading aid's correction.

    ``corrections`` holds one per foot (left, right; None for a missing foot), each with
    ``applied``, ``at(t)`` (the heading error, rad, at times t) and ``as_meta()``. A corrected
    foot's ``meta["heading_aid"]`` says what was done; the pedestrian path turns by the mean of
    the applied corrections.
    """
    feet, shifts = [], []
    for traj, found in zip((result.left, result.right), corrections):
        if traj is None or found is None:
            feet.append(traj)
            continue
        turned = turn_by(traj, found.at(traj.t)) if found.applied else traj
        feet.append(replace(turned, meta={**traj.meta, "heading_aid": {"name": name, **found.as_meta()}}))
        if found.applied:
            shifts.append(found.at(result.path.t))
    path = result.path
    if shifts:
        path = replace(path, position=turn_increments(path.position, np.mean(shifts, axis=0)))
    return replace(result, left=feet[0], right=feet[1], path=path)
