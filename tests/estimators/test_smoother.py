"""The EKF's smoothers (footnav/estimators/ekf/smoother.py) against references independent of the
compiled code.

The references: the dense numpy filter of tests/estimators/test_ins_filter.py (``_reference_forward``),
the RTS recursion written out here, and the identity "sequential Kalman updates with block-diagonal R
equal one stacked update". The tests were written to kill mutants of ``tools/mutate.py``; the comment
above each names them.
"""

from __future__ import annotations

import numpy as np
import pytest
from reference_ins import nominal_step  # tests/reference_ins.py
from test_ins_filter import _reference_forward

import footnav
from footnav.core.types import StanceResult, stance_intervals
from footnav.estimators.ekf import EkfEstimator
from footnav.estimators.ekf.smoother import smooth
from footnav.nav import quaternion as quat


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


# mutant: smooth-initial-velocity-dropped, smooth-initial-q-swapped
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


# mutant: smooth-caller-updates-order
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


# mutant: smooth-step-h-sign
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


# mutant: smooth-step-h-sign
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


# -- two caller updates at one instant, against a dense RTS (smooth-caller-updates-order) ----------
#
# Two caller updates at one instant, smoothed over the whole walk, against a dense RTS reference.
#
# Written for tools/mutate.py's ``smooth-caller-updates-order`` (the whole-walk smoother takes a
# segment's caller updates first-to-last on its way back instead of last-to-first).
#
# Why the order matters (and why the earlier test, an x fix then a y fix on a straight walk, did
# not see it). The smoother's backward pass carries the adjoint lambda through each update
# ``i`` (``y_i = h(x^) - z_i``, ``S_i``, ``K_i``, ``U_i = I - K_i H_i``, ``a_i = S_i^-1 y_i``) as
# ``lambda <- U_i' lambda + H_i' a_i`` (modified Bryson-Frazier). Two updates 1 then 2 at one
# instant must be undone 2 first: ``U_1' U_2' lam + U_1' H_2' a_2 + H_1' a_1``; the other order
# gives ``U_2' U_1' lam + U_2' H_1' a_1 + H_2' a_2``. With nothing known after the instant
# (``lam = 0``) the difference is ``H_2' K_2' H_1' a_1 - H_1' K_1' H_2' a_2``, and what the earlier
# samples see of it is ``P`` times it (P the prior at the instant):
# ``P H_2' S_2^-1 (H_2 P_1 H_1') a_1 - P H_1' S_1^-1 (H_1 P H_2') a_2``. For an x fix and a y fix
# both brackets are the x-y position covariance, near zero on a straight walk: the orders agree
# there. For two fixes of the *same* axis (H_1 = H_2 = e_x, variances r_1, r_2, values z_1, z_2)
# the brackets are ``P1_xx`` and ``P_xx`` and the difference is
# ``P e_x (P1_xx y_1 - P_xx y_2) / (S_1 S_2) = P e_x P_xx (z_2 - z_1) / (S_1 S_2)``: zero only
# when the two fixes agree. Here they differ by six standard deviations of the foot's x position
# (8 cm), and the smoothed positions before the instant move by 16 mm with the wrong order; a
# second case, an x fix then one along the diagonal x + y, moves them by 8 mm.
#
# The reference: the closed-loop error-state filter written densely in numpy (the documented
# mechanization: mid-interval attitude, Simpson's rule; F = I + A dt of the 9-state model; ZUPTs),
# the two fixes applied one after the other with the nominal state corrected in between, and the
# RTS smoother (Simon 2006, eq. 9.94 on the error state), which needs only each sample's predicted
# and final filtered covariance and total correction, so it does not depend on any update order.


def _dense_f(f_n, dt):
    """F = I + A dt of the 9-state model [attitude, velocity, position] error."""
    x, y, z = f_n * dt
    f = np.eye(9)
    f[3:6, 0:3] = [[0, -z, y], [z, 0, -x], [-y, x, 0]]
    f[6:9, 3:6] = np.eye(3) * dt
    return f


def _reference(est, imu, stance, k_fix, fixes):
    """Dense forward filter + RTS; ``fixes`` [(row (9,), z, r)] applied in order at sample k_fix.
    Returns the forward positions (at k_fix: before the fixes, as the filter records its output
    when it reaches a sample) and the smoothed ones, from the filter's first sample on."""
    filt = est.start([imu], [stance])  # the initial state and noise only
    noise = filt.noise
    q_diag = noise.q_diag(9)
    q, v, p = filt.quaternion(0), np.zeros(3), np.zeros(3)
    ba, bg = filt.biases(0)
    cov0 = filt.covariance.copy()
    cov = cov0.copy()
    k0 = filt.index(0)
    f_prev = quat.as_matrix(q) @ (imu.acc[k0] - ba)
    hist, out, seen = [], {k0: p.copy()}, {k0: p.copy()}

    def correct(dx):
        nonlocal q, v, p
        q = quat.normalize(quat.multiply(quat.from_rotvec(dx[:3]), q))
        v, p = v - dx[3:6], p - dx[6:9]

    for k in range(k0 + 1, imu.n_samples):
        dt = imu.t[k] - imu.t[k - 1]
        f = _dense_f(f_prev, dt)
        q, v, p, f_prev = nominal_step(imu, k, q, v, p, f_prev, ba, bg)
        p_pred = f @ cov @ f.T + np.diag(q_diag * dt)
        cov = p_pred
        total = np.zeros(9)
        # (H, z, r) in order: the ZUPT (z = 0 for the velocity), then the caller's fixes
        updates = []
        if stance.mask[k]:
            updates.append(
                (
                    np.hstack([np.zeros((3, 3)), np.eye(3), np.zeros((3, 3))]),
                    np.zeros(3),
                    np.full(3, noise.zupt_std_mps**2),
                )
            )
        n_zupt = len(updates)
        if k == k_fix:
            updates += [(row[None, :], np.atleast_1d(z), np.atleast_1d(r)) for row, z, r in fixes]
        for i, (h, z, r) in enumerate(updates):
            if i == n_zupt:
                seen[k] = p.copy()  # the filter's output of sample k: before the caller's updates
            innov = h[:, 3:6] @ v + h[:, 6:9] @ p - z  # h(x^) - z
            s = h @ cov @ h.T + np.diag(r)
            gain = cov @ h.T @ np.linalg.inv(s)
            dx = gain @ innov
            cov = cov - gain @ h @ cov
            correct(dx)
            total += dx
        hist.append((p_pred, cov.copy(), f, total))
        out[k] = p.copy()
        seen.setdefault(k, p.copy())
    n = imu.n_samples
    delta = np.zeros(9)
    sm = {n - 1: out[n - 1]}
    for k in range(n - 2, k0 - 1, -1):
        p_pred_next, _, f_next, dx_next = hist[k - k0]
        p_filt = hist[k - k0 - 1][1] if k > k0 else cov0
        delta = p_filt @ f_next.T @ np.linalg.inv(p_pred_next) @ (delta + dx_next)
        sm[k] = out[k] - delta[6:9]
    return np.array([seen[k] for k in range(k0, n)]), np.array([sm[k] for k in range(k0, n)])


@pytest.fixture(scope="module")
def mid_swing_walk():
    rec = footnav.simulate("straight", seed=4, distance_m=6.0, standstill_s=1.0)
    stance = StanceResult(rec.truth_left.stance)
    swing = np.flatnonzero(~stance.mask)
    return rec.left, stance, int(swing[len(swing) // 2])  # mid-swing of a middle step


def _footnav(est, imu, stance, k_fix, fixes):
    filt = est.start([imu], [stance])
    filt.run_until(imu.t[k_fix])
    o = filt.block(0, "pos").start
    for row, z, r in fixes:
        h = np.zeros((1, filt.covariance.shape[0]))
        h[0, o : o + 3] = row[6:9]
        filt.update(h, np.atleast_1d(row[6:9] @ filt.position(0) - z), np.atleast_1d(r))
    filt.run_until()
    return filt.outputs(0)[2].copy(), smooth(filt, "whole")[2]


EX, DIAG = np.r_[np.zeros(6), 1.0, 0.0, 0.0], np.r_[np.zeros(6), 1.0, 1.0, 0.0] / np.sqrt(2)


# fixes (row, z, r) given the foot's position p and its x variance v at the instant, m, m^2
CASES = {
    # the same axis twice, 6 sigma apart: the orders differ by P e_x P_xx (z_2 - z_1) / (S_1 S_2)
    "x-twice": lambda p, v: [(EX, p[0] + 4 * np.sqrt(v), v), (EX, p[0] - 2 * np.sqrt(v), 2 * v)],
    # x, then the diagonal x + y: the bracket H_2 P_1 H_1' is (P1_xx + P1_xy) / sqrt(2), not small
    "x-then-diagonal": lambda p, v: [(EX, p[0] + 3 * np.sqrt(v), v), (DIAG, DIAG[6:9] @ p - 3 * np.sqrt(v), v)],
}


# mutant: smooth-caller-updates-order
# smooth-caller-updates-order. Measured max |footnav - dense reference| (seed 4, 9 states, fixes
# at mid-swing where P_xx = 1.7e-4 m^2): forward positions 2.7e-15 / 1.8e-15 m, smoothed
# 2.7e-15 / 2.7e-15 m (x-twice / x-then-diagonal); the tolerance is 1e-9 m. With the mutant
# (the updates undone first-to-last) the smoothed positions are 15.8 mm / 7.9 mm off the reference.
# started with smoother="none" the filter records no segments: smooth(filt, "whole") re-runs each
# on the way back and undoes its caller updates from the checkpoint's list (the path the ported
# mutant changes); started with "whole" they are undone from the kept (or re-recorded) chunks
@pytest.mark.parametrize("started", ["whole", "none"])
@pytest.mark.parametrize("case", sorted(CASES))
def test_two_updates_at_one_instant_smooth_as_the_dense_rts(mid_swing_walk, case, started):
    imu, stance, k_fix = mid_swing_walk
    est = EkfEstimator(smoother=started, heading="sensor")
    probe = est.start([imu], [stance])
    probe.run_until(imu.t[k_fix])
    o = probe.block(0, "pos").start
    fixes = CASES[case](
        probe.position(0), probe.covariance[o, o]
    )  # the fixes' values relative to where the foot is then
    fwd, sm = _footnav(est, imu, stance, k_fix, fixes)
    ref_fwd, ref_sm = _reference(est, imu, stance, k_fix, fixes)
    k0 = len(fwd) - len(ref_fwd)
    np.testing.assert_allclose(fwd[k0:], ref_fwd, atol=1e-9)
    np.testing.assert_allclose(sm[k0:], ref_sm, atol=1e-9)
    assert np.abs(sm - fwd).max() > 0.01  # the fixes reach back (measured 0.015 m, x-twice; 0.056 m, x-then-diagonal)
