"""The range constraint inside the compiled loop (InsFilter.run_until_apart and
run_range_constrained, issue 20).

The reference is the same fusion stepping through its check times in Python (run_until, the
distance, update_position), which it does with a JointFilter that has neither: the same
constraint updates at the same times, on a walk where the constraint acts at many of its checks.
The loop's update is the 3-state kernel (footnav.nav.kalman.update3), Python's the dense one, so
the two agree to rounding, not to the bit. The loop's updates are replayed from a log where the
smoother re-runs a segment: re-run and kept segments must give the same result to the bit.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import footnav
from footnav.core.component import JOINT_FILTER_MEMBERS
from footnav.core.types import StanceResult
from footnav.estimators.ekf import EkfEstimator


class _PythonChecks:
    """The EKF's joint filter with only the JointFilter members: range checks in Python."""

    def __init__(self, inner):
        self._inner = inner

    def __getattr__(self, name):
        if name not in JOINT_FILTER_MEMBERS:
            raise AttributeError(name)
        return getattr(self._inner, name)


class _Estimator(EkfEstimator):
    def start(self, imus, stances, **kwargs):
        filt = super().start(imus, stances, **kwargs)
        return _PythonChecks(filt) if len(imus) == 2 else filt  # one foot: estimate's own filter

    def finish(self, filt, stances):
        return super().finish(getattr(filt, "_inner", filt), stances)


@pytest.fixture(scope="module")
def walk():
    rec = footnav.simulate("path", seed=2, segments=[(25.0, 90.0), (10.0, 0.0)])
    return rec.left, StanceResult(rec.truth_left.stance), rec.right, StanceResult(rec.truth_right.stance)


@pytest.mark.parametrize("projection", ["moving", "symmetric"])
@pytest.mark.parametrize("smoother", ["whole", "step", "none"])
def test_projections_in_the_loop_equal_projections_in_python(walk, projection, smoother):
    fusion = footnav.make_fusion("range", max_separation_m=0.35, projection=projection)  # tight: acts at many checks
    ours = fusion.fuse(footnav.make_estimator("ekf", smoother=smoother), *walk)
    ref = fusion.fuse(_Estimator(smoother=smoother), *walk)
    assert ours.meta["constraint_updates"] == ref.meta["constraint_updates"] > 20
    for foot in ("left", "right"):
        np.testing.assert_allclose(getattr(ours, foot).position, getattr(ref, foot).position, rtol=0, atol=1e-9)
        np.testing.assert_allclose(getattr(ours, foot).position_std, getattr(ref, foot).position_std, rtol=0, atol=1e-9)
        np.testing.assert_allclose(getattr(ours, foot).quaternion, getattr(ref, foot).quaternion, rtol=0, atol=1e-9)


@pytest.mark.parametrize("bias_states", [False, True])
def test_replayed_segments_equal_kept_ones_to_the_bit(walk, bias_states, monkeypatch):
    """No record kept (every segment re-run, the loop's updates replayed from its log) against
    every record kept; short segments, so that many end between the loop's updates and some
    fill with them."""
    from footnav.estimators.ekf import filter as ekf_filter

    monkeypatch.setattr(ekf_filter, "MAX_SEGMENT_EVENTS", 97)
    # a record filled by the loop's own updates must close its chunk, not stop the loop again
    # and again at the same instant (a checkpoint each: it once ran out of memory)
    add = ekf_filter.InsFilter._add_checkpoint
    bound = 4 * 2 * len(walk[0].t) // 97

    def counted(self, *args, **kwargs):
        if len(self.checkpoints) > bound:
            raise RuntimeError(f"more than {bound} checkpoints")
        return add(self, *args, **kwargs)

    monkeypatch.setattr(ekf_filter.InsFilter, "_add_checkpoint", counted)
    fusion = footnav.make_fusion("range", max_separation_m=0.35, projection="symmetric")
    runs = [
        fusion.fuse(footnav.make_estimator("ekf", bias_states=bias_states, smoother_cache_mb=mb), *walk)
        for mb in (0.0, 1e3)
    ]
    assert runs[0].meta["constraint_updates"] > 20
    for foot in ("left", "right"):
        np.testing.assert_array_equal(getattr(runs[0], foot).position, getattr(runs[1], foot).position)
        np.testing.assert_array_equal(getattr(runs[0], foot).quaternion, getattr(runs[1], foot).quaternion)


def test_step_smoother_replayed_equals_step_smoother_during_the_run(walk):
    """smooth(mode="step") of a filter that ran without a step smoother replays the run through
    one, the loop's updates from its log: the same as smoothing each step as the filter runs."""
    from footnav.estimators.ekf.smoother import smooth

    left, sl, right, sr = walk
    times = np.arange(left.t[0], left.t[-1], 0.05)
    filts = [footnav.make_estimator("ekf", smoother=s).start([left, right], [sl, sr]) for s in ("step", "none")]
    for filt in filts:
        assert filt.run_range_constrained(times, 0.35, 0.01)[1] > 20
        filt.run_until()  # the samples after the last time
    a, b = smooth(filts[0], "step"), smooth(filts[1], "step")
    np.testing.assert_array_equal(a.p, b.p)


def test_a_distance_that_is_not_a_number_is_left_to_the_caller(walk):
    left, sl, right, sr = walk
    filt = footnav.make_estimator("ekf", smoother="none").start([left, right], [sl, sr])
    times = np.arange(left.t[0], left.t[-1], 0.05)
    filt.run_until(times[10])
    filt._p[0, 0] = np.nan  # a diverged foot
    found, applied = filt.run_range_constrained(times, 0.35, 0.01, start=11)
    assert (found, applied) == (11, 0)


def test_run_until_apart_stops_where_run_until_and_a_distance_check_would(walk):
    left, sl, right, sr = walk
    est = footnav.make_estimator("ekf", smoother="none")
    times = np.arange(left.t[0], left.t[-1], 0.05)
    a, b = est.start([left, right], [sl, sr]), est.start([left, right], [sl, sr])
    bound = 0.6
    found = a.run_until_apart(times, bound)
    expected = None
    for i, t in enumerate(times):
        b.run_until(t)
        d = b.position(0) - b.position(1)
        if math.sqrt(float(d[0]) ** 2 + float(d[1]) ** 2 + float(d[2]) ** 2) > bound:
            expected = i
            break
    assert found == expected is not None
    np.testing.assert_array_equal(a.position(0), b.position(0))
    assert a.index(0) == b.index(0) and a.index(1) == b.index(1)
    # from the next time on, with a bound nothing exceeds: to the last time, None
    assert a.run_until_apart(times, 1e6, found + 1) is None
    b.run_until(times[-1])
    np.testing.assert_array_equal(a.position(1), b.position(1))
