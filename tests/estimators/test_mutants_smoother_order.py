"""Two caller updates at one instant, smoothed over the whole walk, against a dense RTS reference.

Written for tools/mutate.py's ``smooth-caller-updates-order`` (the whole-walk smoother takes a
segment's caller updates first-to-last on its way back instead of last-to-first).

Why the order matters (and why the earlier test, an x fix then a y fix on a straight walk, did
not see it). The smoother's backward pass carries the adjoint lambda through each update
``i`` (``y_i = h(x^) - z_i``, ``S_i``, ``K_i``, ``U_i = I - K_i H_i``, ``a_i = S_i^-1 y_i``) as
``lambda <- U_i' lambda + H_i' a_i`` (modified Bryson-Frazier). Two updates 1 then 2 at one
instant must be undone 2 first: ``U_1' U_2' lam + U_1' H_2' a_2 + H_1' a_1``; the other order
gives ``U_2' U_1' lam + U_2' H_1' a_1 + H_2' a_2``. With nothing known after the instant
(``lam = 0``) the difference is ``H_2' K_2' H_1' a_1 - H_1' K_1' H_2' a_2``, and what the earlier
samples see of it is ``P`` times it (P the prior at the instant):
``P H_2' S_2^-1 (H_2 P_1 H_1') a_1 - P H_1' S_1^-1 (H_1 P H_2') a_2``. For an x fix and a y fix
both brackets are the x-y position covariance, near zero on a straight walk: the orders agree
there. For two fixes of the *same* axis (H_1 = H_2 = e_x, variances r_1, r_2, values z_1, z_2)
the brackets are ``P1_xx`` and ``P_xx`` and the difference is
``P e_x (P1_xx y_1 - P_xx y_2) / (S_1 S_2) = P e_x P_xx (z_2 - z_1) / (S_1 S_2)``: zero only
when the two fixes agree. Here they differ by six standard deviations of the foot's x position
(8 cm), and the smoothed positions before the instant move by 16 mm with the wrong order; a
second case, an x fix then one along the diagonal x + y, moves them by 8 mm.

The reference: the closed-loop error-state filter written densely in numpy (the documented
mechanization: mid-interval attitude, Simpson's rule; F = I + A dt of the 9-state model; ZUPTs),
the two fixes applied one after the other with the nominal state corrected in between, and the
RTS smoother (Simon 2006, eq. 9.94 on the error state), which needs only each sample's predicted
and final filtered covariance and total correction, so it does not depend on any update order.
"""

from __future__ import annotations

import numpy as np
import pytest
from reference_ins import nominal_step  # tests/reference_ins.py

import footnav
from footnav import StanceResult
from footnav.estimators.ekf import EkfEstimator
from footnav.estimators.ekf.smoother import smooth
from footnav.nav import quaternion as quat


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
def walk():
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


# smooth-caller-updates-order. Measured max |footnav - dense reference| (seed 4, 9 states, fixes
# at mid-swing where P_xx = 1.7e-4 m^2): forward positions 2.7e-15 / 1.8e-15 m, smoothed
# 2.7e-15 / 2.7e-15 m (x-twice / x-then-diagonal); the tolerance is 1e-9 m. With the mutant
# (the updates undone first-to-last) the smoothed positions are 15.8 mm / 7.9 mm off the reference.
# started with smoother="none" the filter records no segments: smooth(filt, "whole") re-runs each
# on the way back and undoes its caller updates from the checkpoint's list (the path the ported
# mutant changes); started with "whole" they are undone from the kept (or re-recorded) chunks
@pytest.mark.parametrize("started", ["whole", "none"])
@pytest.mark.parametrize("case", sorted(CASES))
def test_two_updates_at_one_instant_smooth_as_the_dense_rts(walk, case, started):
    imu, stance, k_fix = walk
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
