"""footnav.analysis.truth_checks: each refusal's reasons alone and the scale warning on both sides
(the simulator's truth, changed one way each; expected outcomes from the module's rules)."""

from __future__ import annotations

import warnings
from dataclasses import replace

import numpy as np
import pytest

import footnav
from footnav.analysis.evaluation import evaluate
from footnav.core.errors import DataQualityWarning, InvalidInputError
from footnav.core.types import Recording


@pytest.fixture(scope="module")
def walk() -> Recording:
    return footnav.simulate("rectangle", seed=5, width_m=8.0, height_m=4.0)


@pytest.fixture(scope="module")
def pipe():
    return footnav.make_pipeline()


def _left(walk, **changes) -> Recording:
    return Recording(left=walk.left, truth_left=replace(walk.truth_left, **changes), name="bad")


def _checks(pipe, rec):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        report = evaluate(pipe, rec, pipeline_name="p")
    return {c.name: c for c in report.checks if c.foot == "left"}, [
        str(w.message) for w in caught if issubclass(w.category, DataQualityWarning)
    ]


def test_one_truth_point_inside_is_refused_though_its_span_covers_the_walk(walk, pipe):
    # mutant: truth-coverage-and. Points at the first sample and 0.5 s after the end: the truth's
    # span covers the whole walk (coverage 1), but one point lies in the recording
    tr = walk.truth_left
    t = np.array([tr.t[0], tr.t[-1] + 0.5])
    rec = _left(walk, t=t, position=tr.position[[0, -1]], quaternion=None, velocity=None, stance=None)
    with pytest.raises(InvalidInputError, match="with 1 truth point"):
        evaluate(pipe, rec)


def test_a_fast_truth_within_the_error_ratio_is_a_warning_not_an_error(walk, pipe):
    # mutant: truth-scale-or. x10: the truth's foot speeds exceed 20 "m/s" but the ratio (10) is
    # under 20: warned (the estimate or the unit is wrong), not refused
    tr = walk.truth_left
    checks, said = _checks(pipe, _left(walk, position=tr.position * 10.0))
    assert checks["scale"].value == pytest.approx(10.0, rel=0.05) and checks["scale"].status == "warning"
    assert any("not in metres" in s for s in said)


@pytest.mark.parametrize("factor", [0.5, 2.0])
def test_a_truth_path_half_or_twice_the_estimates_is_warned_either_way(walk, pipe, factor):
    # mutant: truth-scale-warn-one-sided
    tr = walk.truth_left
    checks, _ = _checks(pipe, _left(walk, position=tr.position * factor))
    assert checks["scale"].value == pytest.approx(factor, rel=0.05)
    assert checks["scale"].status == "warning"
    checks, _ = _checks(pipe, _left(walk, position=tr.position * (1.0 + 0.2 * np.sign(factor - 1.0))))
    assert checks["scale"].status == "ok"
