"""footnav.nav.final_rest: each refusal on its own (a walk cut short; a last stance that is a step).

Hand-built masks at 100 Hz with the expected index or refusal worked out from the docstring's
rule: the last stance reaches within 0.5 s of the end and lasts at least max(1 s, 2 x median).
"""

from __future__ import annotations

import numpy as np
import pytest

from footnav.core.errors import InvalidInputError
from footnav.core.types import StanceResult
from footnav.nav.final_rest import final_rest

RATE = 100.0


def _walk(rest_samples: int, tail_samples: int, step_stance: int = 40, n_steps: int = 6):
    """Steps of ``step_stance`` samples of stance and 60 of swing, then a rest, then a tail."""
    mask = []
    for _ in range(n_steps):
        mask += [True] * step_stance + [False] * 60
    mask += [True] * rest_samples + [False] * tail_samples
    mask = np.array(mask, bool)
    return np.arange(len(mask)) / RATE, StanceResult(mask)


def test_a_long_rest_at_the_end_is_found_at_its_last_sample():
    t, st = _walk(rest_samples=300, tail_samples=20)
    assert final_rest(t, st) == len(t) - 20 - 1


def test_a_long_rest_followed_by_too_long_a_tail_alone_is_refused():
    # mutant: final-rest-or-and (the rest is long enough: only the tail refuses)
    t, st = _walk(rest_samples=300, tail_samples=80)  # 0.8 s > 0.5 s of movement after it
    with pytest.raises(InvalidInputError, match="moves for 0.80 s"):
        final_rest(t, st)


def test_a_short_last_stance_reaching_the_end_alone_is_refused():
    # mutant: final-rest-or-and (the tail is short: only the rest's length refuses)
    t, st = _walk(rest_samples=60, tail_samples=0)  # 0.59 s < 1 s
    with pytest.raises(InvalidInputError, match="lasts 0.59 s"):
        final_rest(t, st)


def test_the_rest_must_outlast_twice_the_median_walking_stance():
    # mutant: final-rest-need-min. Walking stances of 0.79 s: need max(1, 1.58) = 1.58 s
    t, st = _walk(rest_samples=130, tail_samples=0, step_stance=80)  # 1.29 s: > 1 s, < 1.58 s
    with pytest.raises(InvalidInputError, match="at least 1.58 s"):
        final_rest(t, st)
    t, st = _walk(rest_samples=170, tail_samples=0, step_stance=80)  # 1.69 s
    assert final_rest(t, st) == len(t) - 1


def test_tail_boundary_exactly_half_a_second_is_accepted():
    # mutant: final-rest-tail-boundary (0.5 s of movement is allowed: "at most")
    t, st = _walk(rest_samples=300, tail_samples=50)
    assert final_rest(t, st) == len(t) - 51
