"""footnav.pipeline.online_foot: the live forward estimate a user sees, against the offline
forward filter at the same sample.

The sensor is mounted turned 35 deg about z, so the first step's heading (the output frame's
turn, psi) is far from 0 and the position covariance has off-diagonal terms: a covariance turned
the wrong way (R' P R for R P R') changes its diagonal, which the offline run gives as
``position_std`` at every sample (``smoother="none"``: the offline result is the forward filter;
``vertical="free"`` and ``heading_drift_in_std=False``: nothing added after it).
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import footnav


@pytest.fixture(scope="module")
def turned_walk():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return footnav.simulate("rectangle", seed=3, width_m=8, height_m=4, mounting_rpy_deg=(0.0, 0.0, 35.0))


def test_forward_covariance_is_the_offline_filters_at_the_same_sample(turned_walk):
    # mutant: online-forward-cov-turned-back, online-forward-cov-transposed
    rec = turned_walk
    pipe = footnav.make_pipeline(
        "threshold",
        "ekf",
        "independent",
        estimator_params={"smoother": "none", "vertical": "free", "heading_drift_in_std": False},
    )
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        off = pipe.run(rec.left).left
        stream = pipe.online(feet=1)
        start = 0
        for stop in (900, 1400, 2100):
            update = stream.push(left=rec.left.slice(start, stop))
            start = stop
            fwd = update.left.forward
            k = int(np.searchsorted(rec.left.t, fwd.t))
            assert rec.left.t[k] == fwd.t
            np.testing.assert_allclose(fwd.position, off.position[k], atol=1e-9)
            np.testing.assert_allclose(fwd.velocity, off.velocity[k], atol=1e-9)
            np.testing.assert_allclose(np.sqrt(np.diag(fwd.position_cov)), off.position_std[k], rtol=1e-9, atol=1e-12)
            np.testing.assert_allclose(fwd.position_cov, fwd.position_cov.T, atol=1e-15)
    # the case tells a wrong turn apart: turned the other way, the diagonal differs by far
    psi = stream.feet[0].psi
    c, s = np.cos(2 * psi), np.sin(2 * psi)
    twice = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])  # R(psi) R(psi): from one turn to the other
    wrong = twice @ fwd.position_cov @ twice.T
    assert abs(psi) > 0.3 and np.max(np.abs(np.sqrt(np.diag(wrong)) - off.position_std[k])) > 1e-4
