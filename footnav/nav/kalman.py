"""The Kalman update, compiled: a 3-vector of states for every footnav filter's own updates, any H for a caller's.

A zero-velocity update (``ekf``, ``madgwick``), the zero-angular-rate update (``ekf`` with bias
states) and a 3-D position measurement all measure one 3-vector of the state directly, so H is a
selection ``[0 I 0]`` at an offset ``o`` and R is ``r I``. Then (Simon, *Optimal State
Estimation* (2006), ch. 5)::

    S = H P H' + R = P[o:o+3, o:o+3] + r I       (3 x 3, inverted by cofactors)
    K = P H' S^-1 = P[:, o:o+3] S^-1             (N x 3)
    dx = K y,   P <- P - K (H P) = P - K P[o:o+3, :]

in O(N) and O(N^2) operations instead of the dense products' O(N^2 m) and O(N^3). The simple
form of the covariance update (not Joseph's) keeps P symmetric when it is written from one value
into both triangles; the dense reference the tests compare with is tests/reference_kalman.py.

Callers: :mod:`footnav.estimators.ekf._loop` (its ZUPT and ZARU), :mod:`footnav.estimators.madgwick`
(its ZUPT); :func:`sym3_inverse` also serves :mod:`footnav.fusion.particle_ekf`.

:func:`update_dense` is the general form for the few measurements a coupled fusion makes per step
(any (m, N) H, m small): the same equations with S factored by Cholesky, in one compiled call
instead of some twenty small numpy calls (each of which costs more than the arithmetic).
"""

from __future__ import annotations

import numpy as np

from footnav._numba import njit  # numba.njit that survives a read-only install

__all__ = ["DENSE_BAD_INPUT", "DENSE_NOT_PD", "DENSE_OK", "sym3_inverse", "update3", "update3_inline", "update_dense"]


@njit(cache=True, inline="always", error_model="numpy")
def sym3_inverse(a, b, c, d, e, f):
    """Inverse of the symmetric [[a b c] [b d e] [c e f]] by cofactors: (i00, i01, i02, i11, i12,
    i22, det); the entries are undefined when det <= 0 (not positive definite)."""
    i00 = d * f - e * e
    i01 = c * e - b * f
    i02 = b * e - c * d
    det = a * i00 + b * i01 + c * i02
    inv = 1.0 / det if det != 0.0 else 0.0
    return (i00 * inv, i01 * inv, i02 * inv, (a * f - c * c) * inv, (b * c - a * e) * inv, (a * d - b * b) * inv, det)


def _update3(cov, dx, o, y0, y1, y2, r, gate, gain, sy, hp):
    """Kalman update with a measurement of the 3 states at ``o``: ``y = x[o:o+3] + noise``,
    noise variance ``r`` (each axis), in place.

    Parameters
    ----------
    cov
        P (N, N), overwritten by P - K H P, both triangles from one value (exactly symmetric).
    dx
        (N,) written: the correction K y of an error state that is zero before the update,
        computed as P H' (S^-1 y).
    o
        First of the 3 measured states.
    y0, y1, y2
        The innovation y (z - H x, or an error-state filter's h(x^) - z).
    r
        Measurement noise variance per axis.
    gate
        Chi-square gate on the normalised innovation squared y' S^-1 y (inf: none).
    gain, sy, hp
        (N, 3), (3,), (3, N): written with K = P H' S^-1, S^-1 y and H P (before the update).

    Returns
    -------
    bool
        False (and nothing changed but scratch) when S is not positive definite or the gate
        rejects the measurement.

    Notes
    -----
    K and dx read the columns of P (P H'), the covariance update its rows (H P): a filter whose
    prediction leaves P exactly symmetric (``ekf``) gets the same numbers either way, and one whose
    ``Phi P Phi'`` does not (``madgwick``) gets the update written for it.
    """
    big = cov.shape[0]
    # S = H P H' + R
    i00, i01, i02, i11, i12, i22, det = sym3_inverse(
        cov[o, o] + r, cov[o, o + 1], cov[o, o + 2], cov[o + 1, o + 1] + r, cov[o + 1, o + 2], cov[o + 2, o + 2] + r
    )
    if not det > 0.0:
        return False
    # S^-1 y
    s0 = i00 * y0 + i01 * y1 + i02 * y2
    s1 = i01 * y0 + i11 * y1 + i12 * y2
    s2 = i02 * y0 + i12 * y1 + i22 * y2
    if y0 * s0 + y1 * s1 + y2 * s2 > gate:
        return False
    sy[0], sy[1], sy[2] = s0, s1, s2
    for j in range(big):
        hp[0, j], hp[1, j], hp[2, j] = cov[o, j], cov[o + 1, j], cov[o + 2, j]  # H P
        c0, c1, c2 = cov[j, o], cov[j, o + 1], cov[j, o + 2]  # row j of P H'
        # K = P H' S^-1
        gain[j, 0] = c0 * i00 + c1 * i01 + c2 * i02
        gain[j, 1] = c0 * i01 + c1 * i11 + c2 * i12
        gain[j, 2] = c0 * i02 + c1 * i12 + c2 * i22
        dx[j] = c0 * s0 + c1 * s1 + c2 * s2  # dx = P H' S^-1 y
    # P <- P - K H P
    for i in range(big):
        g0, g1, g2 = gain[i, 0], gain[i, 1], gain[i, 2]
        for j in range(i, big):
            val = cov[i, j] - g0 * hp[0, j] - g1 * hp[1, j] - g2 * hp[2, j]
            cov[i, j] = val
            cov[j, i] = val
    return True


update3 = njit(cache=True, error_model="numpy")(_update3)
#: The same kernel, inlined into its caller: madgwick's loop calls it at every stance sample,
#: and a call passing its four arrays costs their reference counting (about 6 % of madgwick's
#: time, measured); the ekf's loop, larger, calls :func:`update3`.
update3_inline = njit(cache=True, inline="always", error_model="numpy")(_update3)


#: What :func:`update_dense` found: the update is computed; S is not positive definite; H, y or r
#: are not finite (or r not positive).
DENSE_OK, DENSE_NOT_PD, DENSE_BAD_INPUT = 0, 1, 2


@njit(cache=True, error_model="numpy")
# complexity: a compiled kernel whose branches are its input checks and the Cholesky's failure cases
def update_dense(cov, h, y, r, chol, ph, gain, sy, dx, new_cov):  # noqa: C901
    """Kalman update with a dense measurement ``y = H dx + noise`` (noise variances ``r``), into
    scratch: nothing the caller passes as input changes, so it can still decide (a gate on the
    returned normalised innovation squared) before it takes ``new_cov`` and ``dx``.

    Parameters
    ----------
    cov
        P (N, N), read only.
    h, y, r
        H (m, N), the innovation (m,) (z - H x, or an error-state filter's h(x^) - z) and the
        measurement noise variance per component (m,).
    chol, ph
        Scratch (m, m) and (N, m): the Cholesky factor L of S = H P H' + diag(r), and P H'.
    gain, sy, dx, new_cov
        Written: K = P H' S^-1 (N, m), S^-1 y (m,), dx = K y (N,) and P - K (H P), symmetrised
        as (A + A') / 2 (N, N).

    Returns
    -------
    tuple of (int, float)
        (``DENSE_OK``, y' S^-1 y); (``DENSE_NOT_PD``, nan) when S is not positive definite;
        (``DENSE_BAD_INPUT``, nan) when H, y or r hold a non-finite value or r a value <= 0.
        Only with ``DENSE_OK`` are ``gain``, ``sy``, ``dx`` and ``new_cov`` written.
    """
    big, m = cov.shape[0], len(y)
    for i in range(m):
        if not (np.isfinite(y[i]) and r[i] > 0.0 and np.isfinite(r[i])):
            return DENSE_BAD_INPUT, np.nan
        for j in range(big):
            if not np.isfinite(h[i, j]):
                return DENSE_BAD_INPUT, np.nan
    for i in range(big):  # P H'
        for a in range(m):
            acc = 0.0
            for j in range(big):
                acc += cov[i, j] * h[a, j]
            ph[i, a] = acc
    for a in range(m):  # S = H (P H') + R, factored S = L L' (lower triangle of chol)
        for b in range(a + 1):
            acc = 0.0
            for j in range(big):
                acc += h[a, j] * ph[j, b]
            if a == b:
                acc += r[a]
            for c in range(b):
                acc -= chol[a, c] * chol[b, c]
            if a == b:
                if not acc > 0.0:
                    return DENSE_NOT_PD, np.nan
                chol[a, a] = np.sqrt(acc)
            else:
                chol[a, b] = acc / chol[b, b]
    # S^-1 v by forward and back substitution: for y, then for each row of P H' (K = P H' S^-1)
    nis = 0.0
    for a in range(m):
        acc = y[a]
        for c in range(a):
            acc -= chol[a, c] * sy[c]
        sy[a] = acc / chol[a, a]
    for a in range(m - 1, -1, -1):
        acc = sy[a]
        for c in range(a + 1, m):
            acc -= chol[c, a] * sy[c]
        sy[a] = acc / chol[a, a]
    for a in range(m):
        nis += y[a] * sy[a]
    for i in range(big):
        for a in range(m):
            acc = ph[i, a]
            for c in range(a):
                acc -= chol[a, c] * gain[i, c]
            gain[i, a] = acc / chol[a, a]
        for a in range(m - 1, -1, -1):
            acc = gain[i, a]
            for c in range(a + 1, m):
                acc -= chol[c, a] * gain[i, c]
            gain[i, a] = acc / chol[a, a]
        acc = 0.0
        for a in range(m):
            acc += gain[i, a] * y[a]
        dx[i] = acc
    for i in range(big):  # P - K (P H')', symmetrised
        for j in range(i + 1):
            u = cov[i, j]
            w = cov[j, i]
            for a in range(m):
                u -= gain[i, a] * ph[j, a]
                w -= gain[j, a] * ph[i, a]
            val = 0.5 * (u + w)
            new_cov[i, j] = val
            new_cov[j, i] = val
    return DENSE_OK, nis
