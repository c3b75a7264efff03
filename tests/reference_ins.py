"""The strapdown step written in numpy: the tests' reference for footnav's compiled one."""

from __future__ import annotations

import numpy as np

import footnav
from footnav.nav import quaternion as quat

__all__ = ["nominal_step"]


def nominal_step(imu, k, q, v, p, f_prev, ba, bg):
    """One sample, k - 1 to k, of :func:`footnav.nav.mechanization.strapdown_step`: the attitude
    turned by the mean rate, velocity by Simpson's rule with the mid-interval attitude, position
    by the trapezoid rule. ``f_prev`` is f^n at k - 1; ``ba``, ``bg`` the bias estimates.
    Returns q, v, p and f^n at k (nav frame, SI)."""
    dt = imu.t[k] - imu.t[k - 1]
    w = 0.5 * ((imu.gyr[k - 1] - bg) + (imu.gyr[k] - bg)) * dt
    q_mid = quat.normalize(quat.multiply(q, quat.from_rotvec(0.5 * w)))
    q = quat.normalize(quat.multiply(q, quat.from_rotvec(w)))
    f_new = quat.as_matrix(q) @ (imu.acc[k] - ba)
    f_mid = quat.as_matrix(q_mid) @ (0.5 * (imu.acc[k - 1] + imu.acc[k]) - ba)
    a_mean = (f_prev + 4 * f_mid + f_new) / 6 - np.array([0.0, 0.0, footnav.GRAVITY_MPS2])
    v_new = v + a_mean * dt
    return q, v_new, p + 0.5 * (v + v_new) * dt, f_new
