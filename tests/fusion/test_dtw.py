"""DTW fusion (seed 002 Alg. 2): heading mismatch by DTW, mid-swing ties, averaged path."""

import numpy as np
import pytest

import footnav
from footnav.estimators.ekf import EkfEstimator
from footnav.fusion.dtw import DtwFusion, _rotated, heading_mismatch, timeless_average
from footnav.fusion.independent import IndependentFusion
from footnav.testing import FusionContract

DRIFTY = {"gyr_bias_walk_radps2_sqrthz": 1e-4}


class TestDtwContract(FusionContract):
    component = DtwFusion


def _fuse(fusion, rec):
    det = footnav.make_detector("threshold")
    return fusion.fuse(EkfEstimator(), rec.left, det.detect(rec.left), rec.right, det.detect(rec.right))


@pytest.mark.parametrize("angle", [-2.0, -0.4, 0.3, 1.5, 3.0])
def test_heading_mismatch_recovers_a_known_rotation(angle):
    rec = footnav.simulate("rectangle", seed=0, width_m=20.0, height_m=10.0, noise=False)
    a = rec.truth_left.position[::10, :2]
    b = _rotated(rec.truth_right.position[::10, :2] - rec.truth_right.position[0, :2], -angle)
    found, dist = heading_mismatch(a, b, band=20)
    # measured 0.014-0.016 rad off: the feet's tracks are 0.2 m apart, so rotating one about its own
    # start cannot lay it exactly onto the other
    assert abs((found - angle + np.pi) % (2 * np.pi) - np.pi) < 0.03  # rad
    assert dist < 0.3  # m: the feet walk 0.2 m apart


def test_timeless_average_lies_on_the_centre_line():
    rec = footnav.simulate("rectangle", seed=0, width_m=20.0, height_m=10.0, noise=False)
    as_traj = [footnav.FootTrajectory(t=tr.t, position=tr.position, velocity=tr.velocity, quaternion=tr.quaternion,
                                      position_std=np.zeros_like(tr.position), steps=np.empty((0, 2)))
               for tr in (rec.truth_left, rec.truth_right)]
    path = timeless_average(*as_traj, band_s=2.0, rate_hz=10.0)
    assert np.all(np.diff(path.t) >= 0)
    # the centre line of the 20 x 10 m rectangle: |y| = 0 or 10 on the long sides, |x| = 10 on the short
    x, y = path.position[:, 0], path.position[:, 1]
    dist = np.minimum.reduce([np.abs(y), np.abs(y - 10.0), np.abs(np.abs(x) - 10.0)])
    inside = (np.abs(x) < 8.5) | ((y > 1.5) & (y < 8.5))  # away from the corner arcs
    assert np.max(dist[inside]) < 0.1  # the feet's midpoint: half the 0.2 m step width away at most


def test_dtw_fusion_ties_the_feet_and_keeps_the_walk_on_course():
    es_i, es_d, ep_i, ep_d = [], [], [], []
    for seed in range(3):
        rec = footnav.simulate("rectangle", seed=seed, width_m=105.0, height_m=68.0, **DRIFTY)
        ind, fused = _fuse(IndependentFusion(), rec), _fuse(DtwFusion(), rec)
        for res, es, ep in ((ind, es_i, ep_i), (fused, es_d, ep_d)):
            es.append(np.linalg.norm(res.left.position[-1, :2] - res.right.position[-1, :2]))
            ep += [np.linalg.norm(tr.position[-1, :2] - t.position[-1, :2]) for tr, t in ((res.left, rec.truth_left), (res.right, rec.truth_right))]
        assert fused.meta["midswing_updates"] > 400 and fused.meta["skipped_other_foot_moving"] < 10
        assert fused.path.meta["path"] == "DTW pairing (timeless)"
    # measured (3 seeds): E_s 13.4 -> 0.10 m, E_p 9.4 -> 6.3 m
    assert np.mean(es_d) * 5 <= np.mean(es_i)
    assert np.mean(ep_d) < np.mean(ep_i)


def test_timed_path_is_the_midpoint_at_common_times():
    rec = footnav.simulate("straight", seed=0, distance_m=10.0)
    res = _fuse(DtwFusion(path="timed", initial_heading="first-step"), rec)
    np.testing.assert_allclose(res.path.position, 0.5 * (res.left.position + res.right.position), atol=1e-12)
