"""Strapdown inertial mechanization for a foot-mounted IMU (Zhao et al. (2019), eq. 1).

Simplified navigation equations, valid for the low speeds and short ranges of walking: Earth
rotation, curvature, Coriolis and centrifugal terms are neglected (Zhao et al. (2019), section II-A)::

    dC_b^n/dt = C_b^n [w_b x],   dv^n/dt = C_b^n f^b + g^n,   dp^n/dt = v^n

with g^n = [0, 0, -GRAVITY_MPS2] (nav z up). Sample k holds the instantaneous rates at t_k; the
step from k-1 to k integrates attitude with the mean angular rate (rotation vector
(w_{k-1} + w_k) dt / 2), velocity by Simpson's rule with the mid-interval attitude, and position
with the trapezoidal rule.

What no rule on the samples can recover: over one motion between rests, the local errors of any
of them (trapezoid, this Simpson step, cubic interpolation) telescope to -dt^2 / 12 times the sum
of the jumps of the nav-frame jerk (Euler-Maclaurin). That is zero for a jerk-continuous gait;
the simulator's quintic gait jumps by +2700 m/s^3 vertically per swing, so its noise-free walks
end about 2.3 mm per step low at 100 Hz and 0.14 mm at 400 Hz
(``tests/estimators/test_vertical.py``).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from footnav._numba import njit  # numba.njit that survives a read-only install
from footnav.core.types import GRAVITY_MPS2, ImuData
from footnav.nav.quaternion import as_matrix_nb, from_rotvec_nb, normalize_nb

__all__ = ["strapdown_step", "strapdown"]


@njit(cache=True, inline="always", error_model="numpy")
def strapdown_step(q, v, p, f_n, f, acc_prev, gyr_prev, acc, gyr, dt, dq, q_tmp, c):
    """Advance attitude, velocity and position of row ``f`` by one sample, in place.

    Attitude turns by the rotation vector (w_{k-1} + w_k) dt / 2. Velocity integrates C f by
    Simpson's rule with the attitude at mid-interval: the trapezoidal rule on C_{k-1} f_{k-1} and
    C_k f_k errs by [w x]^2 f dt^3 / 12 per sample, which does not cancel over a swing (a foot
    turns at up to 10 rad/s: 2 mm/s per swing at 100 Hz); Simpson's rule is exact for the
    rotation's second-order term. Position: trapezoidal rule on v.

    Parameters
    ----------
    q
        Attitude quaternions [w, x, y, z] body -> nav (F, 4); row f at k-1 becomes k.
    v, p
        Velocities (m/s) and positions (m) in nav (F, 3); row f at k-1 becomes k.
    f_n
        Specific forces in nav (F, 3) in m/s^2; row f at k-1 becomes the value at k (the EKF's
        F needs it).
    f
        The row to advance (the foot). Whole arrays and a row, not row views: a view per sample
        costs reference counting in the compiled loops.
    acc_prev, gyr_prev, acc, gyr
        Bias-corrected specific force (m/s^2) and angular rate (rad/s) at k-1 and k, body frame.
    dt
        t_k - t_{k-1} in s.
    dq, q_tmp, c
        Scratch: (4,), (4,), (3, 3).
    """
    h = 0.25 * dt  # half of the half-interval rotation: two half turns make the whole one
    from_rotvec_nb((gyr_prev[0] + gyr[0]) * h, (gyr_prev[1] + gyr[1]) * h, (gyr_prev[2] + gyr[2]) * h, dq)
    # body-side increment: C_mid = C_{k-1} exp([w dt/2 x])
    w, x, y, z = q[f, 0], q[f, 1], q[f, 2], q[f, 3]
    q_tmp[0] = w * dq[0] - x * dq[1] - y * dq[2] - z * dq[3]
    q_tmp[1] = w * dq[1] + x * dq[0] + y * dq[3] - z * dq[2]
    q_tmp[2] = w * dq[2] - x * dq[3] + y * dq[0] + z * dq[1]
    q_tmp[3] = w * dq[3] + x * dq[2] - y * dq[1] + z * dq[0]
    normalize_nb(q_tmp)
    as_matrix_nb(q_tmp, c)
    f_mid = (
        c[0, 0] * (acc_prev[0] + acc[0]) + c[0, 1] * (acc_prev[1] + acc[1]) + c[0, 2] * (acc_prev[2] + acc[2]),
        c[1, 0] * (acc_prev[0] + acc[0]) + c[1, 1] * (acc_prev[1] + acc[1]) + c[1, 2] * (acc_prev[2] + acc[2]),
        c[2, 0] * (acc_prev[0] + acc[0]) + c[2, 1] * (acc_prev[1] + acc[1]) + c[2, 2] * (acc_prev[2] + acc[2]),
    )  # 2 C_mid f_mid, with f_mid the mean of the two samples
    w, x, y, z = q_tmp[0], q_tmp[1], q_tmp[2], q_tmp[3]
    q_tmp[0] = w * dq[0] - x * dq[1] - y * dq[2] - z * dq[3]
    q_tmp[1] = w * dq[1] + x * dq[0] + y * dq[3] - z * dq[2]
    q_tmp[2] = w * dq[2] - x * dq[3] + y * dq[0] + z * dq[1]
    q_tmp[3] = w * dq[3] + x * dq[2] - y * dq[1] + z * dq[0]
    normalize_nb(q_tmp)
    for i in range(4):
        q[f, i] = q_tmp[i]
    as_matrix_nb(q_tmp, c)
    sixth = dt / 6.0
    for i in range(3):
        fi = c[i, 0] * acc[0] + c[i, 1] * acc[1] + c[i, 2] * acc[2]
        a_prev = f_n[f, i]
        f_n[f, i] = fi
        dv = sixth * (a_prev + 2.0 * f_mid[i] + fi)
        if i == 2:
            dv -= GRAVITY_MPS2 * dt
        v_new = v[f, i] + dv
        p[f, i] += 0.5 * (v[f, i] + v_new) * dt
        v[f, i] = v_new


@njit(cache=True, error_model="numpy")
def _strapdown_loop(t, acc, gyr, q0, v0, p0, quat, vel, pos):
    n = len(t)
    q = q0.reshape(1, 4).copy()
    v = v0.reshape(1, 3).copy()
    p = p0.reshape(1, 3).copy()
    f_n = np.zeros((1, 3))
    dq = np.zeros(4)
    q_tmp = np.zeros(4)
    c = np.zeros((3, 3))
    as_matrix_nb(q0, c)
    for i in range(3):
        f_n[0, i] = c[i, 0] * acc[0, 0] + c[i, 1] * acc[0, 1] + c[i, 2] * acc[0, 2]
    quat[0] = q[0]
    vel[0] = v[0]
    pos[0] = p[0]
    for k in range(1, n):
        strapdown_step(q, v, p, f_n, 0, acc[k - 1], gyr[k - 1], acc[k], gyr[k], t[k] - t[k - 1], dq, q_tmp, c)
        quat[k] = q[0]
        vel[k] = v[0]
        pos[k] = p[0]


def strapdown(
    imu: ImuData,
    q0: NDArray[np.float64],
    v0: NDArray[np.float64] | None = None,
    p0: NDArray[np.float64] | None = None,
    gyro_bias_radps: NDArray[np.float64] | None = None,
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """Free inertial integration of a whole recording (no aiding): returns quat, vel, pos (N, .).

    ``q0`` is the initial attitude body -> nav, ``v0``/``p0`` the initial velocity (m/s) and position
    (m) in nav (zero by default); ``gyro_bias_radps`` (3,) is subtracted from the gyro.
    """
    n = imu.n_samples
    gyr = imu.gyr if gyro_bias_radps is None else imu.gyr - np.asarray(gyro_bias_radps, dtype=np.float64)
    quat, vel, pos = np.empty((n, 4)), np.empty((n, 3)), np.empty((n, 3))
    _strapdown_loop(
        imu.t,
        np.ascontiguousarray(imu.acc),
        np.ascontiguousarray(gyr),
        np.asarray(q0, dtype=np.float64),
        np.zeros(3) if v0 is None else np.asarray(v0, dtype=np.float64),
        np.zeros(3) if p0 is None else np.asarray(p0, dtype=np.float64),
        quat,
        vel,
        pos,
    )
    return quat, vel, pos
