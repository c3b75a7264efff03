"""Tests for the DTW and particle fusions' surviving mutants (tools/mutate.py, issue 17).

DTW: the simulated feet normally start side by side with parallel first strides and the
mid-swing offset is 0, so neither the sign of the heading mismatch nor the side of the lateral
offset can matter. Here the walk starts into a turn (the two feet's first strides point in
different directions: the DTW heading search finds a non-zero mismatch) and the mid-swing
offset is the simulated step width; both are checked against the simulator's truth.

Particles: the mutants change the spread of a cloud, not its mean; the spread is checked
against what the paper's equations give for it (Rayleigh moments, the Gaussian product).

``particle-other-growth`` mutated the other foot's cloud covariance, which nothing downstream
read (the Gaussian sum's mean does not depend on the covariances): that dead code is gone from
``_fuse_footnav``, and the mutant with it.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
from scipy.stats import multivariate_normal

import footnav
from footnav.fusion.particle_cloud import _gaussian_weights, systematic_resample
from footnav.fusion.particle_ekf import N_STATES, PaperFoot

G = 9.80665  # m/s^2, written out


def _first_stride_heading(position, stance):
    """Direction (rad) of a foot's first stride: from its start to its first landing."""
    landing = np.flatnonzero(np.diff(stance.astype(int)) == 1)[0] + 1
    d = position[landing, :2] - position[0, :2]
    return math.atan2(d[1], d[0])


def _run(rec, **fusion_params):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return footnav.make_pipeline("glrt", "ekf", "dtw", fusion_params=fusion_params).run(rec.left, rec.right)


# -- DTW fusion ----------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def turning_start():
    """Standing, then straight into a 90 deg left turn (radius 1.5 m), then 5 m straight: the left
    foot's first stride points 0.446 rad left of +x, the right foot's 0.223 rad (truth)."""
    rec = footnav.simulate("path", seed=1, segments=[(0.0, 90.0), (5.0, 0.0)], standstill_s=1.0)
    return rec, _run(rec)


# dtw-fusion-heading-sign: the DTW mismatch turns the right foot's start; the wrong sign turns it
# by twice the mismatch the other way. Measured (seed 1): the right foot's first stride points
# -0.180 rad from the left's in the fused result (truth -0.223; mutant -0.044; the rest of the
# difference is the fusion's start geometry, feet side by side across the left's first stride).
def test_dtw_right_foot_starts_with_the_true_relative_heading(turning_start):
    rec, res = turning_start
    truth = _first_stride_heading(rec.truth_right.position, rec.truth_right.stance) - _first_stride_heading(
        rec.truth_left.position, rec.truth_left.stance
    )
    est = _first_stride_heading(res.right.position, rec.truth_right.stance) - _first_stride_heading(
        res.left.position, rec.truth_left.stance
    )
    assert abs(truth) > 0.2  # the case the default walks never make
    assert abs(est - truth) < 0.09  # measured 0.043; the mutant 0.179


# dtw-fusion-heading-sign: end positions in the fused frame (x the left foot's first stride,
# origin between the feet) against the truth put in that frame. Measured (seed 1): left 0.007 m,
# right 0.234 m; the mutant 0.83 m and 1.95 m.
def test_dtw_turning_start_ends_where_the_truth_ends(turning_start):
    rec, res = turning_start
    hl = _first_stride_heading(rec.truth_left.position, rec.truth_left.stance)
    rot = np.array([[math.cos(hl), math.sin(hl)], [-math.sin(hl), math.cos(hl)]])  # turns by -hl
    origin = 0.5 * (rec.truth_left.position[0, :2] + rec.truth_right.position[0, :2])
    for est, truth in ((res.left, rec.truth_left), (res.right, rec.truth_right)):
        end_truth = rot @ (truth.position[-1, :2] - origin)
        assert np.linalg.norm(est.position[-1, :2] - end_truth) < 0.4


# dtw-fusion-offset-side: with lateral_offset_m = the simulated step width (0.2 m) the mid-swing
# ties hold the moving foot 0.2 m to its own side of the standing one; the wrong side pulls the
# feet across each other. Straight 4 m walk, both feet end side by side: the left foot 0.2 m to
# the left (+y) of the right (truth). Measured (seeds 1, 2): fused separation y 0.200 / 0.201 m;
# mutant -0.236 m.
@pytest.mark.parametrize("seed", [1, 2])
def test_dtw_lateral_offset_keeps_each_foot_on_its_side(seed):
    rec = footnav.simulate("path", seed=seed, segments=[(4.0, 0.0)], standstill_s=1.0)
    res = _run(rec, lateral_offset_m=0.2, midswing_std_m=0.05)
    truth_sep = rec.truth_left.position[-1, :2] - rec.truth_right.position[-1, :2]
    est_sep = res.left.position[-1, :2] - res.right.position[-1, :2]
    np.testing.assert_allclose(truth_sep, [0.0, 0.2], atol=1e-9)
    assert abs(est_sep[1] - truth_sep[1]) < 0.05
    # at every stance of both feet, the left foot is to the left of the right one
    both = rec.truth_left.stance & rec.truth_right.stance
    assert np.all(res.left.position[both, 1] - res.right.position[both, 1] > 0.1)


# -- particle fusion, paper mode: the weights of eq. 15 --------------------------------------------


# particle-gaussian-half: the weight of particle x_n is N(z | x_n, Sigma) (eq. 15), up to a common
# factor; checked against scipy's density, ratios to the largest weight.
def test_gaussian_weights_are_the_normal_density():
    rng = np.random.default_rng(17)
    cloud = rng.normal(0.0, 0.3, (50, 2))
    z = np.array([0.1, -0.2])
    cov = np.array([[0.04, 0.01], [0.01, 0.09]])
    pdf = multivariate_normal(mean=z, cov=cov).pdf(cloud)
    np.testing.assert_allclose(_gaussian_weights(cloud, z, cov), pdf / pdf.max(), rtol=1e-9)


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


# -- particle fusion, paper mode: the lateral drift of eq. 12 ----------------------------------------


def _drift_only_foot(yaw, side, sigma, offset, n_particles, seed):
    """A PaperFoot that stands still (exact gravity, no rotation) with its sensor turned ``yaw``
    about the vertical, while its mask says it moves for 50 samples: no EKF noise, so the cloud
    moves by the drift of eq. 12 alone. The per-sample scale and offset are written from the
    docstring of drift_scales: s = sigma / sqrt(M), o = s sqrt(pi/2) - (sigma sqrt(pi/2) - offset) / M."""
    rate, m = 100.0, 50
    mask = np.r_[np.ones(20, bool), np.zeros(m, bool), np.ones(20, bool)]
    n = len(mask)
    t = np.arange(n) / rate
    acc = np.tile([0.0, 0.0, G], (n, 1))
    gyr = np.zeros((n, 3))
    scale, off = np.zeros(n), np.zeros(n)
    s = sigma / math.sqrt(m)
    scale[~mask] = s
    off[~mask] = s * math.sqrt(math.pi / 2) - (sigma * math.sqrt(math.pi / 2) - offset) / m
    q0 = np.array([math.cos(yaw / 2), 0.0, 0.0, math.sin(yaw / 2)])
    p0 = np.zeros(3)
    foot = PaperFoot(
        t,
        acc,
        gyr,
        mask,
        19,
        q0,
        p0,
        np.zeros(3),
        np.zeros(N_STATES),
        np.array([0.0, 0.0, 0.0, 1e-4]),
        np.zeros((n_particles, 2)),
        side,
        scale,
        off,
    )
    foot.run_until(n - 1, np.random.default_rng(seed))
    return foot.cloud


# particle-ekf-lateral-transposed: the drift moves each particle along the body's +y axis in nav,
# C_b^n [0, f', 0]': for a level sensor turned by yaw psi that is (-sin psi, cos psi). One step's
# drift is Rayleigh(sigma) - offset (Sec. 2.2): mean sigma sqrt(pi/2) - offset, variance
# (2 - pi/2) sigma^2, so the cloud's mean is that mean times side (-sin psi, cos psi) and its
# covariance (2 - pi/2) sigma^2 l l'. With the transposed C the x-component flips sign (0.11 m
# off in the mean at psi = 60 deg; the covariance's xy term changes sign).
@pytest.mark.parametrize("side", [1.0, -1.0])
def test_paper_drift_is_along_the_body_y_axis(side):
    yaw, sigma, offset, n = math.radians(60.0), 0.05, 0.0, 20_000
    cloud = _drift_only_foot(yaw, side, sigma, offset, n, seed=11)
    lat = side * np.array([-math.sin(yaw), math.cos(yaw)])
    mean_step = sigma * math.sqrt(math.pi / 2) - offset
    var_step = (2.0 - math.pi / 2) * sigma**2
    # the mean's standard error is sqrt(var_step / n) = 2.3e-4 m: 5 of them
    np.testing.assert_allclose(cloud.mean(axis=0), mean_step * lat, atol=5 * math.sqrt(var_step / n))
    # the spread: all along lat (rank one), variance var_step within 5 % (sample error about 1 %)
    cov = np.cov(cloud.T)
    np.testing.assert_allclose(cov, var_step * np.outer(lat, lat), atol=0.05 * var_step)
    across = cloud @ np.array([lat[1], -lat[0]])
    assert np.abs(across).max() < 1e-12  # nothing across the body's y axis
