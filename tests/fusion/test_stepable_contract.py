"""The step-able estimator contract coupled fusions drive is written down and checked before
anything runs: an estimator that offers ``start`` but not the rest is refused naming what it
lacks (it used to pass the check and fail inside the fusion with "has no parameter 'smoother'")."""

import pytest

import footnav
from footnav import CompositionError, FootEstimator
from footnav.core.component import stepable_gaps


class _StartOnly(FootEstimator):
    name = "start-only"

    def __init__(self, *, zupt_std_mps: float = 0.01) -> None:
        self.zupt_std_mps = zupt_std_mps

    def estimate(self, imu, stance):
        return footnav.make_estimator("ekf").estimate(imu, stance)

    def start(self, imus, stances, **kw):
        return footnav.make_estimator("ekf").start(imus, stances, **kw)


def test_ekf_meets_the_contract_and_madgwick_does_not():
    assert stepable_gaps(footnav.make_estimator("ekf")) == []
    gaps = stepable_gaps(footnav.make_estimator("madgwick"))
    assert "method start" in gaps and "method trajectory" in gaps


def test_a_partial_estimator_is_refused_before_running_naming_what_it_lacks():
    assert stepable_gaps(_StartOnly()) == ["method trajectory", "parameter smoother", "parameter heading"]
    rec = footnav.simulate("straight", seed=0, distance_m=5.0)
    for fusion in ("range", "step-vector", "dtw", "particle"):
        pipe = footnav.Pipeline(footnav.make_detector("threshold"), _StartOnly(), footnav.make_fusion(fusion))
        with pytest.raises(CompositionError, match="lacks method trajectory, parameter smoother, parameter heading"):
            pipe.run(rec.left, rec.right)
