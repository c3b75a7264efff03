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

Their effect on position is linear along the trajectory (small heading errors): with the
unestimated yaw-rate error ``beta`` and the heading error ``dpsi``::

    d(dp)/dt = dpsi J v,   d(dpsi)/dt = beta,   d(beta)/dt = w,   E[w w'] = q^2 delta(t)

(``J v = [-v_y, v_x]``, the velocity turned by 90 deg), started at the first stance with
``dp = 0, dpsi = 0, var(beta) = b0^2``. :func:`heading_drift_cov` propagates this 4-state
covariance along the estimated velocity and returns its horizontal position block, which the
estimators add to their filter's position covariance. It changes no estimate: it is a
"consider" covariance (Schmidt 1966) for errors the filter does not estimate.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from footnav._numba import njit  # numba.njit that survives a read-only install
from footnav.core.types._arrays import _readonly  # read-only views: one compiled variant of _propagate
from footnav.nav.initial_alignment import MIN_STILL_SAMPLES

__all__ = ["heading_drift_cov", "standstill_rate_std", "TURN_ON_BIAS_STD_RADPS"]

#: Std of a consumer MEMS gyro's turn-on bias after factory calibration (~0.1 deg/s, the
#: simulator's default): the yaw-rate error when the initial-standstill bias is not removed.
TURN_ON_BIAS_STD_RADPS = 2e-3


@njit(cache=True, error_model="numpy")
def _propagate(t, vel, start, var_rate0, q2, out):
    """The horizontal position covariance (xx, xy, yy) of the heading-drift model, in ``out``."""
    # symmetric 4 x 4 over [dp_x, dp_y, dpsi, beta]
    pxx = pxy = pyy = pxp = pyp = pxb = pyb = ppp = ppb = 0.0
    pbb = var_rate0
    for k in range(start + 1):
        out[k, 0] = 0.0
        out[k, 1] = 0.0
        out[k, 2] = 0.0
    for k in range(start + 1, len(t)):
        dt = t[k] - t[k - 1]
        ax, ay = -vel[k - 1, 1] * dt, vel[k - 1, 0] * dt  # dp += dpsi J v dt
        # P <- F P F' + Q, F = [[1 0 ax 0] [0 1 ay 0] [0 0 1 dt] [0 0 0 1]], Q = q^2 dt on beta
        nxx = pxx + 2.0 * ax * pxp + ax * ax * ppp
        nxy = pxy + ax * pyp + ay * pxp + ax * ay * ppp
        nyy = pyy + 2.0 * ay * pyp + ay * ay * ppp
        nxp = pxp + ax * ppp + dt * (pxb + ax * ppb)
        nyp = pyp + ay * ppp + dt * (pyb + ay * ppb)
        nxb = pxb + ax * ppb
        nyb = pyb + ay * ppb
        npp = ppp + 2.0 * dt * ppb + dt * dt * pbb
        npb = ppb + dt * pbb
        pxx, pxy, pyy, pxp, pyp, pxb, pyb, ppp, ppb = nxx, nxy, nyy, nxp, nyp, nxb, nyb, npp, npb
        pbb += q2 * dt
        out[k, 0] = pxx
        out[k, 1] = pxy
        out[k, 2] = pyy


def heading_drift_cov(
    t: NDArray[np.float64], velocity: NDArray[np.float64], start: int, rate_std_radps: float, walk_radps2_sqrthz: float
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
    """
    out = np.empty((len(t), 3))
    if len(t):
        _propagate(
            _readonly(np.asarray(t, dtype=np.float64)),
            _readonly(np.asarray(velocity, dtype=np.float64)),
            int(min(max(start, 0), len(t) - 1)),
            float(rate_std_radps) ** 2,
            float(walk_radps2_sqrthz) ** 2,
            out,
        )
    return out


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
