"""Heading drift removed with the magnetometer, read at stance and gated against disturbances.

A foot at rest knows its tilt well (the zero-velocity updates observe roll and pitch), so the
magnetometer's reading turned into the nav frame by the estimated attitude points to magnetic
north as the filter sees it. Earth's field does not move: a change of that direction along the
walk is the filter's heading error (Foxlin 2005, Sec. 4; Jimenez et al. 2010). Indoors, steel
and electronics bend the field; such a stance shows in the field's strength or its dip (Afzal
et al. 2011, "quasi-static field" detection) and is left out:

Roll and pitch at stance come from the accelerometer (gravity alone at rest), the yaw from the
filter: a filter's tilt error would bend the field's vertical part into its horizontal one.

1. Hard iron (a constant offset in the sensor frame, which turns with the heading and would be
   taken for drift): a least-squares sphere fit to the whole recording's readings, used only
   when the foot's attitudes cover the sphere well enough to fix it (``min_spread``).
2. Per stance, each sample's field in the nav frame: strength and dip against the walk's
   medians (``magnitude_tol``, ``dip_tol_deg``); a stance counts when half its samples pass,
   and its north is the circular mean of the passing samples' horizontal direction.
3. The heading error: each counted stance's north relative to the first, a running median over
   ``window_s`` (the gyro's drift is slow, a missed disturbance is not), interpolated in time;
   the walk keeps its start heading.

Applied only when enough stances count (``min_stances``, ``min_fraction``); otherwise the
reason is recorded and the trajectory stays as it is.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from footnav.core.types import FootTrajectory, ImuData
from footnav.nav import quaternion as quat
from footnav.nav.initial_alignment import align_at_rest

__all__ = ["MagneticCorrection", "hard_iron_offset", "magnetic_heading_correction"]

#: Rounds of the hard-iron fit (each re-selects the readings on the sphere).
_FIT_ROUNDS = 4


@dataclass(frozen=True, eq=False)
class MagneticCorrection:
    """The heading error the magnetometer showed on one foot's walk, and what was done.

    Attributes
    ----------
    applied
        False when too few stances passed the gates (or the data could not be used).
    reason
        Why not applied ('' when applied).
    knots_s, knots_rad
        Times (s) and heading errors (rad) the correction interpolates.
    stances, accepted
        Stance phases seen and those whose field passed the gates.
    rejected_magnitude, rejected_dip
        Stances left out for the field's strength, for its dip.
    field_median, dip_median_deg
        The walk's median field strength (the recording's unit) and dip (deg, down positive).
    hard_iron
        The offset removed (recording's unit, sensor frame), or None with the reason in
        ``hard_iron_note``.
    """

    applied: bool
    reason: str
    knots_s: NDArray[np.float64] = field(default_factory=lambda: np.zeros(0))
    knots_rad: NDArray[np.float64] = field(default_factory=lambda: np.zeros(0))
    stances: int = 0
    accepted: int = 0
    rejected_magnitude: int = 0
    rejected_dip: int = 0
    field_median: float = float("nan")
    dip_median_deg: float = float("nan")
    hard_iron: NDArray[np.float64] | None = None
    hard_iron_note: str = ""

    def at(self, t: NDArray[np.float64]) -> NDArray[np.float64]:
        """The heading error (rad) at times ``t`` (s): 0 everywhere when not applied."""
        if not self.applied:
            return np.zeros(len(t))
        return np.interp(t, self.knots_s, self.knots_rad)

    def as_meta(self) -> dict:
        """Plain values for a trajectory's meta."""
        ends = np.degrees(self.knots_rad) if self.applied else np.zeros(1)
        return {
            "applied": self.applied,
            "reason": self.reason,
            "stances": self.stances,
            "accepted": self.accepted,
            "rejected_magnitude": self.rejected_magnitude,
            "rejected_dip": self.rejected_dip,
            "field_median": round(float(self.field_median), 4),
            "dip_median_deg": round(float(self.dip_median_deg), 3),
            "hard_iron": None if self.hard_iron is None else [round(float(x), 4) for x in self.hard_iron],
            "hard_iron_note": self.hard_iron_note,
            "correction_end_deg": round(float(ends[-1]), 4),
            "correction_max_deg": round(float(np.abs(ends).max()), 4),
        }


def hard_iron_offset(
    mag: NDArray[np.float64],
    up: NDArray[np.float64] | None = None,
    *,
    dip_tol_deg: float = 3.0,
    min_spread: float = 0.05,
) -> tuple[NDArray[np.float64] | None, str]:
    """The sensor-frame offset of the readings' sphere (least squares), or None and why.

    ``|m - c|^2 = r^2`` is linear in ``c`` and ``k = r^2 - |c|^2``: ``2 m . c + k = |m|^2``. Fitted
    in rounds, each on the readings that lie on the last round's sphere (distance from its centre
    within 3 MADs of the median; first round: centre zero, a calibrated sensor's) and, given the
    nav frame's up in the sensor frame ``up`` (N, 3) at each reading, whose dip is within
    ``dip_tol_deg`` of the median dip: a disturbance that keeps the field's strength still bends
    its dip (the tilt is known at every sample; the heading is not needed). A fit needs readings
    in every direction: the smallest eigenvalue of the unit directions' scatter (1/3 each for a
    full sphere) must reach ``min_spread``; a foot that only walked straight ahead does not.
    """
    m = np.asarray(mag, dtype=np.float64)
    finite = np.all(np.isfinite(m), axis=1)
    m = m[finite]
    up = None if up is None else np.asarray(up, dtype=np.float64)[finite]
    if len(m) < 10:
        return None, "too few readings"
    centre = np.zeros(3)
    for _ in range(_FIT_ROUNDS):
        d = m - centre
        r = np.linalg.norm(d, axis=1)
        med = np.median(r)
        keep = np.abs(r - med) <= 3.0 * 1.4826 * np.median(np.abs(r - med)) + 1e-12 * med
        if up is not None:
            dip = np.degrees(np.arcsin(np.clip(-np.einsum("ij,ij->i", up, d) / np.maximum(r, 1e-300), -1.0, 1.0)))
            keep &= np.abs(dip - np.median(dip[keep])) <= dip_tol_deg
        if keep.sum() < 10:
            return None, "too few undisturbed readings"
        a = np.column_stack([2.0 * m[keep], np.ones(keep.sum())])
        sol, *_ = np.linalg.lstsq(a, np.einsum("ij,ij->i", m[keep], m[keep]), rcond=None)
        centre = sol[:3]
    u = (m[keep] - centre) / np.linalg.norm(m[keep] - centre, axis=1)[:, None]
    spread = float(np.linalg.eigvalsh(u.T @ u / len(u))[0])
    if spread < min_spread:
        return None, f"attitudes cover too little of the sphere (spread {spread:.3f} < {min_spread})"
    return centre, ""


def _samples_of(traj: FootTrajectory, imu: ImuData) -> NDArray[np.int64]:
    """Index into ``imu`` of each trajectory sample (the same samples, or the nearest in time)."""
    if len(imu.t) == len(traj.t) and np.array_equal(imu.t, traj.t):
        return np.arange(len(traj.t))
    k = np.clip(np.searchsorted(imu.t, traj.t), 1, len(imu.t) - 1)
    return np.where(np.abs(imu.t[k - 1] - traj.t) <= np.abs(imu.t[k] - traj.t), k - 1, k)


def _stance_attitudes(
    traj: FootTrajectory, acc: NDArray[np.float64], gyr: NDArray[np.float64], steps: NDArray[np.int64]
) -> NDArray[np.float64]:
    """Each stance sample's attitude (sensor -> nav): roll and pitch from the stance's mean
    specific force (gravity alone at rest), yaw the filter's. A roll error dr of the filter
    turns the field's vertical part into the horizontal and reads as a heading error of up to
    tan(dip) dr, changing with the walking direction (1.4 deg of roll: +-2.4 deg at dip 60); the
    accelerometer's tilt at rest is off by only its bias over g."""
    out = [np.zeros((0, 4))]
    for a, b in steps:
        if b <= a:
            continue
        level = align_at_rest(acc, gyr, a, b).quaternion  # roll and pitch, yaw zero
        out.append(quat.multiply(quat.from_yaw(quat.yaw(traj.quaternion[a:b])), level))
    return np.concatenate(out)


def _running_median(t: NDArray[np.float64], x: NDArray[np.float64], window_s: float) -> NDArray[np.float64]:
    half = 0.5 * window_s
    lo = np.searchsorted(t, t - half, side="left")
    hi = np.searchsorted(t, t + half, side="right")
    return np.array([np.median(x[a:b]) for a, b in zip(lo, hi)])


def magnetic_heading_correction(
    traj: FootTrajectory,
    imu: ImuData,
    *,
    magnitude_tol: float = 0.05,
    dip_tol_deg: float = 3.0,
    window_s: float = 20.0,
    min_stances: int = 10,
    min_fraction: float = 0.3,
    hard_iron: bool = True,
    min_spread: float = 0.05,
) -> MagneticCorrection:
    """Find one foot's heading error from its magnetometer at stance (see the module).

    Parameters
    ----------
    traj
        The foot's trajectory (nav frame, z up; attitude sensor -> nav) with its stance intervals.
    imu
        The foot's recording, with ``mag`` (any unit: only ratios and directions are used).
    magnitude_tol
        A sample passes when its field strength is within this fraction of the walk's median.
    dip_tol_deg
        A sample passes when its dip is also within this of the walk's median dip, deg.
    window_s
        Running median of the stances' heading errors over this window, s.
    min_stances, min_fraction
        Stances that must pass, in number and as a share of all, for the correction to apply.
    hard_iron
        Fit and remove a hard-iron offset (when the attitudes allow the fit).
    min_spread
        Coverage of the sphere the hard-iron fit needs (:func:`hard_iron_offset`).
    """
    if imu.mag is None:
        return MagneticCorrection(False, "the recording has no magnetometer")
    steps = np.asarray(traj.steps).reshape(-1, 2)
    if len(steps) < 2:
        return MagneticCorrection(False, "fewer than two stance phases")
    sample = _samples_of(traj, imu)
    raw = np.asarray(imu.mag, dtype=np.float64)[sample]
    up = quat.as_matrix(traj.quaternion)[:, 2, :]  # row 2 of C (sensor -> nav): nav up in the sensor frame
    offset, note = (
        hard_iron_offset(raw, up, dip_tol_deg=dip_tol_deg, min_spread=min_spread)
        if hard_iron
        else (None, "not asked for")
    )
    mag = raw if offset is None else raw - offset
    idx = np.concatenate([np.arange(a, b) for a, b in steps])
    m_nav = np.einsum(
        "nij,nj->ni", quat.as_matrix(_stance_attitudes(traj, imu.acc[sample], imu.gyr[sample], steps)), mag[idx]
    )
    strength = np.linalg.norm(m_nav, axis=1)
    horizontal = np.hypot(m_nav[:, 0], m_nav[:, 1])
    dip = np.degrees(np.arctan2(-m_nav[:, 2], horizontal))
    ok_all = np.isfinite(strength) & (strength > 0)
    if not ok_all.any():
        return MagneticCorrection(False, "no finite field readings at stance", stances=len(steps))
    f_med, dip_med = float(np.median(strength[ok_all])), float(np.median(dip[ok_all]))
    pass_mag = ok_all & (np.abs(strength - f_med) <= magnitude_tol * f_med)
    pass_dip = ok_all & (np.abs(dip - dip_med) <= dip_tol_deg)
    north = np.arctan2(m_nav[:, 1], m_nav[:, 0])
    bounds = np.concatenate([[0], np.cumsum(steps[:, 1] - steps[:, 0])])
    times, heads = [], []
    rej_mag = rej_dip = 0
    for k in range(len(steps)):
        sl = slice(bounds[k], bounds[k + 1])
        n = bounds[k + 1] - bounds[k]
        good = pass_mag[sl] & pass_dip[sl]
        if 2 * good.sum() >= n > 0:
            times.append(traj.t[(steps[k, 0] + steps[k, 1] - 1) // 2])
            heads.append(float(np.angle(np.exp(1j * north[sl][good]).mean())))
        elif 2 * pass_mag[sl].sum() < n:
            rej_mag += 1
        else:
            rej_dip += 1
    base = {
        "stances": len(steps),
        "accepted": len(heads),
        "rejected_magnitude": rej_mag,
        "rejected_dip": rej_dip,
        "field_median": f_med,
        "dip_median_deg": dip_med,
        "hard_iron": offset,
        "hard_iron_note": note,
    }
    if len(heads) < max(min_stances, 2) or len(heads) < min_fraction * len(steps):
        why = (
            f"{len(heads)} of {len(steps)} stances passed the field's gates "
            f"(need {min_stances} and {min_fraction:.0%}): a disturbed field"
        )
        return MagneticCorrection(False, why, **base)
    t_k = np.array(times)
    err = np.unwrap(np.array(heads))
    err = _running_median(t_k, err - err[0], window_s)
    return MagneticCorrection(True, "", t_k, err - err[0], **base)
