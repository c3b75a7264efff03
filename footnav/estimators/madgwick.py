"""Madgwick orientation + 9-state error Kalman filter on [position, velocity, acceleration] (Li et al. (2018)).

Li, Derrode et al. (2018), Sec. 3: the orientation comes from Madgwick's gradient-descent
filter (Madgwick et al. 2011, its ref. [6]), independently of the Kalman filter, which then only
tracks the errors of the integration::

    d_eta = [d^e r, d^e v, d^s a]                                    (eq. 3)
    d_eta(n|n-1) = Phi_n d_eta(n-1|n-1) + w(n-1)                     (eq. 4)
    Phi_n = [[I, dt I, 0], [0, I, dt C_n], [0, 0, I]]                (eq. 5, C_n sensor -> earth)
    z_n = H d_eta + v_n,  H = [0 I 0],  z_n = ^e v_n - 0 in stance   (eq. 6)

and in stance the velocity and position are compensated (``v - dv``, ``r - dr``) and ``dv``, ``dr``
reset to zero; the acceleration error ``d^s a`` (sensor frame, m/s^2) stays in the state.

Madgwick (IMU): ``q_dot = 1/2 q (x) [0, w] - beta grad f / |grad f|`` with
``f = R(q)' [0 0 1] - a / |a|`` (gravity seen in the sensor frame against the normalised specific
force), integrated by one Euler step per sample as in the reference implementation; with a
magnetometer (MARG), f adds the earth field ``[b_x, 0, b_z]`` seen in the sensor frame against the
normalised field, ``b`` re-estimated from the current attitude at every sample.

footnav's choices: noise as densities scaled with dt (rate independent); initial roll, pitch and
gyro bias from the first standstill (as the ``ekf`` estimator); with a magnetometer, the initial
heading from the field of that standstill too (the paper's "short standing time period ... for
initializing the quaternion corresponding to the earth frame", Sec. 4): started at the sensor's
heading instead, the MARG filter would turn towards magnetic north at up to ``beta_radps`` during
the walk and bend the trajectory. The output at every sample is the nominal state compensated by
the filter's current error estimate (the paper compensates in stance only, which leaves the swing
uncorrected).
"""

from __future__ import annotations

import time
from typing import Literal

import numpy as np

from footnav._numba import njit  # numba.njit that survives a read-only install
from footnav.core.component import FootEstimator
from footnav.core.parameters import (
    MAX_ACC_MPS2,
    MAX_RATE_RADPS,
    MAX_SCALE_STD,
    MAX_SPEED_MPS,
    require,
    require_non_negative,
    require_positive,
)
from footnav.core.types import GRAVITY_MPS2, FootTrajectory, ImuData, StanceResult
from footnav.nav import quaternion as quat
from footnav.nav.heading import turn_to_first_step
from footnav.nav.heading_drift import GYRO_SCALE_STD, TURN_ON_BIAS_STD_RADPS, standstill_rate_std, with_heading_drift
from footnav.nav.initial_alignment import MIN_STILL_SAMPLES, Alignment, align_first_stance
from footnav.nav.kalman import update3_inline
from footnav.nav.quaternion import as_matrix_nb

__all__ = ["MadgwickEstimator", "madgwick_imu_step", "madgwick_marg_step"]

#: The magnetometer of an IMU-only run: read-only like ImuData's arrays, so that the IMU and MARG
#: runs share one compiled variant of ``_loop`` (numba types read-only arrays apart).
_NO_MAG = np.zeros((1, 3))
_NO_MAG.setflags(write=False)


@njit(cache=True, inline="always", error_model="numpy")
def _rate(q0, q1, q2, q3, gx, gy, gz):
    """q_dot = 1/2 q (x) [0, w] (Madgwick 2011 eq. 12)."""
    return (
        0.5 * (-q1 * gx - q2 * gy - q3 * gz),
        0.5 * (q0 * gx + q2 * gz - q3 * gy),
        0.5 * (q0 * gy - q1 * gz + q3 * gx),
        0.5 * (q0 * gz + q1 * gy - q2 * gx),
    )


@njit(cache=True, inline="always", error_model="numpy")
def _step(q, d0, d1, d2, d3, s0, s1, s2, s3, beta, dt):
    """q <- normalise(q + (q_dot - beta s / |s|) dt): one Euler step down the gradient s."""
    sn = np.sqrt(s0 * s0 + s1 * s1 + s2 * s2 + s3 * s3)
    if sn > 0.0:
        d0 -= beta * s0 / sn
        d1 -= beta * s1 / sn
        d2 -= beta * s2 / sn
        d3 -= beta * s3 / sn
    q0, q1, q2, q3 = q[0] + d0 * dt, q[1] + d1 * dt, q[2] + d2 * dt, q[3] + d3 * dt
    n = np.sqrt(q0 * q0 + q1 * q1 + q2 * q2 + q3 * q3)
    q[0], q[1], q[2], q[3] = q0 / n, q1 / n, q2 / n, q3 / n


@njit(cache=True, error_model="numpy")
def madgwick_imu_step(q, gx, gy, gz, ax, ay, az, beta, dt):
    """One Madgwick IMU update of q (in place): gyro rate (rad/s), specific force (any unit)."""
    q0, q1, q2, q3 = q[0], q[1], q[2], q[3]
    d0, d1, d2, d3 = _rate(q0, q1, q2, q3, gx, gy, gz)
    s0 = s1 = s2 = s3 = 0.0
    norm = np.sqrt(ax * ax + ay * ay + az * az)
    if norm > 0.0:
        ax /= norm
        ay /= norm
        az /= norm
        f0 = 2.0 * (q1 * q3 - q0 * q2) - ax
        f1 = 2.0 * (q0 * q1 + q2 * q3) - ay
        f2 = 2.0 * (0.5 - q1 * q1 - q2 * q2) - az
        # J' f with J the Jacobian of f (Madgwick 2011 eq. 25-26)
        s0 = -2.0 * q2 * f0 + 2.0 * q1 * f1
        s1 = 2.0 * q3 * f0 + 2.0 * q0 * f1 - 4.0 * q1 * f2
        s2 = -2.0 * q0 * f0 + 2.0 * q3 * f1 - 4.0 * q2 * f2
        s3 = 2.0 * q1 * f0 + 2.0 * q2 * f1
    _step(q, d0, d1, d2, d3, s0, s1, s2, s3, beta, dt)


@njit(cache=True, error_model="numpy")
def madgwick_marg_step(q, gx, gy, gz, ax, ay, az, mx, my, mz, beta, dt):
    """One Madgwick MARG update of q (in place), Madgwick 2011 eq. 27-34; IMU step without a field."""
    mn = np.sqrt(mx * mx + my * my + mz * mz)
    an = np.sqrt(ax * ax + ay * ay + az * az)
    if mn == 0.0 or an == 0.0:
        madgwick_imu_step(q, gx, gy, gz, ax, ay, az, beta, dt)
        return
    ax, ay, az = ax / an, ay / an, az / an
    mx, my, mz = mx / mn, my / mn, mz / mn
    q0, q1, q2, q3 = q[0], q[1], q[2], q[3]
    d0, d1, d2, d3 = _rate(q0, q1, q2, q3, gx, gy, gz)
    # earth field h = q (x) m (x) q*, reference b = [sqrt(hx^2 + hy^2), 0, hz]
    hx = mx * (q0 * q0 + q1 * q1 - q2 * q2 - q3 * q3) + 2.0 * my * (q1 * q2 - q0 * q3) + 2.0 * mz * (q1 * q3 + q0 * q2)
    hy = 2.0 * mx * (q1 * q2 + q0 * q3) + my * (q0 * q0 - q1 * q1 + q2 * q2 - q3 * q3) + 2.0 * mz * (q2 * q3 - q0 * q1)
    hz = 2.0 * mx * (q1 * q3 - q0 * q2) + 2.0 * my * (q2 * q3 + q0 * q1) + mz * (q0 * q0 - q1 * q1 - q2 * q2 + q3 * q3)
    bx = np.sqrt(hx * hx + hy * hy)
    bz = hz
    # objective: gravity (3) and field (3) seen in the sensor frame, minus the measurements
    f0 = 2.0 * (q1 * q3 - q0 * q2) - ax
    f1 = 2.0 * (q0 * q1 + q2 * q3) - ay
    f2 = 2.0 * (0.5 - q1 * q1 - q2 * q2) - az
    f3 = 2.0 * bx * (0.5 - q2 * q2 - q3 * q3) + 2.0 * bz * (q1 * q3 - q0 * q2) - mx
    f4 = 2.0 * bx * (q1 * q2 - q0 * q3) + 2.0 * bz * (q0 * q1 + q2 * q3) - my
    f5 = 2.0 * bx * (q0 * q2 + q1 * q3) + 2.0 * bz * (0.5 - q1 * q1 - q2 * q2) - mz
    s0 = (
        -2.0 * q2 * f0 + 2.0 * q1 * f1 - 2.0 * bz * q2 * f3 + (-2.0 * bx * q3 + 2.0 * bz * q1) * f4 + 2.0 * bx * q2 * f5
    )
    s1 = (
        2.0 * q3 * f0
        + 2.0 * q0 * f1
        - 4.0 * q1 * f2
        + 2.0 * bz * q3 * f3
        + (2.0 * bx * q2 + 2.0 * bz * q0) * f4
        + (2.0 * bx * q3 - 4.0 * bz * q1) * f5
    )
    s2 = (
        -2.0 * q0 * f0
        + 2.0 * q3 * f1
        - 4.0 * q2 * f2
        + (-4.0 * bx * q2 - 2.0 * bz * q0) * f3
        + (2.0 * bx * q1 + 2.0 * bz * q3) * f4
        + (2.0 * bx * q0 - 4.0 * bz * q2) * f5
    )
    s3 = (
        2.0 * q1 * f0
        + 2.0 * q2 * f1
        + (-4.0 * bx * q3 + 2.0 * bz * q1) * f3
        + (-2.0 * bx * q0 + 2.0 * bz * q2) * f4
        + 2.0 * bx * q1 * f5
    )
    _step(q, d0, d1, d2, d3, s0, s1, s2, s3, beta, dt)


@njit(cache=True, error_model="numpy")
# complexity: a compiled loop over the samples, one pass
def _loop(  # noqa: C901
    t,
    acc,
    gyr,
    mag,
    use_mag,
    stance,
    start,
    q0,
    beta,
    var_acc,
    var_da,
    var_zupt,
    p0_diag,
    q_out,
    v_out,
    r_out,
    rcov_out,
):
    """Madgwick attitude, strapdown velocity/position and the eq. 3-6 error filter, samples start:.

    ``rcov_out`` (N, 4) receives the position covariance as xx, xy, yy, zz (m^2): the horizontal
    cross term is needed to turn the uncertainty with the heading."""
    n = len(t)
    q = q0.copy()
    v = np.zeros(3)
    r = np.zeros(3)
    de = np.zeros(9)  # [dr, dv, da]
    p = np.zeros((9, 9))
    for i in range(9):
        p[i, i] = p0_diag[i]
    c = np.zeros((3, 3))
    m = np.zeros((9, 9))
    a_prev = np.zeros(3)
    innov = np.zeros(3)
    gain = np.zeros((9, 3))
    hp = np.zeros((3, 9))
    sy = np.zeros(3)
    kpy = np.zeros(9)  # the kernel's P H' S^-1 y, not used (see the update)
    as_matrix_nb(q, c)
    for i in range(3):
        a_prev[i] = c[i, 0] * acc[start, 0] + c[i, 1] * acc[start, 1] + c[i, 2] * acc[start, 2]
    a_prev[2] -= GRAVITY_MPS2
    for k in range(start + 1):
        # element by element: a row assigned from an array (q_out[k] = q) makes numba compile its
        # shape-mismatch error message too (string formatting, about 2 s of the first call)
        for i in range(4):
            q_out[k, i] = q[i]
        v_out[k] = 0.0
        r_out[k] = 0.0
        rcov_out[k] = 0.0
    for k in range(start + 1, n):
        dt = t[k] - t[k - 1]
        if use_mag:
            madgwick_marg_step(
                q,
                gyr[k, 0],
                gyr[k, 1],
                gyr[k, 2],
                acc[k, 0],
                acc[k, 1],
                acc[k, 2],
                mag[k, 0],
                mag[k, 1],
                mag[k, 2],
                beta,
                dt,
            )
        else:
            madgwick_imu_step(q, gyr[k, 0], gyr[k, 1], gyr[k, 2], acc[k, 0], acc[k, 1], acc[k, 2], beta, dt)
        as_matrix_nb(q, c)
        for i in range(3):
            a_new = c[i, 0] * acc[k, 0] + c[i, 1] * acc[k, 1] + c[i, 2] * acc[k, 2] - (GRAVITY_MPS2 if i == 2 else 0.0)
            v_new = v[i] + 0.5 * (a_prev[i] + a_new) * dt
            r[i] += 0.5 * (v[i] + v_new) * dt
            v[i] = v_new
            a_prev[i] = a_new
        # eq. 4-5: dr += dt dv, dv += dt C da; P <- Phi P Phi' + Q
        for i in range(3):
            de[i] += dt * de[3 + i]
        for i in range(3):
            de[3 + i] += dt * (c[i, 0] * de[6] + c[i, 1] * de[7] + c[i, 2] * de[8])
        for j in range(9):  # M = Phi P (rows)
            for i in range(3):
                m[i, j] = p[i, j] + dt * p[3 + i, j]
                m[3 + i, j] = p[3 + i, j] + dt * (c[i, 0] * p[6, j] + c[i, 1] * p[7, j] + c[i, 2] * p[8, j])
                m[6 + i, j] = p[6 + i, j]
        for i in range(9):  # P = M Phi' (columns)
            m0, m1, m2 = m[i, 3], m[i, 4], m[i, 5]
            p[i, 0] = m[i, 0] + dt * m0
            p[i, 1] = m[i, 1] + dt * m1
            p[i, 2] = m[i, 2] + dt * m2
            for j in range(3):
                p[i, 3 + j] = m[i, 3 + j] + dt * (c[j, 0] * m[i, 6] + c[j, 1] * m[i, 7] + c[j, 2] * m[i, 8])
                p[i, 6 + j] = m[i, 6 + j]
        for i in range(3):
            p[3 + i, 3 + i] += var_acc * dt
            p[6 + i, 6 + i] += var_da * dt
        if stance[k]:
            # eq. 6: z = v^ - 0, H = [0 I 0], y = z - H d_eta; K = P H' (H P H' + R)^-1,
            # P <- P - K H P (footnav.nav.kalman, the ekf's kernel)
            for i in range(3):
                innov[i] = v[i] - de[3 + i]
            if update3_inline(p, kpy, 3, innov[0], innov[1], innov[2], var_zupt, np.inf, gain, sy, hp):
                # d_eta += K y: the error state holds d^s a, not zero, before the update (and
                # (P H' S^-1) y, not the kernel's P H' (S^-1 y): the same up to rounding)
                for i in range(9):
                    de[i] += gain[i, 0] * innov[0] + gain[i, 1] * innov[1] + gain[i, 2] * innov[2]
                # compensation and reset of dr, dv (da stays: it is the sensor's error)
                for i in range(3):
                    v[i] -= de[3 + i]
                    r[i] -= de[i]
                    de[i] = 0.0
                    de[3 + i] = 0.0
        for i in range(4):
            q_out[k, i] = q[i]
        for i in range(3):
            v_out[k, i] = v[i] - de[3 + i]
            r_out[k, i] = r[i] - de[i]
        rcov_out[k, 0], rcov_out[k, 1], rcov_out[k, 2], rcov_out[k, 3] = p[0, 0], p[0, 1], p[1, 1], p[2, 2]


def _magnetic_start(imu: ImuData, align: Alignment, still_gyr_max_radps: float) -> tuple[np.ndarray, float]:
    """Levelled start attitude turned so the horizontal field of the first standstill points
    along nav +x (MARG's earth frame, Madgwick 2011 eq. 45-46), and that turn in rad.

    The field is averaged over the same still samples as the levelling (all of the standstill
    when fewer than ``MIN_STILL_SAMPLES`` are still)."""
    assert imu.mag is not None  # the caller's use_mag: the recording has a magnetometer
    a, b = align.start, align.stop
    still = np.linalg.norm(imu.gyr[a:b], axis=1) < still_gyr_max_radps
    if still.sum() < MIN_STILL_SAMPLES:
        still[:] = True
    h = quat.rotate(align.quaternion, imu.mag[a:b][still].mean(axis=0))
    psi = -float(np.arctan2(h[1], h[0]))
    return quat.multiply(quat.from_yaw(psi), align.quaternion), psi


class MadgwickEstimator(FootEstimator):
    """Madgwick gradient-descent attitude + 9-state error KF [position, velocity, acceleration] (Li et al. (2018)).

    Li et al. (2018), Sec. 3, eq. 3-6 (Derrode, Li et al. 2018) with Madgwick et al. (2011) for the
    attitude. Initial roll, pitch and gyro bias come from the first stance phase, and with a
    magnetometer the heading too (x magnetic north); without one, heading starts at zero. Noise
    parameters are densities, so results do not depend on the sampling rate.

    Parameters
    ----------
    beta_radps : float
        Madgwick's gain: the rate at which the accelerometer (and magnetometer) pull the attitude,
        rad/s.
    use_magnetometer : bool
        Use the MARG filter when the recording has a magnetometer (else the IMU filter).
    acc_noise_mps2_sqrthz : float
        Accelerometer white-noise density driving the velocity error, m/s^2/sqrt(Hz).
    acc_error_walk_mps3_sqrthz : float
        Random walk of the acceleration error state, m/s^3/sqrt(Hz).
    init_acc_error_std_mps2 : float
        Initial acceleration error uncertainty, m/s^2.
    zupt_std_mps : float
        Standard deviation of the zero-velocity measurement, m/s.
    heading : {"first-step", "sensor"}
        Nav frame heading: turn the result so the first step points along +x, or keep the
        filter's own: the sensor's heading at the first standstill (IMU), magnetic north (MARG:
        x north, y west, z up).
    gyro_bias : {"initial-standstill", "none"}
        Subtract the mean angular rate of the still samples of the first stance, or nothing.
    still_gyr_max_radps : float
        Samples of the first stance used for levelling and gyro bias must turn slower than this,
        rad/s.
    heading_drift_in_std : bool
        Add the heading drift of gyro integration to ``position_std`` when there is no
        magnetometer (:mod:`footnav.nav.heading_drift`): a constant yaw-rate error with the std
        of the initial-standstill bias estimate (the standard error of the still samples' mean
        rate; a consumer MEMS turn-on bias with ``gyro_bias="none"``), a bias random walk of
        ``yaw_bias_walk_radps2_sqrthz`` and a scale-factor error of ``gyro_scale_std`` on every
        turn. Changes ``position_std`` only, never the estimate.
    yaw_bias_walk_radps2_sqrthz : float
        Random walk of the gyro bias about the vertical, rad/s^2/sqrt(Hz): the consumer MEMS grade
        of the simulator's default sensor.
    gyro_scale_std : float
        Std of the gyro's scale-factor error, a fraction (0.005 is 0.5 %, a factory-trimmed
        consumer MEMS gyro; 0 for a sensor calibrated for scale).

    Examples
    --------
    >>> pipe = footnav.make_pipeline("hmm", "madgwick")  # doctest: +SKIP
    """

    name = "madgwick"

    def __init__(
        self,
        *,
        beta_radps: float = 0.033,
        use_magnetometer: bool = True,
        acc_noise_mps2_sqrthz: float = 0.05,
        acc_error_walk_mps3_sqrthz: float = 1e-3,
        init_acc_error_std_mps2: float = 0.05,
        zupt_std_mps: float = 0.01,
        heading: Literal["first-step", "sensor"] = "first-step",
        gyro_bias: Literal["initial-standstill", "none"] = "initial-standstill",
        still_gyr_max_radps: float = 0.05,
        heading_drift_in_std: bool = True,
        yaw_bias_walk_radps2_sqrthz: float = 1e-5,
        gyro_scale_std: float = GYRO_SCALE_STD,
    ) -> None:
        self.beta_radps = beta_radps
        self.use_magnetometer = use_magnetometer
        self.acc_noise_mps2_sqrthz = acc_noise_mps2_sqrthz
        self.acc_error_walk_mps3_sqrthz = acc_error_walk_mps3_sqrthz
        self.init_acc_error_std_mps2 = init_acc_error_std_mps2
        self.zupt_std_mps = zupt_std_mps
        self.heading = heading
        self.gyro_bias = gyro_bias
        self.still_gyr_max_radps = still_gyr_max_radps
        self.heading_drift_in_std = heading_drift_in_std
        self.yaw_bias_walk_radps2_sqrthz = yaw_bias_walk_radps2_sqrthz
        self.gyro_scale_std = gyro_scale_std

    def validate_params(self) -> None:
        """Check every parameter (:meth:`footnav.core.component.Component.validate_params`); raises
        InvalidParameterError."""
        # Upper bounds (footnav.core.component): the stds and densities are squared into the
        # velocity filter's covariance (overflow at 1e308); beta is a gyro-error rate.
        require_positive(
            self, "acc_noise_mps2_sqrthz", "acc_error_walk_mps3_sqrthz", "init_acc_error_std_mps2", high=MAX_ACC_MPS2
        )
        require_positive(self, "zupt_std_mps", high=MAX_SPEED_MPS)
        require_positive(self, "still_gyr_max_radps", high=MAX_RATE_RADPS)
        require_non_negative(self, "beta_radps", "yaw_bias_walk_radps2_sqrthz", high=MAX_RATE_RADPS)
        require_non_negative(self, "gyro_scale_std", high=MAX_SCALE_STD)
        require(isinstance(self.heading_drift_in_std, (bool, np.bool_)), self, "heading_drift_in_std", "True or False")
        require(isinstance(self.use_magnetometer, (bool, np.bool_)), self, "use_magnetometer", "True or False")
        require(self.heading in ("first-step", "sensor"), self, "heading", "'first-step' or 'sensor'")
        require(self.gyro_bias in ("initial-standstill", "none"), self, "gyro_bias", "'initial-standstill' or 'none'")

    def estimate(self, imu: ImuData, stance: StanceResult) -> FootTrajectory:
        """Estimate the foot's trajectory: Madgwick attitude, then the error filter of eq. 3-6.

        Parameters
        ----------
        imu
            The foot's recording (body frame, SI; ``mag`` used by the MARG filter).
        stance
            Stance mask aligned with ``imu``; its first stance phase aligns the filter.

        Returns
        -------
        FootTrajectory
            Nav-frame (z up) trajectory, starting at the origin.

        Raises
        ------
        InvalidInputError
            The stance mask's length differs from the recording's, or it has no stance.

        Warns
        -----
        DataQualityWarning
            The recording does not start at standstill (the estimate starts at the first stance,
            ``meta["estimate_start_index"]``), or the integration crosses sampling gaps.
        """
        self.validate_params()
        t0 = time.perf_counter()
        s0, align, align_meta = align_first_stance(imu, stance, still_gyr_max_radps=self.still_gyr_max_radps)
        meta: dict = {"estimator": self.describe(), **align_meta}
        steps = stance.intervals
        bias = np.zeros(3)
        if self.gyro_bias == "initial-standstill":
            bias = align.gyro_bias_radps
            meta["gyro_bias_radps"] = bias.tolist()
        gyr = imu.gyr - bias  # writable either way: numba compiles one variant of _loop per array type
        use_mag = bool(self.use_magnetometer and imu.mag is not None)
        meta["orientation"] = "madgwick-marg" if use_mag else "madgwick-imu"
        q0 = align.quaternion
        if use_mag:
            q0, meta["magnetic_heading_rad"] = _magnetic_start(imu, align, self.still_gyr_max_radps)
        n = imu.n_samples
        q_out, v_out, r_out, cov = np.empty((n, 4)), np.empty((n, 3)), np.empty((n, 3)), np.empty((n, 4))
        p0 = np.array([0.0] * 6 + [self.init_acc_error_std_mps2**2] * 3)
        _loop(
            imu.t,
            np.ascontiguousarray(imu.acc),
            np.ascontiguousarray(gyr),
            np.ascontiguousarray(imu.mag) if use_mag else _NO_MAG,
            use_mag,
            np.ascontiguousarray(stance.mask),
            s0,
            q0,
            float(self.beta_radps),
            float(self.acc_noise_mps2_sqrthz) ** 2,
            float(self.acc_error_walk_mps3_sqrthz) ** 2,
            float(self.zupt_std_mps) ** 2,
            p0,
            q_out,
            v_out,
            r_out,
            cov,
        )
        if self.heading_drift_in_std and not use_mag:  # a magnetometer bounds the heading error
            if self.gyro_bias == "initial-standstill":
                rate_std = standstill_rate_std(imu.gyr, align.start, align.stop, self.still_gyr_max_radps)
                meta["gyro_bias_sem_radps"] = rate_std
            else:
                rate_std = TURN_ON_BIAS_STD_RADPS
            walk, scale = self.yaw_bias_walk_radps2_sqrthz, self.gyro_scale_std
            cov = with_heading_drift(cov, imu.t, v_out, q_out, s0, rate_std, walk, scale, meta)
        if self.heading == "first-step":
            r_out, v_out, q_out, std = turn_to_first_step(r_out, v_out, q_out, cov, steps, meta)
        else:
            std = np.sqrt(np.maximum(cov[:, [0, 2, 3]], 0.0))
        meta["runtime_s"] = time.perf_counter() - t0
        return FootTrajectory(
            t=imu.t, position=r_out, velocity=v_out, quaternion=q_out, position_std=std, steps=steps, meta=meta
        )
