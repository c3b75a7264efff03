"""footnav.nav.spans on hand-made clocks: each reason for "marked" alone, both signs, the cut
indices at sample boundaries and the refusal's two cases. Expected values from the module's
definitions, worked out by hand for the clocks below."""

from __future__ import annotations

import numpy as np
import pytest

from footnav.core.errors import InvalidInputError
from footnav.core.types import ImuData
from footnav.nav.spans import common_bounds, common_span, span_difference


def _imu(t0, t1, rate=10.0):
    t = t0 + np.arange(round((t1 - t0) * rate) + 1) / rate
    acc = np.tile([0.0, 0.0, 9.81], (len(t), 1))
    return ImuData(t=t, acc=acc, gyr=np.zeros((len(t), 3)))


@pytest.mark.parametrize("shift", [3.0, -3.0])
def test_starts_alone_apart_are_marked_either_way(shift):
    # mutant: spans-marked-and, spans-marked-one-sided. 100 s walks: tolerance max(2, 5 s) = 5 s
    left = _imu(10.0, 110.0)
    right = _imu(10.0 + 2 * shift, 110.0)  # starts 6 s apart (either way), ends together
    d = span_difference(left, right)
    assert d["tolerance_s"] == pytest.approx(0.05 * max(100.0, 100.0 - 2 * shift))
    assert d["start_difference_s"] == pytest.approx(2 * shift) and d["end_difference_s"] == 0.0
    assert d["marked"] and d["message"]


@pytest.mark.parametrize("shift", [6.0, -6.0])
def test_ends_alone_apart_are_marked_either_way(shift):
    left = _imu(0.0, 100.0)
    right = _imu(0.0, 100.0 + shift)
    d = span_difference(left, right)
    assert d["start_difference_s"] == 0.0 and d["end_difference_s"] == pytest.approx(shift)
    assert d["marked"]


def test_tolerance_is_the_larger_of_two_seconds_and_five_percent():
    # mutant: spans-tolerance-min. 20 s walks: 5 % is 1 s, the tolerance 2 s; 1.5 s apart is not marked
    d = span_difference(_imu(0.0, 20.0), _imu(1.5, 20.0))
    assert d["tolerance_s"] == 2.0 and not d["marked"]
    d = span_difference(_imu(0.0, 200.0), _imu(8.0, 200.0))  # 5 % of 200 s = 10 s
    assert d["tolerance_s"] == pytest.approx(10.0) and not d["marked"]


def test_cut_indices_hold_the_samples_on_the_bounds():
    # both bounds fall on samples: t_start <= t <= t_stop keeps them
    left, right = _imu(0.0, 10.0), _imu(2.0, 8.0)
    span = common_span(left, right)
    assert (span.start_s, span.stop_s) == (2.0, 8.0)
    assert (span.left.start_index, span.left.stop_index) == (20, 81)
    assert left.t[20] == 2.0 and left.t[80] == 8.0
    assert (span.right.start_index, span.right.stop_index) == (0, len(right.t))
    assert span.left.cut_before_s == 2.0 and span.left.cut_after_s == pytest.approx(2.0)
    assert span.largest_cut_s == pytest.approx(2.0) and span.warn and not span.right.cut


def test_refusal_too_short_and_disjoint():
    with pytest.raises(InvalidInputError, match="share only 2 s"):
        common_bounds((0.0, 10.0), (8.0, 20.0))
    with pytest.raises(InvalidInputError, match="share no time span"):
        common_bounds((0.0, 10.0), (12.0, 20.0))
    assert common_bounds((0.0, 10.0), (7.0, 20.0)) == (7.0, 10.0)  # exactly 3 s: accepted
