"""One simulated foot: a rigid body pivoting on toe and heel, its pose, rates and specific force.

The pose is ``p(t) = X(t) - C(t) c(t)`` (see :mod:`footnav.data.simulate`); this module evaluates
it at the sample times from the gait plan's swings, with the heel-strike impact transient.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from footnav.core.types import GRAVITY_MPS2
from footnav.data.simulate.gait import _FOOT_FLAT, _HEEL_OFF, _STANCE, _SWING, _Swings
from footnav.data.simulate.profiles import _bump, _polyval, _quintic_coefficients, _smoothstep
from footnav.nav import quaternion as quat

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

# Samples this close to heel-off or foot-flat are taken as stance: the profiles are at rest there
# to second order, so the motion this ignores is ~1e-15 m/s.
_EVENT_TIME_TOL_S = 1e-9

# The heel-strike impact wavelet is cut this many sigma from its centre.
_IMPACT_CUT = 6.0


@dataclass(frozen=True)
class _FootMotion:
    """Noise-free motion of one foot's sensor at the sample times (sensor frame = foot frame)."""

    position: NDArray[np.float64]
    velocity: NDArray[np.float64]
    quaternion: NDArray[np.float64]
    gyr: NDArray[np.float64]
    acc: NDArray[np.float64]
    phase: NDArray[np.int8]


def _foot_motion(t: NDArray[np.float64], sw: _Swings, opts: dict[str, Any], twist_rad: float = 0.0) -> _FootMotion:
    """Evaluate the gait model of one foot at times ``t`` (N,), fully vectorised.

    ``twist_rad``: the turn about the vertical through the sensor of each flat-foot stance that
    lies between two swings (``stance_twist_deg`` with this foot's sign); 0 leaves it still.
    """
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
    if twist_rad:
        # the shoe twists about the leg while flat (docs/heading.md measures 1-17 deg/s on real
        # feet): a min-jerk turn from foot-flat to the next heel-off, undone by the next swing
        inner = (ks >= 0) & (ks + 1 < len(sw.t_heel_off))
        k_in = ks[inner]
        t0 = sw.t_foot_flat[k_in]
        span = sw.t_heel_off[k_in + 1] - t0
        s_tw, s_tw_d, _ = _smoothstep(np.clip((t[still[inner]] - t0) / span, 0.0, 1.0), span)
        stand_h[inner] += twist_rad * s_tw
        gyr[still[inner], 2] = twist_rad * s_tw_d
    pos[still, :2] = stand_xy
    pos[still, 2] = np.where(ks >= 0, sw.z_to[np.maximum(ks, 0)], sw.z_from[0])
    q[still] = quat.from_yaw(stand_h)
    acc[still, 2] = GRAVITY_MPS2

    moving = np.flatnonzero(phase != _STANCE)
    # a swing after a twisted stance starts from the twisted heading (every swing but the first)
    twist_from = twist_rad * (k[moving] >= 1) if twist_rad else None
    m = _moving_motion(t[moving], phase[moving], k[moving], sw, opts, twist_from)
    pos[moving], vel[moving], q[moving], gyr[moving], acc[moving] = m
    return _FootMotion(pos, vel, q, gyr, acc, phase)


def _moving_motion(
    t: NDArray[np.float64],
    phase: NDArray[np.int8],
    k: NDArray[np.int64],
    sw: _Swings,
    opts: dict[str, Any],
    twist_from: NDArray[np.float64] | None = None,
) -> tuple[NDArray, NDArray, NDArray, NDArray, NDArray]:
    """Position, velocity, quaternion, body rate and specific force in heel-off, swing and foot-flat.

    ``k`` (M,) is the swing each sample belongs to; ``twist_from`` (M,) the turn the stance
    before it left on the foot's heading (None: none).
    """
    n = len(t)
    t_start = np.select(
        [phase == _HEEL_OFF, phase == _SWING], [sw.t_heel_off[k], sw.t_toe_off[k]], default=sw.t_heel_strike[k]
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
    if twist_from is not None:
        h_from = h_from + twist_from
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
    omega_d = np.stack([-c_th * th_d * psi_d - s_th * psi_dd, th_dd, -s_th * th_d * psi_d + c_th * psi_dd], axis=-1)

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
