"""Heading drift removed along a building's dominant directions (HDR / HDE).

Buildings are walked along a few directions, usually four at right angles. Borenstein et al.
(2009, "Heuristic drift reduction for gyroscopes in vehicle tracking applications", HDR) and
Jimenez et al. (2012, "Improved heuristic drift elimination (iHDE) for pedestrian navigation in
complex buildings") correct a foot-mounted INS's heading at each step that runs straight along
one of them. Here the directions are learned from the walk itself and the correction is made
over the whole walk, as a smoother would make a heading measurement per straight stretch:

1. Strides (footprint to footprint, longer than ``min_stride_m``) whose heading is within
   ``straight_deg`` of both neighbours' are straight.
2. The grid: the length-weighted circular mean of ``n_directions`` x heading over the straight
   strides; its resultant length (0-1) is the grid's strength. Below ``min_strength`` (open
   ground, curves, a walk of no dominant direction) nothing is changed.
3. Stretches: runs of at least ``min_stretch_strides`` straight strides along one grid direction
   and within ``gate_deg`` of it. A stretch's heading error is the direction of its first to its
   last footprint minus the grid direction.
4. The heading error over time: constant along each stretch, linear in time between two
   (through the turn between them, where a gyro scale error adds its share), constant before
   the first and after the last, taken relative to the first stretch's (the walk keeps its
   start heading). The trajectory's increments, velocity and attitude are turned by minus it.

Assumptions, stated: the walk follows the grid where it runs straight (a corridor at 80 degrees
to the others is taken for drift), and the heading error changes slowly along a stretch.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from footnav.core.types import FootTrajectory
from footnav.nav import quaternion as quat

__all__ = ["HeadingCorrection", "dominant_direction_correction"]


@dataclass(frozen=True, eq=False)
class HeadingCorrection:
    """The heading error found on one foot's walk and what was done about it.

    Attributes
    ----------
    applied
        False when the walk has no dominant direction or fewer than two stretches.
    reason
        Why not applied ('' when applied).
    strength
        Resultant length (0-1) of the straight strides' headings on the grid.
    grid_rad
        The grid's first direction, rad about z from +x.
    knots_s, knots_rad
        Times (s) and heading errors (rad) the correction interpolates.
    straight_fraction
        Share of the distance walked on straight strides.
    stretches
        One dict per stretch: first and last stride, direction index, heading error (deg).
    """

    applied: bool
    reason: str
    strength: float
    grid_rad: float
    knots_s: NDArray[np.float64] = field(default_factory=lambda: np.zeros(0))
    knots_rad: NDArray[np.float64] = field(default_factory=lambda: np.zeros(0))
    straight_fraction: float = 0.0
    stretches: list[dict] = field(default_factory=list)

    def at(self, t: NDArray[np.float64]) -> NDArray[np.float64]:
        """The heading error (rad) at times ``t`` (s): 0 everywhere when not applied."""
        if not self.applied:
            return np.zeros(len(t))
        return np.interp(t, self.knots_s, self.knots_rad)

    def as_meta(self) -> dict:
        """Plain values for a trajectory's meta."""
        return {
            "applied": self.applied,
            "reason": self.reason,
            "strength": round(float(self.strength), 4),
            "grid_deg": round(float(np.degrees(self.grid_rad)), 3),
            "straight_fraction": round(float(self.straight_fraction), 4),
            "stretches": self.stretches,
            "correction_end_deg": round(float(np.degrees(self.knots_rad[-1])), 4) if self.applied else 0.0,
            "correction_max_deg": round(float(np.degrees(np.abs(self.knots_rad).max())), 4) if self.applied else 0.0,
        }


def dominant_direction_correction(
    traj: FootTrajectory,
    *,
    n_directions: int = 4,
    straight_deg: float = 20.0,
    gate_deg: float = 15.0,
    min_stride_m: float = 0.4,
    min_stretch_strides: int = 3,
    min_strength: float = 0.5,
) -> HeadingCorrection:
    """Find one foot's heading error along the walk's dominant directions (see the module).

    Parameters
    ----------
    traj
        The foot's trajectory (nav frame, z up) with its stance intervals.
    n_directions
        Directions of the grid, evenly spaced (4: right angles).
    straight_deg
        A stride is straight when its heading is within this of both neighbours', deg.
    gate_deg
        A straight stride counts when within this of its grid direction, deg.
    min_stride_m
        Shorter strides (turning on the spot, shuffling) are never straight, m.
    min_stretch_strides
        Straight strides a stretch needs.
    min_strength
        Below this resultant length (0-1) the walk has no dominant direction.
    """
    fp = traj.footprints
    if len(fp) < min_stretch_strides + 2:
        return HeadingCorrection(False, "too few footprints", 0.0, 0.0)
    mid_t = np.array([traj.t[(a + b - 1) // 2] for a, b in traj.steps])
    d = np.diff(fp[:, :2], axis=0)
    length = np.hypot(d[:, 0], d[:, 1])
    heading = np.arctan2(d[:, 1], d[:, 0])
    limit = np.radians(straight_deg)
    turn_in = np.abs(quat.wrap_angle(np.diff(heading, prepend=heading[0])))
    turn_out = np.abs(quat.wrap_angle(np.diff(heading, append=heading[-1])))
    straight = (length > min_stride_m) & (turn_in < limit) & (turn_out < limit)
    walked = float(length.sum())
    straight_fraction = float(length[straight].sum()) / walked if walked > 0 else 0.0
    resultant = np.sum(length[straight] * np.exp(1j * n_directions * heading[straight]))
    strength = abs(resultant) / max(float(length[straight].sum()), 1e-12)
    grid = float(np.angle(resultant)) / n_directions
    if strength < min_strength or straight.sum() < min_stretch_strides:
        why = f"no dominant direction (strength {strength:.2f} < {min_strength})"
        return HeadingCorrection(False, why, strength, grid, straight_fraction=straight_fraction)
    step = 2.0 * np.pi / n_directions
    off = quat.wrap_angle(n_directions * (heading - grid)) / n_directions  # from the nearest grid direction
    direction = np.round((heading - grid) / step).astype(int) % n_directions
    use = straight & (np.abs(off) < np.radians(gate_deg))
    stretches: list[tuple[int, int, float]] = []
    k, n = 0, len(heading)
    while k < n:
        if not use[k]:
            k += 1
            continue
        j = k
        while j + 1 < n and use[j + 1] and direction[j + 1] == direction[k]:
            j += 1
        if j - k + 1 >= min_stretch_strides:
            dd = fp[j + 1, :2] - fp[k, :2]
            err = float(quat.wrap_angle(n_directions * (np.arctan2(dd[1], dd[0]) - grid)) / n_directions)
            stretches.append((k, j, err))
        k = j + 1
    if len(stretches) < 2:
        return HeadingCorrection(
            False,
            f"{len(stretches)} straight stretch(es): nothing to compare",
            strength,
            grid,
            straight_fraction=straight_fraction,
        )
    knots_s, knots = [], []
    for a, b, err in stretches:  # stride k runs from footprint k to k + 1
        knots_s += [mid_t[a], mid_t[b + 1]]
        knots += [err, err]
    knots_rad = np.array(knots) - knots[0]
    info = [
        {
            "first_stride": a,
            "last_stride": b,
            "direction": int(direction[a]),
            "error_deg": round(float(np.degrees(e)), 3),
        }
        for a, b, e in stretches
    ]
    return HeadingCorrection(True, "", strength, grid, np.array(knots_s), knots_rad, straight_fraction, info)
