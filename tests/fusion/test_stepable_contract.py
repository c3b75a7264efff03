"""The step-able estimator contract coupled fusions drive (footnav.core.component.StepableEstimator
and JointFilter), written as Protocols and checked before anything runs: an estimator that offers
``start`` but not the rest is refused naming what it lacks, and an estimator written by a third
party against the Protocols alone runs with every coupled fusion."""

import numpy as np
import pytest

import footnav
from footnav import CompositionError, FootEstimator
from footnav.core.component import JointFilter, StepableEstimator, stepable_gaps
from footnav.testing import StepableEstimatorContract

COUPLED = ("range", "step-vector", "dtw", "particle")


class _StartOnly(FootEstimator):
    name = "start-only"

    def __init__(self, *, zupt_std_mps: float = 0.01) -> None:
        self.zupt_std_mps = zupt_std_mps

    def estimate(self, imu, stance):
        return footnav.make_estimator("ekf").estimate(imu, stance)

    def start(self, imus, stances, **kw):
        return footnav.make_estimator("ekf").start(imus, stances, **kw)


class _Joint:
    """A third party's joint filter: exactly the JointFilter members, each handed to a wrapped
    filter. A fusion that reached for anything else would fail here with AttributeError."""

    def __init__(self, inner):
        self._inner = inner

    @property
    def covariance(self):
        return self._inner.covariance

    def block(self, foot, name):
        return self._inner.block(foot, name)

    def time(self, foot):
        return self._inner.time(foot)

    def index(self, foot):
        return self._inner.index(foot)

    def position(self, foot):
        return self._inner.position(foot)

    def velocity(self, foot):
        return self._inner.velocity(foot)

    def quaternion(self, foot):
        return self._inner.quaternion(foot)

    def outputs(self, foot):
        return self._inner.outputs(foot)

    def run_until(self, t_stop=np.inf):
        return self._inner.run_until(t_stop)

    def selection(self, indices):
        return self._inner.selection(indices)

    def update(self, h, innovation, r, *, gate=None):
        return self._inner.update(h, innovation, r, gate=gate)

    def update_position(self, foot, z, std_m, axes=3):
        return self._inner.update_position(foot, z, std_m, axes)


class ProtocolEstimator(FootEstimator):
    """Written against the Protocols only: its own component, its own filter type.

    Parameters
    ----------
    smoother : str
        "none", "step" or "whole", as the ekf's.
    heading : str
        "first-step" or "sensor", as the ekf's.
    """

    name = "protocol-probe"

    def __init__(self, *, smoother: str = "whole", heading: str = "first-step") -> None:
        self.smoother = smoother
        self.heading = heading

    def _ekf(self):
        return footnav.make_estimator("ekf", smoother=self.smoother, heading=self.heading)

    def estimate(self, imu, stance):
        return self._ekf().estimate(imu, stance)

    def start(self, imus, stances, *, initial_yaw_rad=None, initial_position_m=None):
        inner = self._ekf().start(imus, stances, initial_yaw_rad=initial_yaw_rad, initial_position_m=initial_position_m)
        return _Joint(inner)

    def finish(self, filt, stances):
        return self._ekf().finish(filt._inner, stances)


class TestProtocolEstimator(StepableEstimatorContract):
    component = ProtocolEstimator


def test_the_protocols_describe_the_ekf_and_not_madgwick():
    ekf = footnav.make_estimator("ekf")
    assert isinstance(ekf, StepableEstimator) and stepable_gaps(ekf) == []
    rec = footnav.simulate("straight", seed=0, distance_m=5.0)
    stances = [footnav.StanceResult(t.stance) for t in (rec.truth_left, rec.truth_right)]
    assert isinstance(ekf.start([rec.left, rec.right], stances), JointFilter)
    madgwick = footnav.make_estimator("madgwick")
    assert not isinstance(madgwick, StepableEstimator)
    gaps = stepable_gaps(madgwick)
    assert "method start" in gaps and "method finish" in gaps


def test_a_protocol_estimator_gives_the_ekfs_results_with_every_coupled_fusion():
    """The probe only hands calls on, so each fusion's result must be the ekf's, bit for bit:
    the fusions used nothing outside the Protocols. (The probe has no ``vertical``: the pipeline
    leaves its heights as they are, the ekf's ``vertical="free"``.)"""
    rec = footnav.simulate("straight", seed=1, distance_m=8.0)
    for fusion in COUPLED:
        ours = footnav.Pipeline(
            footnav.make_detector("threshold"), ProtocolEstimator(), footnav.make_fusion(fusion)
        ).run(rec)
        ref = footnav.make_pipeline("threshold", "ekf", fusion, estimator_params={"vertical": "free"}).run(rec)
        for foot in ("left", "right"):
            np.testing.assert_array_equal(getattr(ours, foot).position, getattr(ref, foot).position, err_msg=fusion)


def test_a_partial_estimator_is_refused_before_running_naming_what_it_lacks():
    assert stepable_gaps(_StartOnly()) == ["method finish", "parameter smoother", "parameter heading"]
    rec = footnav.simulate("straight", seed=0, distance_m=5.0)
    for fusion in COUPLED:
        pipe = footnav.Pipeline(footnav.make_detector("threshold"), _StartOnly(), footnav.make_fusion(fusion))
        with pytest.raises(CompositionError, match="lacks method finish, parameter smoother, parameter heading"):
            pipe.run(rec.left, rec.right)


def test_a_start_that_returns_no_joint_filter_is_refused_naming_the_missing_members():
    class Broken(ProtocolEstimator):
        name = "broken-probe"

        def start(self, imus, stances, **kw):
            return object()

    rec = footnav.simulate("straight", seed=0, distance_m=5.0)
    with pytest.raises(CompositionError, match="lacks covariance, block, time"):
        footnav.Pipeline(footnav.make_detector("threshold"), Broken(), footnav.make_fusion("range")).run(rec)
