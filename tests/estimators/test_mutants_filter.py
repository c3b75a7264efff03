"""Filter and smoother tests that kill mutants of ``tools/mutate.py`` the rest of the suite let through.

References are independent of the compiled code: the dense numpy filter of
tests/estimators/test_ins_filter.py (``_reference_forward``), the RTS recursion written out here, and
the identity "sequential Kalman updates with block-diagonal R equal one stacked update".
"""

from __future__ import annotations

import numpy as np
import pytest
from test_ins_filter import _reference_forward

import footnav
from footnav.core.types import StanceResult, stance_intervals
from footnav.estimators.ekf import EkfEstimator
from footnav.estimators.ekf.smoother import smooth
from footnav.nav import quaternion as quat


@pytest.fixture(scope="module")
def walk():
    rec = footnav.simulate("straight", seed=4, distance_m=6.0, standstill_s=1.0)
    return rec.left, StanceResult(rec.truth_left.stance)


# ins-pcov-index: the reported position covariance (xx, xy, yy, zz) is the filter's P, sample by
# sample, against the dense reference filter
def test_reported_position_covariance_is_the_dense_filters(walk):
    imu, stance = walk
    est = EkfEstimator(smoother="none", heading="sensor")
    _, hist, k0, _ = _reference_forward(est, imu, stance)
    filt = est.start([imu], [stance])
    filt.run_until()
    pcov = filt.outputs(0)[3]
    ref = np.array([[p[6, 6], p[6, 7], p[7, 7], p[8, 8]] for _, p, _, _ in hist])
    np.testing.assert_allclose(pcov[k0 + 1 :], ref, rtol=1e-6, atol=1e-14)
    assert np.abs(ref[:, 1]).max() > 1e-6  # the walk does correlate x and y


def _reference_rts_full(est, imu, stance):
    """The dense RTS of test_ins_filter, also for velocity and attitude, down to the first sample."""
    out, hist, k0, cov0 = _reference_forward(est, imu, stance)
    n = imu.n_samples
    sm_q, sm_v = np.empty((n, 4)), np.empty((n, 3))
    sm_q[-1], sm_v[-1] = out[n - 1][0], out[n - 1][1]
    delta = np.zeros(len(hist[0][3]))
    for k in range(n - 2, k0 - 1, -1):
        p_pred_next, _, f_next, dx_next = hist[k - k0]
        p_filt = hist[k - k0 - 1][1] if k > k0 else cov0
        delta = p_filt @ f_next.T @ np.linalg.inv(p_pred_next) @ (delta + dx_next)
        sm_v[k] = out[k][1] - delta[3:6]
        sm_q[k] = quat.normalize(quat.multiply(quat.from_rotvec(delta[:3]), out[k][0]))
    return sm_q[k0:], sm_v[k0:], k0


# smooth-initial-velocity-dropped, smooth-initial-q-swapped: the whole-walk smoother's velocity
# and attitude, including the filter's first sample (corrected by the adjoint before the first
# event), against the dense RTS
def test_smoothed_velocity_and_attitude_from_the_first_sample_match_the_dense_rts(walk):
    imu, stance = walk
    est = EkfEstimator(smoother="whole", heading="sensor", init_attitude_std_rad=0.05, init_velocity_std_mps=0.05)
    ref_q, ref_v, k0 = _reference_rts_full(est, imu, stance)
    filt = est.start([imu], [stance])
    filt.run_until()
    sm_q, sm_v, _ = smooth(filt, "whole")
    first = len(sm_v) - len(ref_v)
    np.testing.assert_allclose(sm_v[first:], ref_v, atol=1e-8)
    np.testing.assert_allclose(quat.normalize(sm_q[first:]), quat.normalize(ref_q), atol=1e-8)
    filtered_v = filt.outputs(0)[1]
    assert np.abs(sm_v[first] - filtered_v[first]).max() > 1e-4  # the first sample is corrected


def _run_with_position_fix(est, imu, stance, stacked: bool, last_swing: bool = False):
    """Walk to mid-swing (of the middle or the last swing), then fix x and y of the position
    (0.2 m and -0.1 m off) by two sequential scalar updates or by one stacked update; smooth."""
    filt = est.start([imu], [stance])
    swing = np.flatnonzero(~stance.mask)
    if last_swing:
        swing = swing[swing > stance_intervals(stance.mask)[-2, 1]]
    k = swing[len(swing) // 2]
    filt.run_until(imu.t[k])
    o = filt.block(0, "pos").start
    z = filt.position(0)[:2] + [0.2, -0.1]
    if stacked:
        filt.update(filt.selection(np.array([o, o + 1])), filt.position(0)[:2] - z, np.array([1e-4, 1e-4]))
    else:
        for axis in (0, 1):
            filt.update(
                filt.selection(np.array([o + axis])), np.atleast_1d(filt.position(0)[axis] - z[axis]), np.array([1e-4])
            )
    filt.run_until()
    fwd = filt.outputs(0)[2].copy()
    if last_swing:
        return filt.outputs(0)[1].copy(), smooth(filt, est.smoother)[1], k
    return fwd, smooth(filt, est.smoother)[2], k


# smooth-caller-updates-order: two updates at one instant go back through the smoother last
# first; sequential updates with independent noise equal one stacked update, forward and smoothed
def test_two_sequential_updates_smooth_like_one_stacked_update(walk):
    imu, stance = walk
    est = EkfEstimator(smoother="whole", heading="sensor")
    fwd_seq, sm_seq, _ = _run_with_position_fix(est, imu, stance, stacked=False)
    fwd_one, sm_one, _ = _run_with_position_fix(est, imu, stance, stacked=True)
    # the nominal states differ at second order (two attitude resets instead of one): 1e-4 m
    np.testing.assert_allclose(fwd_seq, fwd_one, atol=2e-4)
    np.testing.assert_allclose(sm_seq - fwd_seq, sm_one - fwd_one, atol=2e-4)
    assert np.abs(sm_one - fwd_one).max() > 0.05


# smooth-step-h-sign: within a step, the step-wise smoother carries a caller's position fix back
# to the samples before it, in the direction of the fix, as the whole-walk smoother does
def test_step_smoother_carries_a_position_fix_back_the_right_way(walk):
    imu, stance = walk
    fwd_w, sm_w, k = _run_with_position_fix(EkfEstimator(smoother="whole", heading="sensor"), imu, stance, stacked=True)
    fwd_s, sm_s, _ = _run_with_position_fix(EkfEstimator(smoother="step", heading="sensor"), imu, stance, stacked=True)
    np.testing.assert_allclose(fwd_s, fwd_w, atol=1e-12)
    before = k - 5  # mid-swing, five samples before the fix
    shift_w, shift_s = sm_w[before, :2] - fwd_w[before, :2], sm_s[before, :2] - fwd_s[before, :2]
    assert shift_w[0] > 0.05 and shift_w[1] < -0.02  # towards +0.2 m in x and -0.1 m in y
    assert shift_s[0] > 0.005 and shift_s[1] < -0.005


# smooth-step-h-sign: in the walk's last step both smoothers start from nothing known after the
# recording's end and go back through the same events, so their smoothed velocities agree there
# (velocities are not chained), with a caller's position fix inside that step
def test_step_and_whole_smoothers_agree_on_the_last_step_with_a_position_fix(walk):
    imu, stance = walk
    vel, sm_w, k = _run_with_position_fix(
        EkfEstimator(smoother="whole", heading="sensor"), imu, stance, True, last_swing=True
    )
    _, sm_s, _ = _run_with_position_fix(
        EkfEstimator(smoother="step", heading="sensor"), imu, stance, True, last_swing=True
    )
    start = stance_intervals(stance.mask)[-2, 1]  # the last step starts after its stance's last sample
    np.testing.assert_allclose(sm_s[start:], sm_w[start:], atol=1e-9)
    assert np.abs(sm_w[start:k] - vel[start:k]).max() > 0.01  # the fix moved the velocities before it
