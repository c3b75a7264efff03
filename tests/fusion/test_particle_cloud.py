"""The particle cloud's weights (footnav/fusion/particle_cloud.py, paper mode: eq. 15).

The mutants change the spread of a cloud, not its mean; the spread is checked against what the
paper's equations give for it (the Gaussian product).
"""

from __future__ import annotations

import numpy as np
from scipy.stats import multivariate_normal

from footnav.fusion.particle_cloud import _gaussian_weights, systematic_resample


# mutant: particle-gaussian-half
# particle-gaussian-half: the weight of particle x_n is N(z | x_n, Sigma) (eq. 15), up to a common
# factor; checked against scipy's density, ratios to the largest weight.
def test_gaussian_weights_are_the_normal_density():
    rng = np.random.default_rng(17)
    cloud = rng.normal(0.0, 0.3, (50, 2))
    z = np.array([0.1, -0.2])
    cov = np.array([[0.04, 0.01], [0.01, 0.09]])
    pdf = multivariate_normal(mean=z, cov=cov).pdf(cloud)
    np.testing.assert_allclose(_gaussian_weights(cloud, z, cov), pdf / pdf.max(), rtol=1e-9)


# mutant: particle-gaussian-half
# particle-gaussian-half: weighing a N(0, P) cloud by N(z | x, S) and resampling gives the
# Gaussian product's spread (P^-1 + S^-1)^-1 (the posterior of the PF update, eq. 15-16);
# with the exponent doubled the spread is (P^-1 + 2 S^-1)^-1. P = diag(0.09, 0.04),
# S = diag(0.09, 0.04) m^2: posterior variances 0.045, 0.020; mutant 0.030, 0.0133.
# 40,000 particles: the sample variance's relative standard error is about 1 %, tolerance 6 %.
def test_weighted_and_resampled_cloud_has_the_product_spread():
    rng = np.random.default_rng(4)
    p = np.diag([0.09, 0.04])
    s = np.diag([0.09, 0.04])
    cloud = rng.multivariate_normal([0.0, 0.0], p, 40_000)
    z = np.array([0.0, 0.0])
    out = cloud[systematic_resample(_gaussian_weights(cloud, z, s), rng)]
    expected = np.linalg.inv(np.linalg.inv(p) + np.linalg.inv(s))
    np.testing.assert_allclose(np.cov(out.T).diagonal(), expected.diagonal(), rtol=0.06)
