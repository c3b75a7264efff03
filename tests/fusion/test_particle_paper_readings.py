"""ParticleFusion(mode="paper"), issue 36: the readings of Lee, Cho & Park (2022) eq. 12 and 15
(``drift_mean``, ``likelihood_cov``, ``likelihood_axes``) by hand, ``sigma_sys_m=0`` against the
simulator's truth, and the paper's Tables 2-3 against independent feet with the paper's drift."""

import math
import warnings
from types import SimpleNamespace

import numpy as np
import pytest

import footnav
from footnav.analysis import metrics
from footnav.estimators.ekf import EkfEstimator
from footnav.fusion.independent import IndependentFusion
from footnav.fusion.particle import ParticleFusion
from footnav.fusion.particle_ekf import drift_scales

#: The paper's experiment as docs/make_papers.py rebuilds it: the MTw of Table 1 (gyro 0.05
#: deg/s/sqrt(Hz), acc 0.003 m/s^2/sqrt(Hz)), its 20 deg/h bias stability as a bias walk over the
#: 3-min walk (9.7e-5 rad/s / sqrt(180 s)), 5 s standstill, and the symmetric drift of Sec. 2.1
#: (+b on the left foot's yaw rate, -b on the right's) that gives the standalone errors of
#: Tables 2-3 (0.86 / 0.85 m total on the straight / square against the paper's 0.75 / 0.89 m).
PAPER_DRIFT = {
    "standstill_s": 5.0,
    "gyr_noise_density_radps_sqrthz": math.radians(0.05),
    "acc_noise_density_mps2_sqrthz": 3e-3,
    "gyr_bias_walk_radps2_sqrthz": 7e-6,
    "mirrored_yaw_rate_radps": 6e-4,
}
#: The paper mode of docs/papers.md: sigma_sys is not given by the paper (fitted to Fig. 2).
PAPER_MODE = {"mode": "paper", "sigma_sys_m": 0.1}
NOISE_FREE = {
    k: 0.0
    for k in (
        "gyr_noise_density_radps_sqrthz",
        "acc_noise_density_mps2_sqrthz",
        "gyr_bias_std_radps",
        "acc_bias_std_mps2",
        "gyr_bias_walk_radps2_sqrthz",
        "acc_bias_walk_mps3_sqrthz",
    )
}
SIDE_M = 93.0 / 4


def _fuse(fusion, rec):
    det = footnav.make_detector("threshold")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return fusion.fuse(
            EkfEstimator(smoother="none"), rec.left, det.detect(rec.left), rec.right, det.detect(rec.right)
        )


def _errors(res, rec):
    """Per foot: (mean waypoint error, final error), m, each track aligned on its first five steps."""
    out = []
    for traj, truth in ((res.left, rec.truth_left), (res.right, rec.truth_right)):
        aligned = metrics.align_on_first_steps(traj.position, truth.position, truth.events["heel_strike"]).aligned
        wp = truth.meta["waypoints_m"]
        out.append(
            (
                metrics.waypoint_errors(aligned, truth.position, wp).mean_m,
                float(np.linalg.norm(aligned[-1, :2] - truth.position[-1, :2])),
            )
        )
    return np.array(out)


# -- hand-computed cases ---------------------------------------------------------------------------


@pytest.mark.parametrize("offset", [0.05, -0.3, 1.0])
def test_no_rayleigh_scale_no_drift_whatever_the_offset(offset):
    mask = np.ones(50, bool)
    mask[10:30] = False
    scale, off = drift_scales(mask, 0.0, offset)
    assert not scale.any() and not off.any()


def _foot(cloud):
    # _paper_weights reads the cloud and the attitude only; identity: heading along +x
    return SimpleNamespace(cloud=np.asarray(cloud, float), q=np.array([[1.0, 0.0, 0.0, 0.0]]))


def test_likelihood_own_against_fused_covariance_by_hand():
    cloud = [[0.0, -1.0], [0.0, 0.0], [0.0, 1.0]]  # own covariance diag(0, 2/3)
    own, fused = np.diag([0.0, 2.0 / 3.0]), np.diag([0.0, 6.0])
    z = np.array([0.0, 1.0])
    for cov_name, var in (("own", 2.0 / 3.0), ("fused", 6.0)):
        fusion = ParticleFusion(mode="paper", likelihood_cov=cov_name, step_width_m=0.0)
        w = fusion._paper_weights(_foot(cloud), z, own, fused, 0.0, 0)
        d = np.array([-2.0, -1.0, 0.0])  # lateral offsets of the particles from z
        np.testing.assert_allclose(w, np.exp(-0.5 * d**2 / var))


def test_lateral_likelihood_ignores_the_walking_direction_and_shifts_by_half_the_step_width():
    cloud = [[0.0, 0.1], [3.0, 0.1], [0.0, 0.0]]
    cov = np.eye(2) * 0.01
    left = ParticleFusion(mode="paper", step_width_m=0.2)  # left foot: the pedestrian + 0.1 m to its left
    w = left._paper_weights(_foot(cloud), np.zeros(2), cov, cov, 0.0, 0)
    np.testing.assert_allclose(w, [1.0, 1.0, math.exp(-0.5 * 0.01 / 0.01)])
    # 2-D as printed: the particle 3 m ahead weighs exp(-450) relative to the one at the target
    w2 = ParticleFusion(mode="paper", likelihood_axes="2d")._paper_weights(_foot(cloud), np.zeros(2), cov, cov, 0.0, 0)
    assert w2[0] == 1.0 and w2[1] < 1e-100
    # the right foot's target is 0.1 m to the right: the particle at 0 is the closer
    w_r = left._paper_weights(_foot([[0.0, -0.1], [0.0, 0.0]]), np.zeros(2), cov, cov, 0.0, 1)
    np.testing.assert_allclose(w_r, [1.0, math.exp(-0.5)])


@pytest.mark.parametrize(
    "name, value", [("likelihood_cov", "mixture"), ("likelihood_axes", "3d"), ("drift_mean", "mean")]
)
def test_unknown_readings_are_refused_by_name(name, value):
    with pytest.raises(footnav.InvalidParameterError, match=name):
        ParticleFusion(mode="paper", **{name: value}).validate_params()


# -- against the simulator's truth -------------------------------------------------------------


@pytest.mark.parametrize(
    "drift",
    [
        {},
        {"drift_mean": "offset"},
        {"drift_mean": "offset", "drift_offset_m": -0.5},
        {"drift_mean": "offset", "drift_offset_m": 1.0},
    ],
)
def test_no_rayleigh_scale_keeps_the_feet_on_their_lateral_truth(drift):
    # issue 36: with sigma_sys_m=0 the default offset alone pushed each foot 5 cm per step
    # (2.3 / 2.6 m off after 70 m); noise-free sensors, so any lateral error is the fusion's
    rec = footnav.simulate("straight", seed=0, distance_m=70.0, **NOISE_FREE)
    res = _fuse(ParticleFusion(mode="paper", sigma_sys_m=0.0, **drift), rec)
    for traj, truth in ((res.left, rec.truth_left), (res.right, rec.truth_right)):
        mid = (traj.steps[:, 0] + traj.steps[:, 1]) // 2
        assert np.abs(traj.position[mid, 1] - truth.position[mid, 1]).max() < 0.2


def test_paper_mode_on_the_papers_square_against_independent_feet():
    # Table 3: total waypoint error over both feet 0.89 -> 0.315 m (-65 %); issue 36 asks for
    # at least 40 %. 3 laps, 6 walks as in the paper (measured, 10 seeds: 0.85 -> 0.42 m, -51 %)
    ind, paper = [], []
    for seed in range(6):
        segments = [(SIDE_M / 2, 90.0)] + [(SIDE_M, 90.0)] * 11 + [(SIDE_M / 2, 0.0)]
        rec = footnav.simulate("path", seed=seed, segments=segments, **PAPER_DRIFT)
        ind.append(_errors(_fuse(IndependentFusion(), rec), rec)[:, 0])
        paper.append(_errors(_fuse(ParticleFusion(**PAPER_MODE), rec), rec)[:, 0])
    assert np.mean(paper) < 0.6 * np.mean(ind)


def test_paper_mode_on_the_papers_straight_walk_against_independent_feet():
    # Table 2: final error, both feet, 0.745 -> 0.515 m (-31 %); issue 36 asks for at least 20 %
    # (measured, 10 seeds: 0.86 -> 0.39 m, -55 %)
    ind, paper = [], []
    for seed in range(6):
        rec = footnav.simulate("straight", seed=seed, distance_m=70.0, **PAPER_DRIFT)
        ind.append(_errors(_fuse(IndependentFusion(), rec), rec)[:, 1])
        paper.append(_errors(_fuse(ParticleFusion(**PAPER_MODE), rec), rec)[:, 1])
    assert np.mean(paper) < 0.8 * np.mean(ind)
