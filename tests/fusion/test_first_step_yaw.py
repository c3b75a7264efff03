"""The first-step heading of a coupled fusion's joint filter, found on a prefix (issues 18, 20).

``footnav.fusion.joint.first_step_yaw`` runs the forward filter over a foot's first stance
phases only, doubling them until the first step is found. The reference is the forward filter
run over the whole foot (what the fusions ran before): the heading must be the same to the bit,
and the samples filtered a small part of the walk.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import footnav
from footnav.core.types import StanceResult
from footnav.fusion.joint import first_step_yaw, forward_only


class _Counting:
    """An estimator wrapper that counts the samples handed to ``estimate``."""

    def __init__(self, estimator):
        self.estimator, self.samples, self.calls = estimator, 0, 0

    def estimate(self, imu, stance):
        self.samples += imu.n_samples
        self.calls += 1
        return self.estimator.estimate(imu, stance)


@pytest.fixture(scope="module")
def walk():
    rec = footnav.simulate("path", seed=4, segments=[(70.0, 90.0), (30.0, 0.0)])
    return rec.left, StanceResult(rec.truth_left.stance)


def _whole_yaw(forward, imu, stance) -> float:
    return float(forward.estimate(imu, stance).meta["heading_rotation_rad"])


def test_first_step_yaw_equals_the_whole_forward_run_on_a_fraction_of_the_samples(walk):
    imu, stance = walk
    forward = forward_only(footnav.make_pipeline().estimator)
    counting = _Counting(forward)
    yaw = first_step_yaw(counting, imu, stance)
    assert yaw == _whole_yaw(forward, imu, stance)
    assert counting.calls == 1
    assert counting.samples < 0.1 * imu.n_samples  # four stance phases of a 100 m walk


def test_first_step_yaw_doubles_the_prefix_until_the_foot_has_stepped(walk):
    imu, stance = walk
    # five short breaks in the initial standstill: stance phases whose footprints coincide, so
    # the first step longer than 0.2 m comes only after them
    mask = stance.mask.copy()
    first_stop = int(stance.intervals[0, 1])
    for k in np.linspace(0.3, 0.9, 5) * first_stop:
        mask[int(k) : int(k) + 2] = False
    shuffled = StanceResult(mask)
    assert len(shuffled.intervals) == len(stance.intervals) + 5
    forward = forward_only(footnav.make_pipeline().estimator)
    counting = _Counting(forward)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the shortened first stance aligns with a warning
        yaw = first_step_yaw(counting, imu, shuffled, first_steps=2)
        assert yaw == _whole_yaw(forward, imu, shuffled)
    assert counting.calls == 3  # 2, 4, then 8 stance phases
    assert counting.samples < 0.3 * imu.n_samples


def test_first_step_yaw_is_zero_when_the_foot_never_steps():
    rec = footnav.simulate("straight", seed=0, distance_m=5.0)
    still = StanceResult(np.ones(rec.left.n_samples, dtype=bool))
    forward = forward_only(footnav.make_pipeline().estimator)
    assert first_step_yaw(forward, rec.left, still) == 0.0
