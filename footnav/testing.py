"""Conformance tests every component (built-in or third-party) can reuse.

Subclass the contract in your own test suite and name your class::

    from footnav.testing import DetectorContract

    class TestMyDetector(DetectorContract):
        component = MyDetector

The contracts check the component API (keyword-only parameters stored unchanged, ``get_params`` /
``clone`` / ``repr``, a declared name), that the action method returns the right result type,
sample-aligned and deterministic, and that it is *right* on a short simulated walk (10 m straight,
100 Hz, against the simulator's truth): a detector's stances lie in the true stances and find each
of them, an estimator's foot ends near its true position, a fusion keeps the left foot on the left.
``StepableEstimatorContract`` checks an estimator the coupled fusions drive
(:class:`footnav.core.component.StepableEstimator`) by running every one of them with it.
The bounds are generous (5-10x what the built-ins measure) so they fail only a wrong component,
e.g. one with a flipped ZUPT sign or the feet swapped. They need pytest.
"""

from __future__ import annotations

import inspect
from typing import Any, ClassVar

import numpy as np
import pytest

from footnav.core.component import (
    JOINT_FILTER_MEMBERS,
    FootEstimator,
    Fusion,
    HeadingAid,
    JointFilter,
    StanceDetector,
    StepableEstimator,
    stepable_gaps,
)
from footnav.core.errors import InvalidParameterError
from footnav.core.types import FootTrajectory, FusionResult, Recording, StanceResult, stance_intervals

__all__ = [
    "ComponentContract",
    "DetectorContract",
    "EstimatorContract",
    "FusionContract",
    "HeadingAidContract",
    "OnlineEstimatorContract",
    "StepableEstimatorContract",
    "contract_walk",
]

_WALK: dict[tuple[int, bool], Recording] = {}

#: Smallest fraction of detected stance samples that lie in the simulator's true stance (built-ins:
#: 1.00; the example plugin's gyro-norm detector 0.95; a detector that marks everything: ~0.55).
MIN_STANCE_PRECISION = 0.8
#: Smallest fraction of true stance phases with at least one detected stance sample (built-ins: 1.00).
MIN_STANCE_PHASES_FOUND = 0.9
#: Largest 3-D error of the foot's displacement from its start at the walk's end, m (10 m walk,
#: true stances; ekf 0.02-0.05 m, madgwick 0.03-0.05 m over seeds 0-2).
MAX_ESTIMATE_ERROR_M = 0.5
#: Largest final position error of each foot against its truth in a fusion, m (the truth starts the
#: feet 0.2 m apart; built-ins 0.02-0.13 m over seeds 0-2).
MAX_FUSION_ERROR_M = 0.5
#: Smallest mean signed separation (left minus right, across the walking direction) over double
#: support, m. The truth is +0.2 m; fusions that model the step width measure 0.19-0.21 m (dtw,
#: lateral offset 0: 0.08 m), ``independent`` (both feet start at the origin) 0.00 m; a fusion that
#: swaps the feet or puts the width on the wrong side measures about -0.2 m.
MIN_SIGNED_SEPARATION_M = -0.05


def contract_walk(seed: int = 0, *, magnetometer: bool = False) -> Recording:
    """A short simulated straight walk (both feet, 100 Hz), cached per seed; with
    ``magnetometer``, 20 m long and with the simulator's magnetometer (enough stances for a
    magnetometer aid's gates)."""
    key = (seed, magnetometer)
    if key not in _WALK:
        from footnav.data.simulate import simulate

        extra = {"distance_m": 20.0, "magnetometer": True} if magnetometer else {"distance_m": 10.0}
        _WALK[key] = simulate("straight", seed=seed, rate_hz=100.0, **extra)
    return _WALK[key]


class ComponentContract:
    """The contract every component keeps: a name, keyword-only parameters stored unchanged, clone, repr and parameter
    info."""

    component: ClassVar[type]
    #: Keyword arguments to build the component for the contract (defaults if empty).
    params: ClassVar[dict[str, Any]] = {}

    def make(self):
        """The component under test, built from ``component`` and ``params``."""
        return self.component(**self.params)

    def test_declares_a_name(self):
        assert isinstance(self.component.name, str) and self.component.name

    def test_constructor_takes_keyword_only_parameters(self):
        if self.component.__init__ is object.__init__:
            return  # no parameters (the heading aid 'none'): object's (*args, **kwargs) is not one
        sig = inspect.signature(self.component.__init__)
        for p in list(sig.parameters.values())[1:]:
            assert p.kind is p.KEYWORD_ONLY, f"parameter {p.name!r} must be keyword-only"
            assert p.default is not p.empty, f"parameter {p.name!r} needs a default"

    def test_parameters_are_stored_unchanged(self):
        comp = self.make()
        params = comp.get_params()
        sig = inspect.signature(self.component.__init__)
        for name, value in params.items():
            expected = self.params.get(name, sig.parameters[name].default)
            assert value is expected or value == expected

    def test_clone_and_repr(self):
        comp = self.make()
        twin = comp.clone()
        assert twin is not comp and twin.get_params() == comp.get_params()
        assert type(comp).__name__ in repr(comp)
        with pytest.raises(InvalidParameterError, match="valid parameters"):
            comp.clone(no_such_parameter_xyz=1)

    def test_parameter_info_covers_every_parameter(self):
        names = [p.name for p in self.component.parameter_info()]
        assert names == list(self.make().get_params())


class DetectorContract(ComponentContract):
    """Contract for :class:`~footnav.StanceDetector` subclasses."""

    def test_is_a_detector(self):
        assert issubclass(self.component, StanceDetector)

    def test_detect_returns_aligned_deterministic_result(self):
        rec = contract_walk()
        det = self.make()
        left, _right = det.detect_pair(rec.left, rec.right)
        assert isinstance(left, StanceResult)
        assert left.mask.shape == (rec.left.n_samples,)
        assert 0 < left.mask.mean() < 1, "a walk has both stance and swing"
        again, _ = self.make().detect_pair(rec.left, rec.right)
        np.testing.assert_array_equal(left.mask, again.mask)

    def test_stances_lie_in_the_true_stances_and_find_each(self):
        rec = contract_walk()
        results = self.make().detect_pair(rec.left, rec.right)
        for foot, res, truth in zip(("left", "right"), results, (rec.truth_left, rec.truth_right)):
            mask, true = np.asarray(res.mask, bool), truth.stance
            precision = (mask & true).sum() / max(int(mask.sum()), 1)
            assert precision >= MIN_STANCE_PRECISION, (
                f"{foot} foot: only {precision:.0%} of the detected stance samples are true stance"
            )
            found = np.mean([mask[a:b].any() for a, b in stance_intervals(true)])
            assert found >= MIN_STANCE_PHASES_FOUND, f"{foot} foot: only {found:.0%} of the true stance phases detected"


class EstimatorContract(ComponentContract):
    """Contract for :class:`~footnav.FootEstimator` subclasses."""

    def test_is_an_estimator(self):
        assert issubclass(self.component, FootEstimator)

    def test_estimate_returns_aligned_trajectory(self):
        rec = contract_walk()
        stance = StanceResult(rec.truth_left.stance)
        traj = self.make().estimate(rec.left, stance)
        assert isinstance(traj, FootTrajectory)
        assert traj.position.shape == (rec.left.n_samples, 3)
        assert np.all(np.isfinite(traj.position))
        np.testing.assert_allclose(np.linalg.norm(traj.quaternion, axis=1), 1.0, atol=1e-9)

    def test_estimate_ends_near_the_truth(self):
        # the estimate starts at its own origin with x the walking direction: compare displacements
        rec = contract_walk()
        for foot, imu, truth in (("left", rec.left, rec.truth_left), ("right", rec.right, rec.truth_right)):
            traj = self.make().estimate(imu, StanceResult(truth.stance))
            moved = traj.position[-1] - traj.position[0]
            true = truth.position[-1] - truth.position[0]
            err = float(np.linalg.norm(moved - true))
            assert err <= MAX_ESTIMATE_ERROR_M, (
                f"{foot} foot ends {err:.2f} m from the truth after {np.linalg.norm(true):.1f} m"
            )


class FusionContract(ComponentContract):
    """Contract for :class:`~footnav.Fusion` subclasses (run with the ``ekf`` estimator)."""

    def test_is_a_fusion(self):
        assert issubclass(self.component, Fusion)

    def test_fuse_returns_both_feet_and_a_path(self):
        from footnav.estimators.ekf import EkfEstimator

        rec = contract_walk()
        res = self.make().fuse(
            EkfEstimator(),
            rec.left,
            StanceResult(rec.truth_left.stance),
            rec.right,
            StanceResult(rec.truth_right.stance),
        )
        assert isinstance(res, FusionResult)
        assert res.left.position.shape == (rec.left.n_samples, 3)
        assert res.right is not None and res.right.position.shape == (rec.right.n_samples, 3)
        assert res.path.position.ndim == 2 and len(res.path.t) > 0

    def test_feet_end_near_the_truth_left_foot_on_the_left(self):
        from footnav.estimators.ekf import EkfEstimator

        rec = contract_walk()
        stances = StanceResult(rec.truth_left.stance), StanceResult(rec.truth_right.stance)
        res = self.make().fuse(EkfEstimator(), rec.left, stances[0], rec.right, stances[1])
        for foot, traj, truth in (("left", res.left, rec.truth_left), ("right", res.right, rec.truth_right)):
            err = float(np.linalg.norm(traj.position[-1] - truth.position[-1]))
            assert err <= MAX_FUSION_ERROR_M, f"{foot} foot ends {err:.2f} m from its true position"
        # across the walking direction (the truth's left unit vector at each sample of double support)
        signed = _signed_separation(rec, res)
        assert signed >= MIN_SIGNED_SEPARATION_M, (
            f"the left foot is {-signed:.2f} m to the right of the right foot on average (truth: 0.2 m left)"
        )


def _signed_separation(rec: Recording, res: FusionResult) -> float:
    """Mean signed separation of the feet (left minus right) across the walking direction over
    double support, m (the truth: +0.2 m)."""
    both = rec.truth_left.stance & rec.truth_right.stance
    true_sep = (rec.truth_left.position - rec.truth_right.position)[both, :2]
    across = true_sep / np.linalg.norm(true_sep, axis=1, keepdims=True)
    sep = (res.left.position - res.right.position)[both, :2]
    return float(np.mean(np.sum(sep * across, axis=1)))


class StepableEstimatorContract(EstimatorContract):
    """Contract for an estimator that coupled fusions drive step by step
    (:class:`footnav.core.component.StepableEstimator`): it has every member, its ``start`` returns
    a :class:`~footnav.core.component.JointFilter`, and every built-in coupled fusion run with it
    ends each foot near its truth with the left foot on the left."""

    #: The coupled fusions the contract runs (built-in names).
    fusions: ClassVar[tuple[str, ...]] = ("range", "step-vector", "particle", "dtw")

    def test_has_every_member_of_the_protocol(self):
        est = self.make()
        assert stepable_gaps(est) == [], f"{self.component.__name__} lacks {stepable_gaps(est)}"
        assert isinstance(est, StepableEstimator)

    def test_start_returns_a_joint_filter(self):
        rec = contract_walk()
        stances = [StanceResult(rec.truth_left.stance), StanceResult(rec.truth_right.stance)]
        filt = self.make().start([rec.left, rec.right], stances)
        missing = [m for m in JOINT_FILTER_MEMBERS if not hasattr(filt, m)]
        assert isinstance(filt, JointFilter), f"start() returned a {type(filt).__name__} lacking {missing}"

    def test_every_coupled_fusion_ends_near_the_truth_left_foot_on_the_left(self):
        from footnav.pipeline.factory import make_fusion

        rec = contract_walk()
        stances = StanceResult(rec.truth_left.stance), StanceResult(rec.truth_right.stance)
        for name in self.fusions:
            res = make_fusion(name).fuse(self.make(), rec.left, stances[0], rec.right, stances[1])
            for foot, traj, truth in (("left", res.left, rec.truth_left), ("right", res.right, rec.truth_right)):
                err = float(np.linalg.norm(traj.position[-1] - truth.position[-1]))
                assert err <= MAX_FUSION_ERROR_M, f"{name}: {foot} foot ends {err:.2f} m from its true position"
            signed = _signed_separation(rec, res)
            assert signed >= MIN_SIGNED_SEPARATION_M, (
                f"{name}: the left foot is {-signed:.2f} m right of the right foot"
            )


class OnlineEstimatorContract(EstimatorContract):
    """Contract for an estimator a stream runs (:class:`footnav.core.online_contract.OnlineEstimator`):
    it has every member, its ``start`` returns an :class:`~footnav.core.online_contract.OnlineFilter`,
    and the ``threshold`` detector's pipeline with it, fed both feet of the contract walk in
    chunks into filter segments of ``online_segment`` samples (many ``rebase`` s), returns the
    offline run's positions within ``online_atol_m`` (per step with ``smoother="whole"``: its
    pushes are then smoothed per step, only ``close`` is compared)."""

    #: Filter segment size in the stream test (samples; a stream's default is 16384).
    online_segment: ClassVar[int] = 300
    #: Largest difference of the online positions from the offline ones, m.
    online_atol_m: ClassVar[float] = 1e-9

    def test_has_every_member_of_the_online_protocol(self):
        from footnav.core.online_contract import OnlineEstimator, online_gaps

        est = self.make()
        assert online_gaps(est) == [], f"{self.component.__name__} lacks {online_gaps(est)}"
        assert isinstance(est, OnlineEstimator)

    def test_start_returns_an_online_filter(self):
        from footnav.core.online_contract import ONLINE_FILTER_MEMBERS, OnlineFilter

        rec = contract_walk()
        filt = self.make().start([rec.left], [StanceResult(rec.truth_left.stance)])
        missing = [m for m in ONLINE_FILTER_MEMBERS if not hasattr(filt, m)]
        assert isinstance(filt, OnlineFilter), f"start() returned a {type(filt).__name__} lacking {missing}"

    def test_a_stream_in_small_segments_gives_the_offline_result(self, monkeypatch):
        import warnings

        from footnav.pipeline import online_foot
        from footnav.pipeline.factory import make_pipeline

        monkeypatch.setattr(online_foot, "SEGMENT_SAMPLES", self.online_segment)
        rec = contract_walk()
        pipe = make_pipeline("threshold", self.make(), "independent")
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            offline = pipe.run(rec.left, rec.right)
            stream = pipe.online(feet=2)
            got: dict[str, list] = {"left": [], "right": []}
            for a in range(0, rec.left.n_samples, 37):
                chunks = [
                    (imu.t[a : a + 37], imu.acc[a : a + 37], imu.gyr[a : a + 37]) for imu in (rec.left, rec.right)
                ]
                update = stream.push(left=chunks[0], right=chunks[1])
                for foot, parts in got.items():
                    parts.append(getattr(update, foot).position)
            result = stream.close()
        for foot, parts in got.items():
            parts.append(getattr(stream.last_update, foot).position)
            ref = getattr(offline, foot).position
            np.testing.assert_allclose(
                getattr(result, foot).position, ref, atol=self.online_atol_m, rtol=0, err_msg=foot
            )
            if getattr(pipe.estimator, "smoother", None) != "whole":
                pushed = np.concatenate(parts)
                np.testing.assert_allclose(pushed, ref, atol=self.online_atol_m, rtol=0, err_msg=foot)


class HeadingAidContract(ComponentContract):
    """Contract for :class:`~footnav.core.component.HeadingAid` subclasses: ``correct`` returns a
    :class:`~footnav.core.types.FusionResult` aligned with the fusion's, deterministic, and on the
    contract walk (ekf, true stances, ``independent`` fusion; with a magnetometer for an aid that
    needs one) each corrected foot still ends near its truth: an aid may turn the path, but not a
    straight walk away from its true heading."""

    def test_is_a_heading_aid(self):
        assert issubclass(self.component, HeadingAid)
        assert isinstance(self.component.online, bool)

    def _fused(self):
        from footnav.estimators.ekf import EkfEstimator
        from footnav.fusion.independent import IndependentFusion

        rec = contract_walk(magnetometer=self.component.needs_magnetometer)
        stances = StanceResult(rec.truth_left.stance), StanceResult(rec.truth_right.stance)
        return rec, IndependentFusion().fuse(EkfEstimator(), rec.left, stances[0], rec.right, stances[1])

    def test_correct_returns_aligned_deterministic_result(self):
        rec, fused = self._fused()
        res = self.make().correct(fused, rec.left, rec.right)
        again = self.make().correct(fused, rec.left, rec.right)
        assert isinstance(res, FusionResult)
        for foot, traj in (("left", res.left), ("right", res.right)):
            assert traj.position.shape == (rec.left.n_samples, 3), foot
            assert np.all(np.isfinite(traj.position)), foot
        np.testing.assert_array_equal(res.left.position, again.left.position)

    def test_feet_still_end_near_the_truth(self):
        rec, fused = self._fused()
        res = self.make().correct(fused, rec.left, rec.right)
        for foot, traj, truth in (("left", res.left, rec.truth_left), ("right", res.right, rec.truth_right)):
            moved = traj.position[-1] - traj.position[0]
            true = truth.position[-1] - truth.position[0]
            err = float(np.linalg.norm(moved - true))
            assert err <= MAX_ESTIMATE_ERROR_M, f"{foot} foot ends {err:.2f} m from the truth after the heading aid"
