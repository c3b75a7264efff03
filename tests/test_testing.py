"""footnav.testing's contracts fail a wrong component: a flipped ZUPT, an inverted stance mask, swapped feet.

Each wrong component is a small third-party-style class next to its right twin; the twin passes the
contract's accuracy check and the wrong one fails it, so the contract's conformance means the
component works, not only that its result has the right shape.
"""

import dataclasses

import numpy as np
import pytest

from footnav.core.component import FootEstimator, Fusion, HeadingAid, StanceDetector
from footnav.core.types import FootTrajectory, FusionResult, StanceResult, stance_intervals
from footnav.fusion.independent import IndependentFusion
from footnav.fusion.step_vector import StepVectorFusion
from footnav.nav import quaternion as quat
from footnav.nav.initial_alignment import align_at_rest
from footnav.testing import (
    DetectorContract,
    EstimatorContract,
    FusionContract,
    HeadingAidContract,
    StepableEstimatorContract,
    contract_walk,
)

G = 9.80665  # standard gravity, m/s^2 (CGPM 1901), written out: not read from the library


class NaiveZuptEstimator(FootEstimator):
    """Strapdown with a velocity reset at each stance sample: ``v <- v - zupt_sign * v``.

    ``zupt_sign=1`` is the textbook reset (v = 0); ``-1`` doubles the velocity instead, the
    third-party bug the estimator contract must catch.
    """

    name = "naive-zupt"

    def __init__(self, *, zupt_sign: float = 1.0):
        self.zupt_sign = zupt_sign

    def estimate(self, imu, stance):
        first = stance_intervals(stance.mask)[0]
        align = align_at_rest(imu.acc, imu.gyr, int(first[0]), int(first[1]))
        n = imu.n_samples
        q, v, p = align.quaternion, np.zeros(3), np.zeros(3)
        qs, vs, ps = np.tile(q, (n, 1)), np.zeros((n, 3)), np.zeros((n, 3))
        for k in range(1, n):
            dt = imu.t[k] - imu.t[k - 1]
            q = quat.normalize(quat.multiply(q, quat.from_rotvec((imu.gyr[k] - align.gyro_bias_radps) * dt)))
            a = quat.rotate(q, imu.acc[k]) - [0.0, 0.0, G]
            v_new = v + a * dt
            p = p + 0.5 * (v + v_new) * dt
            v = v_new
            if stance.mask[k]:
                v = v - self.zupt_sign * v
            qs[k], vs[k], ps[k] = q, v, p
        return FootTrajectory(
            t=imu.t, position=ps, velocity=vs, quaternion=qs, position_std=np.zeros((n, 3)), steps=stance.intervals
        )


class InvertibleDetector(StanceDetector):
    """The simulator's own stance truth is not available to a detector: this one thresholds the
    gyro norm, and ``invert=True`` returns swing as stance."""

    name = "invertible"

    def __init__(self, *, threshold_radps: float = 0.6, invert: bool = False):
        self.threshold_radps = threshold_radps
        self.invert = invert

    def detect(self, imu):
        mask = np.linalg.norm(imu.gyr, axis=1) < self.threshold_radps
        return StanceResult(~mask if self.invert else mask)


class SwappedFeetFusion(Fusion):
    """Step-vector fusion that hands back the feet swapped (a left/right mix-up)."""

    name = "swapped-feet"

    def __init__(self):
        pass

    def fuse(self, estimator, left, stance_left, right=None, stance_right=None):
        res = StepVectorFusion().fuse(estimator, left, stance_left, right, stance_right)
        return FusionResult(left=res.right, right=res.left, path=res.path, meta=res.meta)


def _check(contract_cls, component, params, method):
    contract = type("C", (contract_cls,), {"component": component, "params": params})()
    getattr(contract, method)()


@pytest.mark.filterwarnings("ignore:overflow:RuntimeWarning")  # the flipped ZUPT doubles v each stance sample
def test_estimator_contract_passes_a_right_zupt_and_fails_a_flipped_one():
    _check(EstimatorContract, NaiveZuptEstimator, {"zupt_sign": 1.0}, "test_estimate_ends_near_the_truth")
    with pytest.raises(AssertionError, match="from the truth"):
        _check(EstimatorContract, NaiveZuptEstimator, {"zupt_sign": -1.0}, "test_estimate_ends_near_the_truth")


def test_detector_contract_passes_a_right_detector_and_fails_an_inverted_one():
    method = "test_stances_lie_in_the_true_stances_and_find_each"
    _check(DetectorContract, InvertibleDetector, {}, method)
    with pytest.raises(AssertionError, match="true stance"):
        _check(DetectorContract, InvertibleDetector, {"invert": True}, method)


def test_fusion_contract_fails_swapped_feet():
    method = "test_feet_end_near_the_truth_left_foot_on_the_left"
    _check(FusionContract, StepVectorFusion, {}, method)
    _check(FusionContract, IndependentFusion, {}, method)
    with pytest.raises(AssertionError):
        _check(FusionContract, SwappedFeetFusion, {}, method)


class TestEkfIsStepable(StepableEstimatorContract):
    """footnav's ekf, the reference implementation of the step-able Protocols."""

    from footnav.estimators.ekf import EkfEstimator as component


def test_stepable_contract_fails_an_estimator_that_swaps_the_feet_in_its_filter():
    """A joint filter whose feet are swapped (a third party's indexing slip) ends each foot at the
    other's place: the contract's accuracy test catches it."""
    from footnav.estimators.ekf import EkfEstimator

    class SwappedStart(EkfEstimator):
        name = "swapped-start"

        def start(self, imus, stances, **kw):
            return super().start(imus[::-1], stances[::-1], **kw)

        def finish(self, filt, stances):
            return super().finish(filt, stances[::-1])[::-1]

    with pytest.raises(AssertionError, match="left foot is|from its true position"):
        _check(
            StepableEstimatorContract,
            SwappedStart,
            {},
            "test_every_coupled_fusion_ends_near_the_truth_left_foot_on_the_left",
        )


def test_contract_walk_is_the_documented_walk():
    rec = contract_walk()
    # 10 m along +x at 100 Hz, the left foot 0.1 m left of the centre line (simulate's defaults)
    assert np.median(np.diff(rec.left.t)) == pytest.approx(0.01)
    assert rec.truth_left.position[-1, 0] == pytest.approx(10.0, abs=0.8)
    assert rec.truth_left.position[0, 1] == pytest.approx(0.1, abs=1e-9)
    assert rec.truth_right.position[0, 1] == pytest.approx(-0.1, abs=1e-9)


class _TurningAid(HeadingAid):
    """A heading aid that turns both feet about their start by ``turn_rad`` (wrong when not 0)."""

    name = "turning-test"

    def __init__(self, *, turn_rad: float = 0.0) -> None:
        self.turn_rad = turn_rad

    def correct(self, result, left, right=None):
        c, s = np.cos(self.turn_rad), np.sin(self.turn_rad)
        rot = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
        feet = []
        for traj in (result.left, result.right):
            p0 = traj.position[0]
            feet.append(dataclasses.replace(traj, position=(traj.position - p0) @ rot.T + p0))
        return dataclasses.replace(result, left=feet[0], right=feet[1])


def test_heading_aid_contract_passes_no_turn_and_fails_a_turn():
    _check(HeadingAidContract, _TurningAid, {}, "test_feet_still_end_near_the_truth")
    with pytest.raises(AssertionError, match="from the truth"):
        _check(HeadingAidContract, _TurningAid, {"turn_rad": 0.2}, "test_feet_still_end_near_the_truth")
