"""Error-state ZUPT-aided INS: the closed-loop 9-state extended Kalman filter.

Error state dx = [dphi, dv, dp] (attitude, velocity, position errors in the nav frame; seed 001
eq. 1-3, seed 002 eq. 1-3 and Alg. 1 without the smoother). With the estimated attitude
C^ = (I - [dphi x]) C and dv = v^ - v, dp = p^ - p, the continuous error model is (seed 001 eq. 2)::

    d(dphi)/dt = -C^ dw,   d(dv)/dt = [f^n x] dphi + C^ df,   d(dp)/dt = dv

discretised per sample as F = I + A dt and Q = diag(sigma_g^2 dt I, sigma_a^2 dt I, 0), with
sigma_a, sigma_g the sensor noise *densities*: the filter then behaves the same at any rate. In
stance the pseudo-measurement z = v^ (the foot is still) updates the error state (H = [0 I 0]),
which is fed back into attitude, velocity and position and reset to zero (closed loop).
"""

from __future__ import annotations

import time
import warnings
from typing import Literal

import numpy as np
from numba import njit
from numpy.typing import NDArray

from footnav.core import kalman
from footnav.core import quaternion as quat
from footnav.core.component import FootEstimator, require
from footnav.core.errors import DataQualityWarning, InvalidInputError
from footnav.core.initial_alignment import align_at_rest
from footnav.core.mechanization import strapdown_step
from footnav.core.quaternion import as_matrix_nb, from_rotvec_nb, multiply_nb, normalize_nb
from footnav.core.types import FootTrajectory, ImuData, StanceResult

__all__ = ["EkfEstimator", "heading_of_first_step"]

N_STATES = 9
#: Footprints closer than this (m) do not define a walking direction.
MIN_FIRST_STEP_M = 0.2


@njit(cache=True)
def _predict_ins(cov, f_n, dt, var_gyr, var_acc, m):
    """P <- F P F' + Q for F = [[I,0,0],[S,I,0],[0,dt I,I]], S = [f^n x] dt (seed 001 eq. 2-3),
    using the block structure (about a seventh of the flops of a dense 9x9 product)."""
    # S = [f^n x] dt = [[0, -z, y], [z, 0, -x], [-y, x, 0]]
    x, y, z = f_n[0] * dt, f_n[1] * dt, f_n[2] * dt
    # M = F P (rows): [P0; P1 + S P0; P2 + dt P1]
    for j in range(N_STATES):
        p0, p1, p2 = cov[0, j], cov[1, j], cov[2, j]
        m[0, j], m[1, j], m[2, j] = p0, p1, p2
        m[3, j] = cov[3, j] - z * p1 + y * p2
        m[4, j] = cov[4, j] + z * p0 - x * p2
        m[5, j] = cov[5, j] - y * p0 + x * p1
        for i in range(3):
            m[6 + i, j] = cov[6 + i, j] + dt * cov[3 + i, j]
    # P = M F' (columns): [M0, M1 + M0 S', M2 + dt M1]
    for i in range(N_STATES):
        m0, m1, m2 = m[i, 0], m[i, 1], m[i, 2]
        cov[i, 0], cov[i, 1], cov[i, 2] = m0, m1, m2
        cov[i, 3] = m[i, 3] - z * m1 + y * m2
        cov[i, 4] = m[i, 4] + z * m0 - x * m2
        cov[i, 5] = m[i, 5] - y * m0 + x * m1
        for j in range(3):
            cov[i, 6 + j] = m[i, 6 + j] + dt * m[i, 3 + j]
    for i in range(3):
        cov[i, i] += var_gyr * dt  # C Sg C' dt = sigma_g^2 dt I (C orthonormal)
        cov[3 + i, 3 + i] += var_acc * dt
    kalman.symmetrize(cov)


@njit(cache=True)
def _store(k, q, v, p, cov, quat_out, vel, pos, pos_cov):
    """Write sample k's attitude, velocity, position and position covariance (xx, xy, yy, zz)."""
    quat_out[k] = q
    vel[k] = v
    pos[k] = p
    pos_cov[k, 0] = cov[6, 6]
    pos_cov[k, 1] = cov[6, 7]
    pos_cov[k, 2] = cov[7, 7]
    pos_cov[k, 3] = cov[8, 8]


@njit(cache=True)
def _ekf_loop(t, acc, gyr, stance, start, q0, var_gyr, var_acc, var_zupt, p0_diag, quat_out, vel, pos, pos_cov):
    """Run the filter over samples ``start:``; write attitude, velocity, position and the position
    covariance entries (xx, xy, yy, zz) per sample. No allocation inside the sample loop."""
    n = len(t)
    q = q0.copy()
    v = np.zeros(3)
    p = np.zeros(3)
    f_n = np.zeros(3)
    dq = np.zeros(4)
    q_tmp = np.zeros(4)
    c = np.zeros((3, 3))
    cov = np.zeros((N_STATES, N_STATES))
    for i in range(N_STATES):
        cov[i, i] = p0_diag[i]
    r = np.zeros((3, 3))
    for i in range(3):
        r[i, i] = var_zupt
    dx = np.zeros(N_STATES)
    innov = np.zeros(3)
    nn1 = np.zeros((N_STATES, N_STATES))
    nm1 = np.zeros((N_STATES, 3))
    nm2 = np.zeros((N_STATES, 3))
    mm1 = np.zeros((3, 3))
    mm2 = np.zeros((3, 3))
    mm3 = np.zeros((3, 3))

    as_matrix_nb(q, c)
    for i in range(3):
        f_n[i] = c[i, 0] * acc[start, 0] + c[i, 1] * acc[start, 1] + c[i, 2] * acc[start, 2]
    for k in range(start + 1):
        _store(k, q, v, p, cov, quat_out, vel, pos, pos_cov)
    for k in range(start + 1, n):
        dt = t[k] - t[k - 1]
        strapdown_step(q, v, p, f_n, acc[k - 1], gyr[k - 1], acc[k], gyr[k], dt, dq, q_tmp, c)
        _predict_ins(cov, f_n, dt, var_gyr, var_acc, nn1)  # P = F P F' + Q  (seed 001 eq. 3)
        if stance[k]:
            for i in range(N_STATES):
                dx[i] = 0.0
            for i in range(3):
                innov[i] = v[i]  # z = v^ - 0 = dv + noise
            # K = P H' (H P H' + R)^-1, Joseph-form P  (seed 001 eq. 3, seed 002 Alg. 1)
            if kalman.update_block(dx, cov, 3, r, innov, nn1, nm1, nm2, mm1, mm2, mm3):
                # feedback: C <- (I + [dphi x]) C^, v <- v^ - dv, p <- p^ - dp; error reset to 0
                from_rotvec_nb(dx[0], dx[1], dx[2], dq)
                multiply_nb(dq, q, q_tmp)
                for i in range(4):
                    q[i] = q_tmp[i]
                normalize_nb(q)
                for i in range(3):
                    v[i] -= dx[3 + i]
                    p[i] -= dx[6 + i]
        _store(k, q, v, p, cov, quat_out, vel, pos, pos_cov)


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


class EkfEstimator(FootEstimator):
    """Closed-loop error-state ZUPT EKF, 9 states [attitude, velocity, position].

    Seed 001 eq. 1-3 (Zhao et al. 2019) and seed 002 Alg. 1 (Chistyakov et al. 2021), forward
    filter. Initial roll, pitch and gyro bias come from the first stance phase; heading starts at
    zero. Noise parameters are densities, so results do not depend on the sampling rate.

    Parameters
    ----------
    acc_noise_mps2_sqrthz : float
        Accelerometer white-noise density driving the velocity error, m/s^2/sqrt(Hz).
    gyr_noise_radps_sqrthz : float
        Gyroscope white-noise density driving the attitude error, rad/s/sqrt(Hz).
    zupt_std_mps : float
        Standard deviation of the zero-velocity pseudo-measurement, m/s.
    init_attitude_std_rad : float
        Initial roll/pitch/heading uncertainty, rad.
    init_velocity_std_mps : float
        Initial velocity uncertainty, m/s.
    heading : {"first-step", "sensor"}
        Nav frame heading: "first-step" turns the result so the first step points along +x;
        "sensor" keeps the sensor's initial heading as x.
    gyro_bias : {"initial-standstill", "none"}
        Subtract the mean angular rate of the still samples of the first stance phase, or nothing.
    still_gyr_max_radps : float
        Samples of the first stance used for levelling and gyro bias must turn slower than this,
        rad/s (a detected stance is not always a true standstill).

    Examples
    --------
    >>> est = EkfEstimator(zupt_std_mps=0.02)
    >>> traj = est.estimate(imu, make_detector("threshold").detect(imu))  # doctest: +SKIP
    """

    name = "ekf"

    def __init__(
        self,
        *,
        acc_noise_mps2_sqrthz: float = 0.05,
        gyr_noise_radps_sqrthz: float = 2e-3,
        zupt_std_mps: float = 0.01,
        init_attitude_std_rad: float = 0.01,
        init_velocity_std_mps: float = 0.01,
        heading: Literal["first-step", "sensor"] = "first-step",
        gyro_bias: Literal["initial-standstill", "none"] = "initial-standstill",
        still_gyr_max_radps: float = 0.05,
    ) -> None:
        self.acc_noise_mps2_sqrthz = acc_noise_mps2_sqrthz
        self.gyr_noise_radps_sqrthz = gyr_noise_radps_sqrthz
        self.zupt_std_mps = zupt_std_mps
        self.init_attitude_std_rad = init_attitude_std_rad
        self.init_velocity_std_mps = init_velocity_std_mps
        self.heading = heading
        self.gyro_bias = gyro_bias
        self.still_gyr_max_radps = still_gyr_max_radps

    def validate_params(self) -> None:
        for name in (
            "acc_noise_mps2_sqrthz",
            "gyr_noise_radps_sqrthz",
            "zupt_std_mps",
            "init_attitude_std_rad",
            "init_velocity_std_mps",
            "still_gyr_max_radps",
        ):
            value = getattr(self, name)
            require(isinstance(value, (int, float)) and np.isfinite(value) and value > 0, self, name, "a positive number")
        require(self.heading in ("first-step", "sensor"), self, "heading", "'first-step' or 'sensor'")
        require(self.gyro_bias in ("initial-standstill", "none"), self, "gyro_bias", "'initial-standstill' or 'none'")

    def estimate(self, imu: ImuData, stance: StanceResult) -> FootTrajectory:
        """Estimate the foot's trajectory from its IMU data and stance phases.

        Parameters
        ----------
        imu
            The foot's recording (body frame, SI).
        stance
            Stance mask aligned with ``imu``; its first stance phase aligns the filter.

        Returns
        -------
        FootTrajectory
            Nav-frame (z up) trajectory, starting at the origin.
        """
        self.validate_params()
        if len(stance.mask) != imu.n_samples:
            raise InvalidInputError(
                f"stance mask has {len(stance.mask)} samples but the IMU data has {imu.n_samples}",
                field="stance.mask",
                path=imu.meta.get("source"),
            )
        steps = stance.intervals
        if len(steps) == 0:
            raise InvalidInputError(
                "no stance phase detected, so the filter cannot be aligned or aided; "
                "check the detector's thresholds against this recording",
                field="stance.mask",
                path=imu.meta.get("source"),
            )
        t0 = time.perf_counter()
        meta: dict = {"estimator": self.describe()}
        s0, e0 = int(steps[0, 0]), int(steps[0, 1])
        if s0 > 0:
            meta["estimate_start_index"] = s0
            warnings.warn(
                f"{imu.meta.get('source') or 'ImuData'}: recording does not start at standstill; the estimate "
                f"starts at the first stance phase (index {s0}) and holds that state before it",
                DataQualityWarning,
                stacklevel=2,
            )
        align = align_at_rest(imu.acc, imu.gyr, s0, e0, still_gyr_max_radps=self.still_gyr_max_radps)
        meta["alignment_samples"] = [s0, e0, align.n_used]
        gyr = imu.gyr
        if self.gyro_bias == "initial-standstill":
            gyr = gyr - align.gyro_bias_radps
            meta["gyro_bias_radps"] = align.gyro_bias_radps.tolist()
        n = imu.n_samples
        q_out, vel, pos, pos_cov = np.empty((n, 4)), np.empty((n, 3)), np.empty((n, 3)), np.empty((n, 4))
        var_att = self.init_attitude_std_rad**2
        var_vel = self.init_velocity_std_mps**2
        p0_diag = np.array([var_att] * 3 + [var_vel] * 3 + [0.0] * 3)
        _ekf_loop(
            imu.t,
            np.ascontiguousarray(imu.acc),
            np.ascontiguousarray(gyr),
            np.ascontiguousarray(stance.mask),
            s0,
            align.quaternion,
            float(self.gyr_noise_radps_sqrthz) ** 2,
            float(self.acc_noise_mps2_sqrthz) ** 2,
            float(self.zupt_std_mps) ** 2,
            p0_diag,
            q_out,
            vel,
            pos,
            pos_cov,
        )
        psi = heading_of_first_step(pos, steps) if self.heading == "first-step" else None
        if psi is not None:
            pos, vel, q_out, pos_cov = _rotate_about_z(-psi, pos, vel, q_out, pos_cov)
            meta["heading_rotation_rad"] = -psi
        std = np.sqrt(np.maximum(pos_cov[:, [0, 2, 3]], 0.0))
        meta["runtime_s"] = time.perf_counter() - t0
        return FootTrajectory(
            t=imu.t, position=pos, velocity=vel, quaternion=q_out, position_std=std, steps=steps, meta=meta
        )


def _rotate_about_z(angle: float, pos, vel, q_out, pos_cov):
    """Turn a nav-frame solution by ``angle`` rad about z (positions, velocities, attitude, and the
    horizontal position covariance stored as xx, xy, yy, zz)."""
    c, s = np.cos(angle), np.sin(angle)
    rot = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
    xx, xy, yy = pos_cov[:, 0], pos_cov[:, 1], pos_cov[:, 2]
    cov = np.stack(
        [c * c * xx - 2 * c * s * xy + s * s * yy, c * s * (xx - yy) + (c * c - s * s) * xy, s * s * xx + 2 * c * s * xy + c * c * yy, pos_cov[:, 3]],
        axis=1,
    )
    return pos @ rot.T, vel @ rot.T, quat.multiply(quat.from_yaw(angle), q_out), cov
