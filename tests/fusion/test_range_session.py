"""The range fusion's session: its check times are numpy's arange, whether the walk's end is known
(offline) or not yet (online, times asked for in increasing pieces)."""

from __future__ import annotations

import numpy as np

from footnav.fusion.range_constraint import RangeConstraintFusion, RangeSession


def test_check_times_are_numpys_arange_in_one_piece_or_many():
    rng = np.random.default_rng(1)
    for _ in range(2000):
        t0 = rng.uniform(-100, 5000)
        step = float(rng.choice([0.05, 0.01, 0.033, rng.uniform(1e-3, 1)]))
        t1 = t0 + rng.uniform(0, 300)
        fusion = RangeConstraintFusion(check_interval_s=step)
        reference = np.arange(t0, t1, step)
        whole = RangeSession(fusion, t0)._times(t1, t1)
        pieces = RangeSession(fusion, t0)
        parts = [pieces._times(u, None) for u in np.sort(rng.uniform(t0 - 1, t1, 7))]
        parts.append(pieces._times(t1, t1))
        np.testing.assert_array_equal(whole, reference)
        np.testing.assert_array_equal(np.concatenate(parts), reference)


def test_landings_join_the_checks_once_each():
    session = RangeSession(RangeConstraintFusion(check_interval_s=0.5), 0.0)
    session._landings = [0.25, 1.0, 3.7]  # 1.0 is also a check time
    np.testing.assert_array_equal(session._times(2.0, None), [0.0, 0.25, 0.5, 1.0, 1.5, 2.0])
    np.testing.assert_array_equal(session._times(4.0, 4.0), [2.5, 3.0, 3.5, 3.7])
