"""Particle-filter fusion (seed 004): resampling, Gaussian sum, offset Rayleigh, the EKF feedback
and the walk."""

import numpy as np
import pytest

import footnav
from footnav import CompositionError
from footnav.estimators.ekf import EkfEstimator
from footnav.estimators.madgwick import MadgwickEstimator
from footnav.fusion.independent import IndependentFusion
from footnav.fusion.particle import ParticleFusion
from footnav.fusion.particle_cloud import (
    _weigh_and_resample,
    equivalent_measurement,
    gaussian_sum,
    offset_rayleigh,
    systematic_resample,
)

# a consumer-grade gyro (bias walk 5x the simulator's default) so that the feet drift apart
DRIFTY = {"gyr_bias_walk_radps2_sqrthz": 5e-5}


class _FixedU:
    """A generator whose one uniform draw is fixed: makes systematic resampling hand-computable."""

    def __init__(self, u):
        self.u = u

    def random(self):
        return self.u


# -- systematic resampling ---------------------------------------------------------------------


def test_systematic_resampling_hand_computed():
    w = np.array([0.1, 0.4, 0.0, 0.5])
    # points (u + k) / 4 in the cumulative weights [0.1, 0.5, 0.5, 1.0]
    # u = 0.5: 0.125, 0.375, 0.625, 0.875 -> particles 1, 1, 3, 3
    np.testing.assert_array_equal(systematic_resample(w, _FixedU(0.5)), [1, 1, 3, 3])
    # u = 0: 0, 0.25, 0.5, 0.75 -> 0, 1, 3 (0.5 is past particle 1's slice [0.1, 0.5)), 3
    np.testing.assert_array_equal(systematic_resample(w, _FixedU(0.0)), [0, 1, 3, 3])
    # unnormalised weights give the same draw
    np.testing.assert_array_equal(systematic_resample(10 * w, _FixedU(0.5)), [1, 1, 3, 3])


def test_systematic_resampling_copies_each_particle_within_one_of_n_w():
    rng = np.random.default_rng(3)
    for n in (5, 37, 1000):
        for _ in range(20):
            w = rng.random(n) ** 3
            counts = np.bincount(systematic_resample(w, rng), minlength=n)
            expected = n * w / w.sum()
            assert counts.sum() == n
            assert np.all(np.abs(counts - expected) < 1.0)


def test_compiled_weighing_and_resampling_equals_the_reference():
    rng = np.random.default_rng(5)
    cloud = rng.standard_normal((500, 2))
    z, lateral, var, u = np.array([0.3, -0.2]), np.array([0.6, 0.8]), 0.7, 0.37
    out, logw, mean, cov = np.empty((500, 2)), np.empty(500), np.empty(2), np.empty((2, 2))
    _weigh_and_resample(cloud, z, lateral, var, u, out, logw, mean, cov)
    d = (cloud - z) @ lateral
    ref = cloud[systematic_resample(np.exp(-0.5 * d * d / var), _FixedU(u))]
    np.testing.assert_array_equal(out, ref)
    np.testing.assert_allclose(mean, ref.mean(axis=0), atol=1e-14)
    np.testing.assert_allclose(cov, np.cov(ref.T, bias=True), atol=1e-12)


# -- Gaussian sum (eq. 13-14) --------------------------------------------------------------------


def test_gaussian_sum_hand_computed():
    means = np.array([[0.0, 0.0], [2.0, 0.0]])
    covs = np.array([np.eye(2), 3 * np.eye(2)])
    mu, cov = gaussian_sum(means, covs, np.array([1.0, 1.0]))
    np.testing.assert_allclose(mu, [1.0, 0.0])
    # mean of the covariances (2 I) plus the spread of the means (1 along x)
    np.testing.assert_allclose(cov, [[3.0, 0.0], [0.0, 2.0]])
    # weights 3:1: mu = 0.25 * 2 = 0.5; 0.75 I + 0.25 * 3 I = 1.5 I; spread 0.75 * 0.5^2 + 0.25 * 1.5^2 = 0.75
    mu, cov = gaussian_sum(means, covs, np.array([3.0, 1.0]))
    np.testing.assert_allclose(mu, [0.5, 0.0])
    np.testing.assert_allclose(cov, [[2.25, 0.0], [0.0, 1.5]])


def test_gaussian_sum_matches_samples_of_the_mixture():
    rng = np.random.default_rng(1)
    means = np.array([[0.5, -1.0], [2.0, 0.3]])
    covs = np.array([[[0.2, 0.05], [0.05, 0.1]], [[0.4, -0.1], [-0.1, 0.3]]])
    weights = np.array([0.3, 0.7])
    pick = rng.random(400_000) < weights[0]
    draws = [rng.multivariate_normal(m, c, len(pick)) for m, c in zip(means, covs)]
    x = np.where(pick[:, None], draws[0], draws[1])
    mu, cov = gaussian_sum(means, covs, weights)
    np.testing.assert_allclose(mu, x.mean(axis=0), atol=5e-3)
    np.testing.assert_allclose(cov, np.cov(x.T), atol=5e-3)


# -- offset Rayleigh (eq. 1, 12) -----------------------------------------------------------------


def test_offset_rayleigh_moments_match_the_distribution():
    sigma = 0.2
    x = offset_rayleigh(sigma, 400_000, np.random.default_rng(0))
    # Rayleigh(sigma): mean sigma sqrt(pi/2), variance (4 - pi)/2 sigma^2, median sigma sqrt(2 ln 2),
    # skewness 2 sqrt(pi) (pi - 3) / (4 - pi)^1.5; offset by the mean
    assert abs(x.mean()) < 3 * sigma * 0.66 / np.sqrt(len(x))
    assert x.var() == pytest.approx((4 - np.pi) / 2 * sigma**2, rel=0.01)
    assert np.median(x) == pytest.approx(sigma * (np.sqrt(2 * np.log(2)) - np.sqrt(np.pi / 2)), abs=0.002)
    skew = np.mean(x**3) / x.std() ** 3
    assert skew == pytest.approx(2 * np.sqrt(np.pi) * (np.pi - 3) / (4 - np.pi) ** 1.5, abs=0.03)


# -- the EKF follows the PF (Jeffrey's rule) ------------------------------------------------------


def _kalman(mu, cov, h, y, r):
    """Reference update: y = H dx + noise with dx = estimate - truth."""
    s = h @ cov @ h.T + np.diag(r)
    k = cov @ h.T @ np.linalg.inv(s)
    return mu - k @ y, cov - k @ h @ cov


def _random_prior(rng, n=6):
    m = rng.standard_normal((n, n))
    return rng.standard_normal(n), m @ m.T + 0.1 * np.eye(n)


@pytest.mark.parametrize("seed", range(4))
def test_equivalent_measurement_replaces_the_position_marginal(seed):
    rng = np.random.default_rng(seed)
    mu, cov = _random_prior(rng)
    ip = [2, 3]  # the horizontal position within the state
    sel = np.eye(6)[ip]
    p_pp = cov[np.ix_(ip, ip)]
    m_post = mu[ip] + rng.standard_normal(2)
    b = rng.standard_normal((2, 2))
    c_post = 0.5 * p_pp + 0.05 * b @ b.T  # tighter than the prior, rotated
    assert np.all(np.linalg.eigvalsh(p_pp - c_post) > 0)
    a, y, r = np.empty((2, 2)), np.empty(2), np.empty(2)
    equivalent_measurement(mu[ip], p_pp, m_post, c_post, a, y, r)
    mu_new, cov_new = _kalman(mu, cov, a @ sel, y, r)
    # Jeffrey's rule: p ~ N(m_post, c_post), the rest by its regression on p
    g = cov[:, ip] @ np.linalg.inv(p_pp)
    np.testing.assert_allclose(mu_new, mu + g @ (m_post - mu[ip]), atol=1e-9)
    np.testing.assert_allclose(cov_new, cov - g @ (p_pp - c_post) @ g.T, atol=1e-9)
    np.testing.assert_allclose(cov_new[np.ix_(ip, ip)], c_post, atol=1e-9)


def test_equivalent_measurement_moves_only_the_mean_where_the_cloud_is_wider():
    rng = np.random.default_rng(7)
    mu, cov = _random_prior(rng)
    ip = [2, 3]
    p_pp = cov[np.ix_(ip, ip)]
    m_post = mu[ip] + np.array([0.3, -0.4])
    a, y, r = np.empty((2, 2)), np.empty(2), np.empty(2)
    equivalent_measurement(mu[ip], p_pp, m_post, 2.0 * p_pp, a, y, r)
    mu_new, cov_new = _kalman(mu, cov, a @ np.eye(6)[ip], y, r)
    np.testing.assert_allclose(mu_new[ip], m_post, atol=1e-9)
    np.testing.assert_allclose(cov_new, cov, rtol=1e-5, atol=1e-9)


# -- the walk --------------------------------------------------------------------------------------


def _fuse(fusion, rec, estimator=None):
    det = footnav.make_detector("threshold")
    return fusion.fuse(estimator or EkfEstimator(), rec.left, det.detect(rec.left), rec.right, det.detect(rec.right))


def _es_ep(res, rec):
    es = float(np.linalg.norm(res.left.position[-1, :2] - res.right.position[-1, :2]))
    pairs = ((res.left, rec.truth_left), (res.right, rec.truth_right))
    ep = [float(np.linalg.norm(tr.position[-1, :2] - truth.position[-1, :2])) for tr, truth in pairs]
    return es, ep


@pytest.mark.parametrize(
    "scenario, opts",
    [
        ("straight", {"distance_m": 100.0}),
        ("rectangle", {"width_m": 105.0, "height_m": 68.0, "direction": "cw"}),
        ("rectangle", {"width_m": 105.0, "height_m": 68.0, "direction": "ccw"}),
    ],
)
def test_particle_fusion_keeps_the_feet_together_and_the_walk_on_course(scenario, opts):
    # 20 seeds: E_s drops in every seed, but E_p only on average. The feet's heading drifts are
    # independent random walks here, not seed 004's symmetric drift, so the fused feet walk on
    # their mean: E_p ~ 1/sqrt(2) of independent's in expectation, either way in any one seed
    # (with 2 seeds the comparison is a coin toss; with 20, about 1.5-3 standard errors).
    es_i, es_p, ep_i, ep_p = [], [], [], []
    for seed in range(20):
        rec = footnav.simulate(scenario, seed=seed, **DRIFTY, **opts)
        for fusion, es, ep in ((IndependentFusion(), es_i, ep_i), (ParticleFusion(), es_p, ep_p)):
            res = _fuse(fusion, rec)
            s, p = _es_ep(res, rec)
            es.append(s)
            ep.extend(p)
    err_i, err_p = np.abs(np.array(es_i) - 0.2), np.abs(np.array(es_p) - 0.2)
    # measured, 20 seeds (straight / cw / ccw): E_s 0.78 -> 0.21, 5.90 -> 0.21, 5.93 -> 0.22 m;
    # |E_s - 0.2| 0.61 -> 0.014, 5.70 -> 0.021, 5.73 -> 0.021 m; E_p 0.62 -> 0.48, 4.68 -> 3.74,
    # 4.73 -> 3.47 m
    assert np.mean(err_p) * 10 <= np.mean(err_i)
    assert np.max(err_p) < 0.1  # every seed: the feet end about step_width_m apart
    # the feet end 0.2 m apart, which bounds E_s from below: 5x only where independent's is large
    assert np.mean(es_p) * (5 if scenario == "rectangle" else 3) <= np.mean(es_i)
    assert np.mean(ep_p) < 0.9 * np.mean(ep_i)


def test_same_seed_same_output_different_seed_different():
    rec = footnav.simulate("straight", seed=1, distance_m=20.0, **DRIFTY)
    a, b = _fuse(ParticleFusion(seed=4), rec), _fuse(ParticleFusion(seed=4), rec)
    c = _fuse(ParticleFusion(seed=5), rec)
    for foot in ("left", "right"):
        np.testing.assert_array_equal(getattr(a, foot).position, getattr(b, foot).position)
        np.testing.assert_array_equal(getattr(a, foot).quaternion, getattr(b, foot).quaternion)
    np.testing.assert_array_equal(a.path.position, b.path.position)
    assert not np.array_equal(a.left.position, c.left.position)
    assert not np.array_equal(a.right.position, c.right.position)
    assert a.meta["pf_updates"] > 20


def test_one_foot_is_a_composition_error():
    rec = footnav.simulate("straight", distance_m=5.0)
    stance = footnav.make_detector("threshold").detect(rec.left)
    with pytest.raises(CompositionError, match="'particle' needs both feet"):
        ParticleFusion().fuse(EkfEstimator(), rec.left, stance)
    with pytest.raises(CompositionError, match="'particle' needs both feet"):
        ParticleFusion().fuse(EkfEstimator(), rec.left, stance, rec.right, None)


def test_an_estimator_without_a_stepable_filter_is_a_composition_error():
    with pytest.raises(CompositionError, match="step-able filter"):
        _fuse(ParticleFusion(), footnav.simulate("straight", distance_m=5.0), estimator=MadgwickEstimator())


def test_bad_parameters_are_named():
    rec = footnav.simulate("straight", distance_m=5.0)
    for params, name in (
        ({"n_particles": 1}, "n_particles"),
        ({"n_particles": 10.0}, "n_particles"),
        ({"sigma_sys_m": -0.1}, "sigma_sys_m"),
        ({"step_width_m": -0.2}, "step_width_m"),
        ({"seed": 1.5}, "seed"),
    ):
        with pytest.raises(footnav.InvalidParameterError, match=name):
            _fuse(ParticleFusion(**params), rec)
