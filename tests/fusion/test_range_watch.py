"""The range constraint's checks inside the compiled loop (InsFilter.run_until_apart, issue 20).

The reference is the same fusion stepping through its check times in Python (run_until, then the
distance), which it does with a JointFilter that has no run_until_apart: the results must be the
same to the bit, on a walk where the constraint acts at many of its checks.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import footnav
from footnav.component import JOINT_FILTER_MEMBERS
from footnav.estimators.ekf import EkfEstimator
from footnav.types import StanceResult


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


def test_checks_in_the_loop_equal_checks_in_python_to_the_bit(walk):
    fusion = footnav.make_fusion("range", max_separation_m=0.35)  # tight: acts at many checks
    ours = fusion.fuse(footnav.make_estimator("ekf"), *walk)
    ref = fusion.fuse(_Estimator(), *walk)
    assert ours.meta["constraint_updates"] == ref.meta["constraint_updates"] > 20
    for foot in ("left", "right"):
        np.testing.assert_array_equal(getattr(ours, foot).position, getattr(ref, foot).position)
        np.testing.assert_array_equal(getattr(ours, foot).position_std, getattr(ref, foot).position_std)


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
