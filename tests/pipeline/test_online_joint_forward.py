"""footnav.pipeline.online_joint: the live forward estimate of a coupled fusion (the joint
filter's state and position covariance per foot) against the offline joint filter at the same
sample (``smoother="none"``, nothing added to ``position_std`` after the filter)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import footnav

EST = {"smoother": "none", "vertical": "free", "heading_drift_in_std": False}


@pytest.fixture(scope="module")
def walk():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return footnav.simulate("rectangle", seed=3, width_m=8, height_m=4)


@pytest.mark.parametrize("fusion, params", [("range", {"max_separation_m": 0.6}), ("step-vector", {"step_length": "pendulum"})])
def test_joint_forward_covariance_is_the_offline_filters_at_the_same_sample(walk, fusion, params):
    # mutant: online-joint-forward-cov-block
    pipe = footnav.make_pipeline("threshold", "ekf", fusion, estimator_params=EST, fusion_params=params)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        off = pipe.run(walk.left, walk.right)
        stream = pipe.online(feet=2)
        update = stream.push(left=walk.left.slice(0, 1500), right=walk.right.slice(0, 1500))
    for foot, imu in (("left", walk.left), ("right", walk.right)):
        fwd, traj = getattr(update, foot).forward, getattr(off, foot)
        k = int(np.searchsorted(imu.t, fwd.t))
        assert imu.t[k] == fwd.t and k > 1000
        np.testing.assert_allclose(fwd.position, traj.position[k], atol=1e-8)
        np.testing.assert_allclose(np.sqrt(np.diag(fwd.position_cov)), traj.position_std[k], rtol=1e-7, atol=1e-12)
