"""Dense Kalman filter and Rauch-Tung-Striebel primitives: the tests' reference, not footnav's.

footnav's filters use the structured kernels of :mod:`footnav.nav.kalman` and
:mod:`footnav.estimators.ekf._kernels`; the tests check those against these general, dense forms
(any F, H, R), which are themselves checked against filterpy (tests/nav/test_kalman.py). They
work in place on caller-owned arrays (scratch from :func:`workspace`). Notation as in Simon,
*Optimal State Estimation* (2006), ch. 5 and 9.3:

* predict:  P <- F P F' + Q
* update:   K = P H' (H P H' + R)^-1,  x <- x + K (z - H x),
            P <- (I - K H) P (I - K H)' + K R K'   (Joseph form, then symmetrised)
* RTS:      C = P_f F' P_p^-1,  x_s = x_f + C (x_s+ - x_p),  P_s = P_f + C (P_s+ - P_p) C'
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from footnav._numba import njit  # numba.njit that survives a read-only install

__all__ = ["predict", "rts_step", "spd_inverse", "symmetrize", "update", "workspace"]


def workspace(n: int, m: int) -> tuple[NDArray[np.float64], ...]:
    """Scratch arrays for :func:`predict` / :func:`update` with n states and m measurements.

    Returns ``(nn1, nn2, nm1, nm2, mm1, mm2, mm3)``.
    """
    return (
        np.zeros((n, n)),
        np.zeros((n, n)),
        np.zeros((n, m)),
        np.zeros((n, m)),
        np.zeros((m, m)),
        np.zeros((m, m)),
        np.zeros((m, m)),
    )


@njit(cache=True)
def _matmul(a, b, out):
    """out = a @ b (no allocation)."""
    n, k = a.shape
    m = b.shape[1]
    for i in range(n):
        for j in range(m):
            s = 0.0
            for l in range(k):
                s += a[i, l] * b[l, j]
            out[i, j] = s


@njit(cache=True)
def _matmul_bt(a, b, out):
    """out = a @ b.T (no allocation)."""
    n, k = a.shape
    m = b.shape[0]
    for i in range(n):
        for j in range(m):
            s = 0.0
            for l in range(k):
                s += a[i, l] * b[j, l]
            out[i, j] = s


@njit(cache=True)
def symmetrize(p):
    """P <- (P + P') / 2 in place: rounding must not break the covariance's symmetry."""
    n = p.shape[0]
    for i in range(n):
        for j in range(i + 1, n):
            s = 0.5 * (p[i, j] + p[j, i])
            p[i, j] = s
            p[j, i] = s


@njit(cache=True)
def spd_inverse(s, out, low):
    """out = S^-1 for symmetric positive-definite S via Cholesky S = L L' (no allocation).

    Returns False (and leaves ``out`` undefined) when S is not positive definite.
    """
    m = s.shape[0]
    for i in range(m):
        for j in range(m):
            low[i, j] = 0.0
    for j in range(m):
        d = s[j, j]
        for k in range(j):
            d -= low[j, k] * low[j, k]
        if d <= 0.0:
            return False
        low[j, j] = np.sqrt(d)
        for i in range(j + 1, m):
            v = s[i, j]
            for k in range(j):
                v -= low[i, k] * low[j, k]
            low[i, j] = v / low[j, j]
    # invert L in place of ``out`` (lower triangular), then S^-1 = L^-T L^-1
    for i in range(m):
        for j in range(m):
            out[i, j] = 0.0
    for j in range(m):
        out[j, j] = 1.0 / low[j, j]
        for i in range(j + 1, m):
            v = 0.0
            for k in range(j, i):
                v -= low[i, k] * out[k, j]
            out[i, j] = v / low[i, i]
    # out <- out' out, computed column-wise from the bottom so entries are read before overwritten
    for i in range(m):
        for j in range(i, m):
            v = 0.0
            for k in range(j, m):
                v += out[k, i] * out[k, j]
            low[i, j] = v
    for i in range(m):
        for j in range(i, m):
            out[i, j] = low[i, j]
            out[j, i] = low[i, j]
    return True


@njit(cache=True)
def predict(p, f, q, nn1):
    """Covariance time update in place: P <- F P F' + Q, symmetrised.

    Parameters
    ----------
    p
        Covariance (n, n), overwritten.
    f
        State transition (n, n).
    q
        Process noise covariance (n, n) of the discrete step.
    nn1
        Scratch (n, n).
    """
    _matmul(f, p, nn1)  # F P
    _matmul_bt(nn1, f, p)  # (F P) F'
    n = p.shape[0]
    for i in range(n):
        for j in range(n):
            p[i, j] += q[i, j]
    symmetrize(p)


@njit(cache=True)
def update(x, p, h, r, innovation, nn1, nn2, nm1, nm2, mm1, mm2, mm3):
    """Measurement update in place (Joseph form): x <- x + K y, P <- (I-KH)P(I-KH)' + K R K'.

    Parameters
    ----------
    x
        State (n,), overwritten (an error-state filter passes zeros and reads the correction).
    p
        Covariance (n, n), overwritten.
    h
        Measurement matrix (m, n).
    r
        Measurement noise covariance (m, m).
    innovation
        y = z - H x (m,).
    nn1, nn2, nm1, nm2, mm1, mm2, mm3
        Scratch from :func:`workspace`.

    Returns
    -------
    bool
        False when the innovation covariance is not positive definite (nothing is changed).
    """
    n = p.shape[0]
    m = h.shape[0]
    _matmul_bt(p, h, nm1)  # P H'
    _matmul(h, nm1, mm1)  # H P H'
    for i in range(m):
        for j in range(m):
            mm1[i, j] += r[i, j]  # S = H P H' + R
    if not spd_inverse(mm1, mm2, mm3):
        return False
    _matmul(nm1, mm2, nm2)  # K = P H' S^-1
    for i in range(n):
        v = 0.0
        for j in range(m):
            v += nm2[i, j] * innovation[j]
        x[i] += v  # x + K y
    _matmul(nm2, h, nn1)  # K H
    for i in range(n):
        for j in range(n):
            nn1[i, j] = (1.0 if i == j else 0.0) - nn1[i, j]  # A = I - K H
    _matmul(nn1, p, nn2)  # A P
    _matmul_bt(nn2, nn1, p)  # A P A'
    _matmul(nm2, r, nm1)  # K R
    for i in range(n):
        for j in range(n):
            v = 0.0
            for k in range(m):
                v += nm1[i, k] * nm2[j, k]
            p[i, j] += v  # + K R K'
    symmetrize(p)
    return True


@njit(cache=True)
def rts_step(x_f, p_f, x_p_next, p_p_next, f_next, x_s_next, p_s_next, x_out, p_out):
    """One backward Rauch-Tung-Striebel step (Simon 2006, eq. 9.94 in information-free form).

    Parameters
    ----------
    x_f, p_f
        Filtered state (n,) and covariance (n, n) at step k.
    x_p_next, p_p_next
        Predicted state and covariance at k+1 (before its update).
    f_next
        Transition from k to k+1.
    x_s_next, p_s_next
        Smoothed state and covariance at k+1.
    x_out, p_out
        Smoothed state and covariance at k (written).
    """
    # C = P_f F' P_p^-1, solved as P_p C' = F P_f (P_p symmetric)
    c = np.linalg.solve(p_p_next, f_next @ p_f).T
    x_out[:] = x_f + c @ (x_s_next - x_p_next)
    p_out[:, :] = p_f + c @ (p_s_next - p_p_next) @ c.T
    symmetrize(p_out)
