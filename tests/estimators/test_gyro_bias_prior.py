"""The 15-state filter's gyro bias prior: from the standstill, and what a loose one does.

References are the simulator's: its sensor's noise density (the standard error of a mean of n
samples is density * sqrt(rate / n)) and its truth's path length.
"""

import numpy as np
import pytest

import footnav
from footnav.estimators.ekf.estimator import GYRO_BIAS_STD_FLOOR_RADPS
from footnav.nav.heading_drift import TURN_ON_BIAS_STD_RADPS

#: Li et al. (2018)'s 1075 m road as docs/make_papers.py rebuilds it (five turns, 729 strides).
ROAD = [(250.0, 90.0), (120.0, 90.0), (180.0, -90.0), (80.0, -90.0), (200.0, 90.0), (245.0, 0.0)]


def _forward_15(rec, **params):
    est = footnav.make_estimator("ekf", bias_states=True, smoother="none", **params)
    return est.estimate(rec.left, footnav.make_detector("threshold").detect(rec.left))


def _length_2d(pos):
    return float(np.linalg.norm(np.diff(pos[:, :2], axis=0), axis=1).sum())


@pytest.fixture(scope="module")
def road():
    return footnav.simulate("path", segments=ROAD, stride_length_m=1075 / 729, seed=0)


def test_prior_is_the_standstill_standard_error():
    density = 1.7e-4  # rad/s/sqrt(Hz), the simulator's default gyro
    rec = footnav.simulate("straight", distance_m=10.0, seed=1, gyr_noise_density_radps_sqrthz=density)
    tr = _forward_15(rec)
    n_used = tr.meta["alignment_samples"][2]  # [start, stop, still samples used]
    expected = density * np.sqrt(rec.left.rate_hz / n_used)
    assert tr.meta["init_gyr_bias_std_radps"] == pytest.approx(expected, rel=0.25)
    assert tr.meta["init_gyr_bias_std_radps"] == tr.meta["gyro_bias_sem_radps"]


def test_prior_without_standstill_bias_is_the_turn_on_bias_and_a_value_wins():
    rec = footnav.simulate("straight", distance_m=4.0, seed=1)
    assert _forward_15(rec, gyro_bias="none").meta["init_gyr_bias_std_radps"] == TURN_ON_BIAS_STD_RADPS
    assert _forward_15(rec, init_gyr_bias_std_radps=3e-4).meta["init_gyr_bias_std_radps"] == 3e-4


def test_noise_free_standstill_gets_the_floor_not_zero():
    rec = footnav.simulate("straight", distance_m=4.0, seed=1, gyr_noise_density_radps_sqrthz=0.0)
    tr = _forward_15(rec)
    assert tr.meta["gyro_bias_sem_radps"] < GYRO_BIAS_STD_FLOOR_RADPS
    assert tr.meta["init_gyr_bias_std_radps"] == GYRO_BIAS_STD_FLOOR_RADPS


def test_forward_track_is_not_lengthened_by_stance_re_estimates(road):
    """Loose gyro bias priors (2e-3 rad/s, walk 1e-4) let every stance sample re-place the
    position through the unobservable heading: the per-sample track was 17 % longer than the
    truth's on this walk (Li et al. 2018's IEZ row: 0.32 %). The data's prior keeps it near 1 %."""
    truth = _length_2d(road.truth_left.position)
    honest = _length_2d(_forward_15(road).position)
    loose = _length_2d(_forward_15(road, init_gyr_bias_std_radps=2e-3, gyr_bias_walk_radps2_sqrthz=1e-4).position)
    assert abs(honest / truth - 1) < 0.015
    assert loose / truth - 1 > 0.10  # the case tells the two priors apart
