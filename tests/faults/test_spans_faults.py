"""Fault cases: feet whose time spans do not overlap (clock hours off, disjoint recordings)."""

from __future__ import annotations

import warnings

import pytest

import footnav
from footnav.core.errors import DataQualityWarning, InvalidInputError

COUPLED = ["range", "step-vector", "particle", "dtw"]


@pytest.mark.fault
@pytest.mark.parametrize("fusion", COUPLED)
def test_right_clock_3_hours_ahead_is_refused_naming_both_spans(fusion):
    """Before: 4.6 / 7.9 m errors on a 12 m walk (range) or unrelated errors."""
    rec = footnav.simulate("straight", seed=1, distance_m=12.0, clock_offset_s=3 * 3600.0)
    with pytest.raises(InvalidInputError, match="share no time span") as err:
        footnav.make_pipeline("adaptive", "ekf", fusion).run(rec)
    msg = str(err.value)
    assert err.value.field == "t"
    assert "left foot 0..14 s (14 s)" in msg and "right foot 10800..10814 s (14 s)" in msg and "10786 s apart" in msg
    assert "sync='data'" in msg and "independent" in msg


@pytest.mark.fault
@pytest.mark.parametrize("fusion", COUPLED)
def test_disjoint_feet_are_refused(fusion):
    rec = footnav.simulate("straight", seed=1, distance_m=30.0)
    left, right = rec.left.slice(0, 1200), rec.right.slice(1500, None)
    with pytest.raises(InvalidInputError, match=r"share no time span \(3.01 s apart\)"):
        footnav.make_pipeline("adaptive", "ekf", fusion).run(left, right)


@pytest.mark.fault
@pytest.mark.parametrize("fusion", COUPLED)
def test_too_little_common_span_is_refused(fusion):
    rec = footnav.simulate("straight", seed=1, distance_m=30.0)
    left, right = rec.left.slice(0, 1200), rec.right.slice(1000, None)  # 2 s in common
    with pytest.raises(InvalidInputError, match=r"share only 1.99 s \(at least 3 s needed\)"):
        footnav.make_pipeline("adaptive", "ekf", fusion).run(left, right)


@pytest.mark.fault
def test_independent_runs_with_a_3_hour_clock_offset_and_says_so():
    rec = footnav.simulate("straight", seed=1, distance_m=12.0, clock_offset_s=3 * 3600.0)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        res = footnav.make_pipeline("adaptive", "ekf", "independent").run(rec)
    marked = [
        str(w.message) for w in caught if issubclass(w.category, DataQualityWarning) and "markedly" in str(w.message)
    ]
    assert len(marked) == 1 and "+1.08e+04 s" in marked[0] and "sync='data'" in marked[0]
    assert res.meta["pipeline"]["fusion"]["name"] == "independent"
    assert any("markedly" in w for w in res.meta["warnings"])
    assert len(res.path.t) == 0  # no common part: no midpoint path, and nothing invented
    assert len(res.right.t) == len(rec.right.t)
