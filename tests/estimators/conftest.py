"""Fixtures shared by the estimator tests."""

from __future__ import annotations

import pytest

import footnav
from footnav.core.types import StanceResult


@pytest.fixture(scope="module")
def walk():
    rec = footnav.simulate("straight", seed=4, distance_m=6.0, standstill_s=1.0)
    return rec.left, StanceResult(rec.truth_left.stance)
