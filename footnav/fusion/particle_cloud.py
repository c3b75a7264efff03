"""The particle clouds of Lee, Cho & Park (2022) and the Gaussian-sum numerics around them.

Propagation of a foot's cloud with its EKF (eq. 10-12), the weights and systematic resampling
(eq. 15-16), the Gaussian sum of the two feet (eq. 13-14), and the equivalent measurement that
hands a cloud back to the EKF by Jeffrey's rule (:func:`equivalent_measurement`). Positions in m,
nav frame; clouds (n, 2) horizontal. :mod:`footnav.fusion.particle` is the fusion that uses them.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from footnav._numba import njit  # numba.njit that survives a read-only install

__all__ = ["systematic_resample", "offset_rayleigh", "gaussian_sum", "mixture_mean", "equivalent_measurement"]

#: Largest variance ratio (PF / EKF, whitened) that still counts as information: above it the
#: equivalent measurement's variance would exceed 1e6 x the EKF's, and the update only moves
#: the mean.
_MAX_RATIO = 1.0 - 1e-6
#: Smallest variance ratio: a cloud collapsed onto one particle is not an exact position.
_MIN_RATIO = 1e-6
#: Floor of the likelihood's variance, m^2: a cloud that collapsed across the heading.
_MIN_VAR_M2 = 1e-12


@njit(cache=True)
def _moments(cloud, mean, cov):
    """Mean (2,) and covariance (2, 2) of the cloud (N, 2), 1/N normalised (eq. 14)."""
    n = cloud.shape[0]
    mx = my = 0.0
    for i in range(n):
        mx += cloud[i, 0]
        my += cloud[i, 1]
    mx /= n
    my /= n
    cxx = cxy = cyy = 0.0
    for i in range(n):
        dx = cloud[i, 0] - mx
        dy = cloud[i, 1] - my
        cxx += dx * dx
        cxy += dx * dy
        cyy += dy * dy
    mean[0], mean[1] = mx, my
    cov[0, 0], cov[0, 1], cov[1, 0], cov[1, 1] = cxx / n, cxy / n, cxy / n, cyy / n


@njit(cache=True)
def _propagate(cloud, shift, noise_t, normals, drift, lateral, mean, cov):
    """Eq. 10-12 in place: ``x_n += shift + noise_t' normals_n + drift_n lateral``; writes the
    propagated cloud's mean and covariance (eq. 14)."""
    for i in range(cloud.shape[0]):
        cloud[i, 0] += shift[0] + normals[i, 0] * noise_t[0, 0] + normals[i, 1] * noise_t[1, 0] + drift[i] * lateral[0]
        cloud[i, 1] += shift[1] + normals[i, 0] * noise_t[0, 1] + normals[i, 1] * noise_t[1, 1] + drift[i] * lateral[1]
    _moments(cloud, mean, cov)


@njit(cache=True)
def _weigh_and_resample(cloud, z, lateral, var, u, out, logw, mean, cov):
    """Eq. 15-16 across ``lateral``: weights ``exp(-d^2 / 2 var)``, ``d = lateral . (x_n - z)``,
    then systematic resampling with the one uniform draw ``u`` in [0, 1) into ``out`` (the same
    rule as :func:`systematic_resample`); ``logw`` (N,) is work space. Writes out's moments."""
    n = cloud.shape[0]
    best = -np.inf
    for i in range(n):
        d = (cloud[i, 0] - z[0]) * lateral[0] + (cloud[i, 1] - z[1]) * lateral[1]
        logw[i] = -0.5 * d * d / var
        if logw[i] > best:
            best = logw[i]
    total = 0.0
    for i in range(n):
        logw[i] = np.exp(logw[i] - best)  # now the unnormalised weight
        total += logw[i]
    j = 0
    cum = logw[0] / total
    for k in range(n):
        point = (u + k) / n
        while cum <= point and j < n - 1:
            j += 1
            cum += logw[j] / total
        out[k, 0] = cloud[j, 0]
        out[k, 1] = cloud[j, 1]
    _moments(out, mean, cov)


def systematic_resample(weights: NDArray[np.float64], rng: np.random.Generator) -> NDArray[np.int64]:
    """Indices of N particles drawn by systematic resampling (Kitagawa 1996; Lee, Cho & Park (2022), Sec. 3.2).

    One uniform draw ``u ~ U[0, 1)``; the points ``(u + k) / N``, k = 0..N-1, fall into the
    slices of the cumulative normalised weights, and particle i is copied once per point in its
    slice: ``floor(N w_i)`` or ``ceil(N w_i)`` times.

    Parameters
    ----------
    weights
        (N,) non-negative, not all zero; normalised here.
    rng
        Source of the one uniform draw (only ``rng.random()`` is called).

    Returns
    -------
    ndarray of int64
        (N,) indices into the particles, non-decreasing.
    """
    w = np.asarray(weights, dtype=float)
    n = len(w)
    cum = np.cumsum(w / w.sum())
    cum[-1] = 1.0  # rounding must not lose the last particle
    points = (rng.random() + np.arange(n)) / n
    return np.searchsorted(cum, points, side="right").astype(np.int64)


def offset_rayleigh(
    sigma_m: float, size: int, rng: np.random.Generator, offset_m: float | None = None
) -> NDArray[np.float64]:
    """Samples of the offset Rayleigh distribution ``Rayleigh(sigma) - offset``, m (Lee, Cho &
    Park (2022), eq. 1 and 12).

    ``offset_m`` None: the Rayleigh mean ``sigma sqrt(pi/2)`` (footnav's zero-mean drift): variance
    ``(2 - pi/2) sigma^2``, mode ``sigma (1 - sqrt(pi/2)) < 0`` and a long positive tail (the
    right shoe's; the left shoe's is its mirror, ``-x``). Any other offset leaves the mean
    ``sigma sqrt(pi/2) - offset``: the systematic drift the paper fits to a histogram (Sec. 2.2).
    """
    offset = sigma_m * np.sqrt(np.pi / 2) if offset_m is None else offset_m
    return rng.rayleigh(sigma_m, size) - offset


def gaussian_sum(
    means: NDArray[np.float64], covs: NDArray[np.float64], weights: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Mean and covariance of the Gaussian mixture ``sum_i a_i N(mu_i, S_i)`` (Lee, Cho & Park (2022), eq. 13).

    ``mu = sum a_i mu_i``, ``S = sum a_i (S_i + (mu_i - mu)(mu_i - mu)')``, the weights ``a``
    normalised to sum to 1. ``means`` (K, d), ``covs`` (K, d, d), ``weights`` (K,).
    """
    a = np.asarray(weights, float) / np.sum(weights)
    mu = mixture_mean(means, weights)
    d = means - mu
    cov = np.einsum("i,ijk->jk", a, covs) + np.einsum("i,ij,ik->jk", a, d, d)
    return mu, cov


def mixture_mean(means: NDArray[np.float64], weights: NDArray[np.float64]) -> NDArray[np.float64]:
    """The mean ``sum a_i mu_i`` of :func:`gaussian_sum` alone: it does not depend on the covariances."""
    a = np.asarray(weights, float) / np.sum(weights)
    return np.einsum("i,ij->j", a, means)


@njit(cache=True)
def _eig_sym2(p, q, s):
    """Eigenvalues (larger first) and the angle of the first eigenvector of [[p q] [q s]]:
    the eigenvectors are (cos a, sin a) and (-sin a, cos a)."""
    mid = 0.5 * (p + s)
    rad = np.sqrt(0.25 * (p - s) ** 2 + q * q)
    return mid + rad, mid - rad, 0.5 * np.arctan2(2.0 * q, p - s)


@njit(cache=True)
def _psd_sqrt_t(a, out):
    """``out`` (2, 2) = T with ``T' T`` the positive part of the symmetric ``a`` (2, 2)."""
    l1, l2, ang = _eig_sym2(a[0, 0], 0.5 * (a[0, 1] + a[1, 0]), a[1, 1])
    c, s = np.cos(ang), np.sin(ang)
    r1, r2 = np.sqrt(max(l1, 0.0)), np.sqrt(max(l2, 0.0))
    out[0, 0], out[0, 1] = r1 * c, r1 * s
    out[1, 0], out[1, 1] = -r2 * s, r2 * c


@njit(cache=True)
def equivalent_measurement(p_prior, cov_prior, mean_post, cov_post, a, y, r):
    """The measurement that turns the prior ``N(p_prior, cov_prior)`` of a 2-vector into the
    posterior ``N(mean_post, cov_post)`` by one Kalman update (Jeffrey's rule).

    Whitened by the prior (``L L' = cov_prior``, Cholesky), the posterior covariance is
    ``U diag(l) U'``. Along each ``u_i`` a measurement with variance ``r_i = l_i / (1 - l_i)``
    (whitened units: the prior variance there is 1) shrinks the variance to ``l_i``, and the
    innovation ``y_i = (1 + r_i) u_i' L^-1 (p_prior - mean_post)`` moves the mean onto
    ``mean_post``::

        H = A S,  A = U' L^-1 (S selects the position),  y = h(x^) - z,  R = diag(r)

    Every other state x then moves by ``-P_xp P_pp^-1 (p_prior - mean_post)`` and its
    covariance by ``-P_xp P_pp^-1 (P_pp - cov_post) P_pp^-1 P_px``: the EKF's conditional
    ``p(x | p)`` is kept and the position's marginal replaced. The ratios ``l_i`` are clipped to
    ``[1e-6, 1 - 1e-6]``: where the posterior is not tighter than the prior, the mean still
    moves and the variance stays (a measurement cannot widen it).

    Parameters
    ----------
    p_prior, cov_prior
        (2,), (2, 2): the EKF's horizontal position and its covariance, m, m^2.
    mean_post, cov_post
        (2,), (2, 2): the particle cloud's mean and covariance, m, m^2.
    a, y, r
        Outputs: (2, 2) rows applied to the position, (2,) innovations, m, and (2,) variances.
    """
    l11 = np.sqrt(cov_prior[0, 0])
    l21 = cov_prior[1, 0] / l11
    l22 = np.sqrt(cov_prior[1, 1] - l21 * l21)
    i11, i21, i22 = 1.0 / l11, -l21 / (l11 * l22), 1.0 / l22  # L^-1, lower triangular
    # M = L^-1 S L^-T
    s00, s01, s11 = cov_post[0, 0], 0.5 * (cov_post[0, 1] + cov_post[1, 0]), cov_post[1, 1]
    m00 = i11 * i11 * s00
    m01 = i11 * (i21 * s00 + i22 * s01)
    m11 = i21 * i21 * s00 + 2.0 * i21 * i22 * s01 + i22 * i22 * s11
    l1, l2, ang = _eig_sym2(m00, m01, m11)
    c, s = np.cos(ang), np.sin(ang)
    d0, d1 = p_prior[0] - mean_post[0], p_prior[1] - mean_post[1]
    for i in range(2):
        u0, u1 = (c, s) if i == 0 else (-s, c)
        lam = min(max(l1 if i == 0 else l2, _MIN_RATIO), _MAX_RATIO)
        r[i] = lam / (1.0 - lam)
        a[i, 0] = u0 * i11 + u1 * i21  # u' L^-1
        a[i, 1] = u1 * i22
        y[i] = (1.0 + r[i]) * (a[i, 0] * d0 + a[i, 1] * d1)


def _gaussian_weights(
    cloud: NDArray[np.float64], z: NDArray[np.float64], cov: NDArray[np.float64]
) -> NDArray[np.float64]:
    """Unnormalised ``N(z | x_n, cov)`` of each particle (eq. 15), scaled so the largest is 1;
    ``cov`` (2, 2) gets a floor of 1e-12 m^2 on its diagonal."""
    d = cloud - z
    inv = np.linalg.inv(cov + _MIN_VAR_M2 * np.eye(2))
    logw = -0.5 * np.einsum("ni,ij,nj->n", d, inv, d)
    return np.exp(logw - logw.max())
