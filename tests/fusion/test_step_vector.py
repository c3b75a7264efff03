"""Step-vector fusion (Zhao et al. (2019), eq. 5-7) on a hand-worked step (issue 17).

The fusion runs through its public ``fuse`` on a stand-in for the step-able estimator
(``footnav.core.component.stepable_gaps`` is the contract): its filter is footnav's own
:class:`~footnav.estimators.ekf.filter.InsFilter` (so the measurement update is footnav's), with the
propagation replaced by nothing and the per-sample attitudes set by hand. Every expected value is
computed here in plain numpy from the paper's equations:

    q = q1 (x) q2*,  theta = 2 acos(q_w)         (eq. 5)    S = 2 l sin(theta / 2)   (eq. 6)
    dp^b = [S, +w, e] (front foot left),  dp^n = C_z(psi_rear) dp^b     (Sec. IV-B)
    y = (p_front - p_rear) - dp^n,  H = [I]_front - [I]_rear            (eq. 7)

and the Kalman update in the nav frame with R_nav = C R C^T (R = diag of the step length, width
and elevation variances in the rear foot's frame): K = P H^T (H P H^T + R_nav)^-1,
dx = K y, p+ = p - dx (footnav's error state is estimate minus truth), P+ = (I - K H) P.
"""

from __future__ import annotations

import numpy as np
import pytest

from footnav.core.types import FootTrajectory, ImuData, StanceResult
from footnav.estimators.ekf._records import POS, FilterNoise
from footnav.estimators.ekf.filter import InsFilter
from footnav.fusion.joint import FeetView
from footnav.fusion.step_vector import StepVectorFusion

RATE_HZ = 100.0
N = 500  # 5 s per foot: more than the 3 s a coupled fusion needs in common
LEFT, RIGHT = 0, 1
N_STATES = 9

# The hand-worked step: the right foot lands at sample 120 (heel strike exactly at its stance
# start), the left foot at sample 250 (idem); the right foot is the rear, supporting foot of the
# left foot's step. The left foot's first stance ended at sample 100, 0.2 s before the right
# foot's landing at 1.2 s: more than heel_strike_before_stance_s + 0.1 s, so that landing has no
# supporting rear foot and is skipped.
LEFT_STANCE = [(0, 100), (250, N)]
RIGHT_STANCE = [(0, 60), (120, N)]
HS_LEFT, HS_RIGHT = 250, 120

YAW0_RIGHT = 0.3  # the right sensor's yaw when its foot faces +x (mounted askew), rad
PSI_REAR = YAW0_RIGHT + np.pi / 2  # the rear foot's sensor yaw at its heel strike: 90 deg turned
LEG_M = 0.9
STEP_WIDTH_M = 0.2
STEP_ELEVATION_M = 0.03
# strongly anisotropic R in the rear foot's frame: forward 1 cm, lateral 20 cm, vertical 2 cm
STD_M = np.array([0.01, 0.20, 0.02])
# position variances of each foot's filter (x, y, z) before the update, m^2
POS_VAR = np.array([0.04, 0.01, 0.0025])
P_FRONT = np.array([0.45, 1.30, 0.05])  # left foot, nav, m
P_REAR = np.array([0.70, 0.60, 0.01])  # right foot, nav, m


def _pitch_rear(i: int) -> float:
    """The rear foot's pitch at sample i, rad: flat (0) at its heel strike (120), rising 4 mrad
    per sample into heel-off after it, -0.05 rad before (foot-flat)."""
    return (i - HS_RIGHT) * 0.004 if i >= HS_RIGHT else -0.05


def _quat_yaw_pitch(yaw: float, pitch: float) -> np.ndarray:
    """[w, x, y, z] of C = Rz(yaw) Ry(pitch), the Hamilton product qz (x) qy written out."""
    cz, sz, cy, sy = np.cos(yaw / 2), np.sin(yaw / 2), np.cos(pitch / 2), np.sin(pitch / 2)
    return np.array([cz * cy, -sz * sy, cz * sy, sz * cy])


def _hamilton(p: np.ndarray, q: np.ndarray) -> np.ndarray:
    """p (x) q, [w, x, y, z]."""
    pw, pv, qw, qv = p[0], p[1:], q[0], q[1:]
    return np.concatenate([[pw * qw - pv @ qv], pw * qv + qw * pv + np.cross(pv, qv)])


def _stance(runs, heel_strikes):
    mask = np.zeros(N, dtype=bool)
    for a, b in runs:
        mask[a:b] = True
    return StanceResult(mask, events={"heel_strike": np.array(heel_strikes)})


class _HandFilter(InsFilter):
    """footnav's InsFilter with the hand-set state: no propagation (``run_until`` only records
    the instants the fusion stops at) and hand-set per-sample attitudes (``outputs``)."""

    def __init__(self, t, q_out, q0, p0, cov0_diag):
        z3 = np.zeros((len(t), 3))
        super().__init__(
            [t, t],
            [z3, z3],
            [z3, z3],
            [np.ones(len(t), bool)] * 2,
            [0, 0],
            q0,
            p0,
            [np.zeros(3)] * 2,
            cov0_diag,
            FilterNoise(acc_mps2_sqrthz=0.1, gyr_radps_sqrthz=0.01, zupt_std_mps=0.01),
            N_STATES,
        )
        self.q_out = q_out
        self.t_hand = t
        self.stops: list[float] = []
        self.updates: list[dict] = []

    def run_until(self, t_stop: float = np.inf) -> None:
        self.stops.append(float(t_stop))

    def outputs(self, foot):
        n = len(self.q_out[foot])
        return self.q_out[foot], np.zeros((n, 3)), np.zeros((n, 3)), np.zeros((n, 4))

    def update(self, h, innovation, r, *, gate=None):
        cov_before = self.covariance
        dx = super().update(h, innovation, r, gate=gate)
        self.updates.append(
            {
                "h": np.array(h),
                "y": np.array(innovation),
                "r": np.array(r),
                "dx": dx,
                "cov_before": cov_before,
                "cov_after": self.covariance,
                "p_after": [self.position(LEFT), self.position(RIGHT)],
            }
        )
        return dx


class _HandEstimator:
    """The step-able estimator contract (footnav.core.component.StepableEstimator: start, finish,
    estimate, clone; smoother, heading) around one :class:`_HandFilter`."""

    name = "hand"
    smoother = "none"
    heading = "first-step"

    def __init__(self, filt):
        self.filt = filt

    def get_params(self, deep=True):
        return {"smoother": self.smoother, "heading": self.heading}

    def clone(self, **changes):
        return self

    def estimate(self, imu, stance):
        n = len(imu.t)
        quat = np.tile([1.0, 0.0, 0.0, 0.0], (n, 1))
        return FootTrajectory(
            imu.t,
            np.zeros((n, 3)),
            np.zeros((n, 3)),
            quat,
            np.zeros((n, 3)),
            stance.intervals,
            meta={"heading_rotation_rad": 0.0},
        )

    def start(self, imus, stances, *, initial_yaw_rad=None, initial_position_m=None):
        return self.filt

    def finish(self, filt, stances):
        filt.run_until()
        return [self.estimate(ImuData(filt.t_hand, np.zeros((N, 3)), np.zeros((N, 3))), st) for st in stances]


def _run_hand_step():
    t = np.arange(N) / RATE_HZ
    q_rear = np.array([_quat_yaw_pitch(PSI_REAR, _pitch_rear(i)) for i in range(N)])
    q_front = np.tile(_quat_yaw_pitch(-0.2, 0.0), (N, 1))
    q0 = [_quat_yaw_pitch(-0.2, 0.0), _quat_yaw_pitch(YAW0_RIGHT, 0.0)]  # yaw0 of each sensor
    cov0 = np.concatenate([[1e-4] * 3, [1e-2] * 3, POS_VAR])
    filt = _HandFilter(t, [q_front, q_rear], q0, [P_FRONT, P_REAR], cov0)
    imu = ImuData(t, np.tile([0.0, 0.0, 9.80665], (N, 1)), np.zeros((N, 3)))
    fusion = StepVectorFusion(
        step_length="pendulum",
        leg_length_m=LEG_M,
        relative_frame="heading",
        step_width_m=STEP_WIDTH_M,
        step_elevation_m=STEP_ELEVATION_M,
        step_length_std_m=STD_M[0],
        step_width_std_m=STD_M[1],
        step_elevation_std_m=STD_M[2],
    )
    res = fusion.fuse(
        _HandEstimator(filt), imu, _stance(LEFT_STANCE, [HS_LEFT]), imu, _stance(RIGHT_STANCE, [HS_RIGHT])
    )
    return filt, res, t


def _hand_measurement():
    """The step vector, its innovation and the nav-frame H, R of the left foot's step, by hand."""
    # eq. 5: q1 (x) q2* between the rear foot's heel strike (pitch 0) and the front foot's heel
    # strike (sample 250, pitch 0.52 rad), both at yaw psi: a pure pitch of -0.52 rad, theta = 0.52
    theta = (HS_LEFT - HS_RIGHT) * 0.004
    q1, q2 = _quat_yaw_pitch(PSI_REAR, _pitch_rear(HS_RIGHT)), _quat_yaw_pitch(PSI_REAR, _pitch_rear(HS_LEFT))
    q = _hamilton(q1, q2 * [1.0, -1.0, -1.0, -1.0])
    assert 2.0 * np.arccos(q[0]) == pytest.approx(theta, abs=1e-12)  # eq. 5 as printed (q[1] is the scalar)
    s = 2.0 * LEG_M * np.sin(theta / 2)  # eq. 6
    yaw_r = PSI_REAR - YAW0_RIGHT  # footprint heading relative to the sensor's first-step yaw: 90 deg
    c = np.array([[np.cos(yaw_r), -np.sin(yaw_r), 0.0], [np.sin(yaw_r), np.cos(yaw_r), 0.0], [0.0, 0.0, 1.0]])
    dp_b = np.array([s, +STEP_WIDTH_M, STEP_ELEVATION_M])  # + : the front foot is the left one
    dp_n = c @ dp_b
    y = (P_FRONT - P_REAR) - dp_n
    h = np.zeros((3, 2 * N_STATES))
    h[:, LEFT * N_STATES + POS : LEFT * N_STATES + POS + 3] = np.eye(3)
    h[:, RIGHT * N_STATES + POS : RIGHT * N_STATES + POS + 3] = -np.eye(3)
    r_nav = c @ np.diag(STD_M**2) @ c.T
    return s, c, dp_n, y, h, r_nav


# mutant: step-vector-innovation-sign, step-vector-rot-transposed, step-vector-width-side,
# step-vector-theta-half, step-vector-pendulum-factor
# Issue 17, deliverable 1: the step-vector measurement and its innovation, by hand.
# step-vector-innovation-sign, step-vector-rot-transposed, step-vector-width-side,
# step-vector-theta-half and step-vector-pendulum-factor change these numbers too.
def test_step_vector_measurement_and_innovation_by_hand():
    filt, res, t = _run_hand_step()
    s, c, dp_n, y_nav, h_nav, _ = _hand_measurement()
    # the hand numbers themselves: theta 0.52 rad, S = 1.8 sin(0.26) = 0.462735... m
    assert s == pytest.approx(1.8 * np.sin(0.26), abs=1e-15)
    np.testing.assert_allclose(dp_n, [-STEP_WIDTH_M, s, STEP_ELEVATION_M], atol=1e-15)  # 90 deg: forward is +y
    assert res.meta["updates"] == 1 and res.meta["skipped_rear_foot_moving"] == 1
    assert res.meta["step_length_m"]["median"] == pytest.approx(s, abs=1e-12)
    (u,) = filt.updates
    # footnav passes the measurement in the rear foot's frame: C^T y and C^T H
    np.testing.assert_allclose(u["y"], c.T @ y_nav, rtol=0, atol=1e-12)
    np.testing.assert_allclose(u["h"], c.T @ h_nav, rtol=0, atol=1e-12)
    # back in nav, the innovation is the paper's (p_front - p_rear) - dp^n
    np.testing.assert_allclose(c @ u["y"], y_nav, rtol=0, atol=1e-12)


# mutant: step-vector-frame-dropped
# step-vector-frame-dropped: the update in the nav frame (H, y, R unrotated) differs from the
# rear foot's frame only through R; here R is 1 cm forward / 20 cm lateral and the rear foot has
# turned 90 deg, so R in nav is diag(0.04, 1e-4, 4e-4) m^2, not diag(1e-4, 0.04, 4e-4).
def test_step_vector_kalman_update_in_the_rear_foot_frame_by_hand():
    filt, res, t = _run_hand_step()
    _, _, _, y, h, r_nav = _hand_measurement()
    (u,) = filt.updates
    p = u["cov_before"]
    np.testing.assert_allclose(p, np.diag(np.tile(np.concatenate([[1e-4] * 3, [1e-2] * 3, POS_VAR]), 2)), atol=0)
    s_mat = h @ p @ h.T + r_nav
    gain = p @ h.T @ np.linalg.inv(s_mat)
    dx = gain @ y
    cov = (np.eye(2 * N_STATES) - gain @ h) @ p
    np.testing.assert_allclose(u["dx"], dx, rtol=0, atol=1e-12)
    np.testing.assert_allclose(u["cov_after"], cov, rtol=0, atol=1e-12)
    np.testing.assert_allclose(u["p_after"][LEFT], P_FRONT - dx[POS : POS + 3], rtol=0, atol=1e-12)
    np.testing.assert_allclose(
        u["p_after"][RIGHT], P_REAR - dx[N_STATES + POS : N_STATES + POS + 3], rtol=0, atol=1e-12
    )
    # the frame matters here: with R unrotated the correction differs by centimetres
    r_wrong = np.diag(STD_M**2)
    dx_wrong = p @ h.T @ np.linalg.solve(h @ p @ h.T + r_wrong, y)
    assert np.max(np.abs(dx_wrong - dx)) > 0.01


# mutant: step-vector-heel-strike-boundary
# step-vector-heel-strike-boundary: a heel strike exactly at the stance run's first sample opens
# that run (hs <= start); with hs < start the fusion falls back to 0.1 s before, 10 samples early.
def test_landing_and_support_at_heel_strikes_on_the_stance_start():
    filt, res, t = _run_hand_step()
    # the fusion stops at each landing (the heel strikes 120 and 250), then at the end
    assert filt.stops == [t[HS_RIGHT], t[HS_LEFT], np.inf]
    fusion = StepVectorFusion()
    imu = ImuData(t, np.tile([0.0, 0.0, 9.80665], (N, 1)), np.zeros((N, 3)))
    assert fusion._heel_strikes(FeetView.of([imu], [_stance(RIGHT_STANCE, [HS_RIGHT])]), 0, [120]).tolist() == [120]
    # one sample later is outside the run's past: the fallback 0.1 s before the stance start
    assert fusion._heel_strikes(FeetView.of([imu], [_stance(RIGHT_STANCE, [121])]), 0, [120]).tolist() == [110]
    # unsorted heel strikes, one too early (0.5 s window), none at all
    assert fusion._heel_strikes(
        FeetView.of([imu], [_stance(RIGHT_STANCE, [118, 60, 115])]), 0, [120, 116, 200]
    ).tolist() == [118, 115, 190]
    assert fusion._heel_strikes(FeetView.of([imu], [_stance(RIGHT_STANCE, [])]), 0, [120, 5]).tolist() == [110, 0]
