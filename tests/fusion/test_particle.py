"""Particle-filter fusion (seed 004): resampling, Gaussian sum, offset Rayleigh, and the walk."""

import numpy as np
import pytest

import footnav
from footnav.estimators.ekf import EkfEstimator
from footnav.fusion.independent import IndependentFusion
from footnav.fusion.particle import ParticleFusion, gaussian_sum, offset_rayleigh, systematic_resample
from footnav.testing import FusionContract

DRIFTY = {"gyr_bias_walk_radps2_sqrthz": 1e-4}


class TestParticleContract(FusionContract):
    component = ParticleFusion


class _FixedU:
    """A generator whose one uniform draw is fixed: makes systematic resampling hand-computable."""

    def __init__(self, u):
        self.u = u

    def random(self):
        return self.u


def test_systematic_resampling_hand_computed():
    w = np.array([0.1, 0.4, 0.0, 0.5])
    # points (0.5 + k) / 4 = 0.125, 0.375, 0.625, 0.875 in cumulative [0.1, 0.5, 0.5, 1.0]
    np.testing.assert_array_equal(systematic_resample(w, _FixedU(0.5)), [1, 1, 3, 3])
    np.testing.assert_array_equal(systematic_resample(w, _FixedU(0.0)), [0, 1, 3, 3])


def test_systematic_resampling_copies_each_particle_floor_or_ceil_of_n_w():
    rng = np.random.default_rng(3)
    for _ in range(50):
        w = rng.random(37) ** 3
        counts = np.bincount(systematic_resample(w, rng), minlength=37)
        expected = 37 * w / w.sum()
        assert np.all(counts >= np.floor(expected) - 1e-9) and np.all(counts <= np.ceil(expected) + 1e-9)


def test_compiled_weighing_and_resampling_equals_the_reference():
    from footnav.fusion.particle import _weigh_and_resample

    rng = np.random.default_rng(5)
    cloud = rng.standard_normal((500, 2))
    z, lateral, var, u = np.array([0.3, -0.2]), np.array([0.6, 0.8]), 0.7, 0.37
    out, mean, cov = np.empty((500, 2)), np.empty(2), np.empty((2, 2))
    _weigh_and_resample(cloud, z, lateral, var, u, out, mean, cov)
    d = (cloud - z) @ lateral
    ref = cloud[systematic_resample(np.exp(-0.5 * d * d / var), _FixedU(u))]
    np.testing.assert_array_equal(out, ref)
    np.testing.assert_allclose(mean, ref.mean(axis=0))
    np.testing.assert_allclose(cov, np.cov(ref.T, bias=True), atol=1e-12)


def test_gaussian_sum_hand_computed():
    means = np.array([[0.0, 0.0], [2.0, 0.0]])
    covs = np.array([np.eye(2), 3 * np.eye(2)])
    mu, cov = gaussian_sum(means, covs, np.array([1.0, 1.0]))
    np.testing.assert_allclose(mu, [1.0, 0.0])
    # mean of the covariances (2 I) plus the spread of the means (1 along x)
    np.testing.assert_allclose(cov, [[3.0, 0.0], [0.0, 2.0]])


def test_offset_rayleigh_moments():
    rng = np.random.default_rng(0)
    x = offset_rayleigh(0.2, 200_000, rng)
    assert abs(x.mean()) < 0.002
    assert x.var() == pytest.approx((2 - np.pi / 2) * 0.04, rel=0.02)
    assert (x < 0).mean() > 0.5  # skewed: the mode and the median lie below the zero mean


def _fuse(fusion, rec):
    det = footnav.make_detector("threshold")
    return fusion.fuse(EkfEstimator(), rec.left, det.detect(rec.left), rec.right, det.detect(rec.right))


@pytest.mark.parametrize(
    "scenario, opts",
    [("straight", {"distance_m": 100.0}), ("rectangle", {"width_m": 105.0, "height_m": 68.0, "direction": "cw"}),
     ("rectangle", {"width_m": 105.0, "height_m": 68.0, "direction": "ccw"})],
)
def test_particle_fusion_keeps_the_feet_together_and_the_walk_on_course(scenario, opts):
    es_i, es_p, ep_i, ep_p = [], [], [], []
    for seed in range(5):
        rec = footnav.simulate(scenario, seed=seed, **DRIFTY, **opts)
        for fusion, es, ep in ((IndependentFusion(), es_i, ep_i), (ParticleFusion(), es_p, ep_p)):
            res = _fuse(fusion, rec)
            es.append(np.linalg.norm(res.left.position[-1, :2] - res.right.position[-1, :2]))
            ep += [np.linalg.norm(tr.position[-1, :2] - t.position[-1, :2]) for tr, t in ((res.left, rec.truth_left), (res.right, rec.truth_right))]
    # measured (5 seeds): E_s 1.45 -> 0.07 m straight, 13.4-14.5 -> 0.27 m rectangles;
    # E_p 1.16 -> 1.10 m straight, 9.2-9.8 -> 6.2-6.4 m rectangles
    assert np.mean(es_p) * 5 <= np.mean(es_i)
    assert np.mean(ep_p) < np.mean(ep_i)


def test_same_seed_same_output_different_seed_different():
    rec = footnav.simulate("straight", seed=1, distance_m=20.0)
    a, b = _fuse(ParticleFusion(seed=4), rec), _fuse(ParticleFusion(seed=4), rec)
    c = _fuse(ParticleFusion(seed=5), rec)
    np.testing.assert_array_equal(a.left.position, b.left.position)
    assert not np.array_equal(a.left.position, c.left.position)
    assert a.meta["pf_updates"] > 20


def test_bad_parameters_are_named():
    rec = footnav.simulate("straight", distance_m=5.0)
    with pytest.raises(footnav.InvalidParameterError, match="n_particles"):
        _fuse(ParticleFusion(n_particles=1), rec)
    with pytest.raises(footnav.InvalidParameterError, match="sigma_sys_m"):
        _fuse(ParticleFusion(sigma_sys_m=-0.1), rec)
