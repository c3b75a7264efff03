"""Conformance tests every component (built-in or third-party) can reuse.

Subclass the contract in your own test suite and name your class::

    from footnav.testing import DetectorContract

    class TestMyDetector(DetectorContract):
        component = MyDetector

The contracts check the component API (keyword-only parameters stored unchanged, ``get_params`` /
``clone`` / ``repr``, a declared name) and that the action method returns the right result type,
sample-aligned, deterministic, on a short simulated walk. They need pytest.
"""

from __future__ import annotations

import inspect
from typing import Any, ClassVar

import numpy as np
import pytest

from footnav.core.component import FootEstimator, Fusion, StanceDetector
from footnav.core.errors import InvalidParameterError
from footnav.core.types import FootTrajectory, FusionResult, Recording, StanceResult

__all__ = ["ComponentContract", "DetectorContract", "EstimatorContract", "FusionContract", "contract_walk"]

_WALK: dict[int, Recording] = {}


def contract_walk(seed: int = 0) -> Recording:
    """A short simulated straight walk (both feet, 100 Hz), cached per seed."""
    if seed not in _WALK:
        from footnav.core.simulate import simulate

        _WALK[seed] = simulate("straight", seed=seed, rate_hz=100.0, distance_m=10.0)
    return _WALK[seed]


class ComponentContract:
    component: ClassVar[type]
    #: Keyword arguments to build the component for the contract (defaults if empty).
    params: ClassVar[dict[str, Any]] = {}

    def make(self):
        return self.component(**self.params)

    def test_declares_a_name(self):
        assert isinstance(self.component.name, str) and self.component.name

    def test_constructor_takes_keyword_only_parameters(self):
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
        left, right = det.detect_pair(rec.left, rec.right)
        assert isinstance(left, StanceResult)
        assert left.mask.shape == (rec.left.n_samples,)
        assert 0 < left.mask.mean() < 1, "a walk has both stance and swing"
        again, _ = self.make().detect_pair(rec.left, rec.right)
        np.testing.assert_array_equal(left.mask, again.mask)


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


class FusionContract(ComponentContract):
    """Contract for :class:`~footnav.Fusion` subclasses (run with the ``ekf`` estimator)."""

    def test_is_a_fusion(self):
        assert issubclass(self.component, Fusion)

    def test_fuse_returns_both_feet_and_a_path(self):
        from footnav.estimators.ekf import EkfEstimator

        rec = contract_walk()
        res = self.make().fuse(
            EkfEstimator(), rec.left, StanceResult(rec.truth_left.stance), rec.right, StanceResult(rec.truth_right.stance)
        )
        assert isinstance(res, FusionResult)
        assert res.left.position.shape == (rec.left.n_samples, 3)
        assert res.right is not None and res.right.position.shape == (rec.right.n_samples, 3)
        assert res.path.position.ndim == 2 and len(res.path.t) > 0
