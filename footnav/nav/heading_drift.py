"""The position uncertainty that heading drift adds, which a ZUPT filter cannot see.

A zero-velocity update observes velocity, and through it roll, pitch and the horizontal gyro
bias, but never heading nor the gyro bias about the vertical: the heading error grows without
bound, and the position error it causes grows with the distance walked since. The 9-state
``ekf`` filter (and ``madgwick`` without a magnetometer) takes the gyro bias as known after the
initial standstill, so its covariance holds only the white-noise part of the heading error
(growing as sqrt(t)) and is overconfident over long walks (docs/concepts.md, "What position_std
means"). Two errors it leaves out dominate:

* the residual of the initial-standstill bias estimate, a constant yaw-rate error ``b0``
  (heading error ``b0 t``): the standard error of the still samples' mean angular rate;
* the bias random walk (density ``q``, heading error growing as ``q t^1.5 / sqrt(3)``).

A third, the gyro's scale-factor error ``k`` (a fraction; 0.5-3 % in consumer MEMS datasheets),
turns the heading by ``k`` times every turn walked: 1.8 deg per U-turn at 1 %. Turns one way and
back cancel; a walk that keeps turning the same way (laps of a building) accumulates it.

Their effect on position is linear along the trajectory (small heading errors): with the
unestimated yaw-rate error ``beta``, the scale error ``k`` and the heading error ``dpsi``::

    d(dp)/dt = dpsi J v,   d(dpsi)/dt = beta + k r_z,   d(beta)/dt = w,   dk/dt = 0,
    E[w w'] = q^2 delta(t)

(``J v = [-v_y, v_x]``, the velocity turned by 90 deg; ``r_z`` the estimated angular rate about
the navigation frame's vertical, from the attitude), started at the first stance with
``dp = 0, dpsi = 0, var(beta) = b0^2, var(k) = s_k^2``. :func:`heading_drift_cov` propagates
this 5-state covariance along the estimated velocity and attitude and returns its horizontal
position block, which the estimators add to their filter's position covariance. It changes no
estimate: it is a "consider" covariance (Schmidt 1966) for errors the filter does not estimate.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from footnav._numba import njit  # numba.njit that survives a read-only install
from footnav.core.types._arrays import _readonly  # read-only views: one compiled variant of _propagate
from footnav.nav.initial_alignment import MIN_STILL_SAMPLES

__all__ = ["heading_drift_cov", "with_heading_drift", "standstill_rate_std", "TURN_ON_BIAS_STD_RADPS", "GYRO_SCALE_STD"]

#: Std of a consumer MEMS gyro's turn-on bias after factory calibration (~0.1 deg/s, the
#: simulator's default): the yaw-rate error when the initial-standstill bias is not removed.
TURN_ON_BIAS_STD_RADPS = 2e-3

#: Std of a consumer MEMS gyro's scale-factor error after factory trimming, a fraction (0.5 %):
#: datasheet tolerances of 0.5-3 % are bounds, not stds. Sensors calibrated for scale do better.
GYRO_SCALE_STD = 5e-3


@njit(cache=True, error_model="numpy")
def _turn_about_vertical(q0, q1):
    """Angle (rad) of the rotation from attitude ``q0`` to ``q1`` about the nav frame's vertical:
    the z component of the rotation vector of ``q1 q0*`` (the shorter way)."""
    # q1 q0* written out: quaternion.multiply_nb needs (4,) buffers, which made this loop 1.6x slower
    w = q1[0] * q0[0] + q1[1] * q0[1] + q1[2] * q0[2] + q1[3] * q0[3]
    x = -q1[0] * q0[1] + q1[1] * q0[0] - q1[2] * q0[3] + q1[3] * q0[2]
    y = -q1[0] * q0[2] + q1[1] * q0[3] + q1[2] * q0[0] - q1[3] * q0[1]
    z = -q1[0] * q0[3] - q1[1] * q0[2] + q1[2] * q0[1] + q1[3] * q0[0]
    if w < 0.0:
        w, x, y, z = -w, -x, -y, -z
    s = np.sqrt(x * x + y * y + z * z)
    if s < 1e-12:
        return 2.0 * z
    return 2.0 * np.arctan2(s, w) / s * z


@njit(cache=True, error_model="numpy")
def _propagate(t, vel, quat, start, var_rate0, q2, var_scale, out):
    """The horizontal position covariance (xx, xy, yy) of the heading-drift model, in ``out``."""
    # P over [dp_x, dp_y, dpsi, beta, k]; F = I except F[0,2] = ax, F[1,2] = ay, F[2,3] = dt,
    # F[2,4] = turn, so F P F' is three row updates and the same three column updates
    p = np.zeros((5, 5))
    p[3, 3] = var_rate0
    p[4, 4] = var_scale
    for k in range(start + 1):
        out[k, 0] = 0.0
        out[k, 1] = 0.0
        out[k, 2] = 0.0
    for k in range(start + 1, len(t)):
        dt = t[k] - t[k - 1]
        ax, ay = -vel[k - 1, 1] * dt, vel[k - 1, 0] * dt  # dp += dpsi J v dt
        turn = _turn_about_vertical(quat[k - 1], quat[k])  # dpsi += k turn
        for j in range(5):  # rows 0 and 1 read row 2 before it changes
            p[0, j] += ax * p[2, j]
            p[1, j] += ay * p[2, j]
            p[2, j] += dt * p[3, j] + turn * p[4, j]
        for i in range(5):
            p[i, 0] += ax * p[i, 2]
            p[i, 1] += ay * p[i, 2]
            p[i, 2] += dt * p[i, 3] + turn * p[i, 4]
        p[3, 3] += q2 * dt
        out[k, 0] = p[0, 0]
        out[k, 1] = p[0, 1]
        out[k, 2] = p[1, 1]


def heading_drift_cov(
    t: NDArray[np.float64],
    velocity: NDArray[np.float64],
    start: int,
    rate_std_radps: float,
    walk_radps2_sqrthz: float,
    quaternion: NDArray[np.float64] | None = None,
    scale_std: float = 0.0,
) -> NDArray[np.float64]:
    """Horizontal position covariance from unestimated heading drift, (N, 3): xx, xy, yy in m^2.

    Parameters
    ----------
    t
        Times in s, (N,).
    velocity
        Estimated nav-frame velocity in m/s, (N, 3) (only x and y are used).
    start
        Sample where the heading error starts (the end of the alignment); zero before it.
    rate_std_radps
        Std of the constant yaw-rate error left at ``start`` (the bias estimate's), rad/s.
    walk_radps2_sqrthz
        Random walk of the gyro bias about the vertical, rad/s^2/sqrt(Hz).
    quaternion
        Estimated attitude, body to nav, [w, x, y, z], (N, 4): the turns the scale error
        multiplies. None: no turns (the scale term adds nothing).
    scale_std
        Std of the gyro scale-factor error, a fraction (0.01 is 1 %).
    """
    out = np.empty((len(t), 3))
    if quaternion is None:
        quaternion, scale_std = np.tile([1.0, 0.0, 0.0, 0.0], (len(t), 1)), 0.0
    if len(t):
        _propagate(
            _readonly(np.asarray(t, dtype=np.float64)),
            _readonly(np.asarray(velocity, dtype=np.float64)),
            _readonly(np.asarray(quaternion, dtype=np.float64)),
            int(min(max(start, 0), len(t) - 1)),
            float(rate_std_radps) ** 2,
            float(walk_radps2_sqrthz) ** 2,
            float(scale_std) ** 2,
            out,
        )
    return out


def with_heading_drift(
    pos_cov: NDArray[np.float64],
    t: NDArray[np.float64],
    velocity: NDArray[np.float64],
    quaternion: NDArray[np.float64],
    start: int,
    rate_std_radps: float,
    walk_radps2_sqrthz: float,
    scale_std: float,
    meta: dict,
) -> NDArray[np.float64]:
    """``pos_cov`` (N, >=3: xx, xy, yy first) plus :func:`heading_drift_cov`, as a new array.

    Records the three error sizes in ``meta["heading_drift"]``: every estimator that widens its
    ``position_std`` this way says by how much.
    """
    drift = heading_drift_cov(t, velocity, start, rate_std_radps, walk_radps2_sqrthz, quaternion, scale_std)
    meta["heading_drift"] = {
        "yaw_rate_std_radps": float(rate_std_radps),
        "yaw_bias_walk_radps2_sqrthz": float(walk_radps2_sqrthz),
        "gyro_scale_std": float(scale_std),
    }
    return np.concatenate([pos_cov[:, :3] + drift, pos_cov[:, 3:]], axis=1)


def standstill_rate_std(gyr: NDArray[np.float64], start: int, stop: int, still_gyr_max_radps: float) -> float:
    """Standard error (rad/s) of the mean angular rate of the still samples of ``start:stop``.

    The initial-standstill gyro bias is that mean (:func:`footnav.nav.initial_alignment.align_at_rest`,
    same choice of samples): its error is the rate's sample std over sqrt(n), the axes averaged
    (the sensor's vertical is any mix of them).
    """
    seg = np.asarray(gyr[start:stop], dtype=np.float64)
    still = np.linalg.norm(seg, axis=1) < still_gyr_max_radps
    if still.sum() < MIN_STILL_SAMPLES:  # as align_at_rest: then the whole range is used
        still[:] = True
    used = seg[still]
    if len(used) < 2:
        return 0.0
    return float(np.sqrt(np.mean(np.var(used, axis=0, ddof=1)) / len(used)))
