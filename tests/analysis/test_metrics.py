"""footnav.analysis.metrics: the height RMSE removes the constant offset only (hand-computed)."""

from __future__ import annotations

import numpy as np
import pytest

from footnav.analysis.metrics import height_rmse


def test_height_rmse_after_the_best_constant_offset():
    # mutant: metrics-height-rmse-offset. z errors 0.5 + (+0.1, -0.1, +0.1, -0.1): RMSE 0.1
    ref = np.column_stack([np.arange(4.0), np.zeros(4), [0.0, 0.2, 0.4, 0.6]])
    est = ref + np.array([[0.0, 0.0, 0.6], [0.0, 0.0, 0.4], [0.0, 0.0, 0.6], [0.0, 0.0, 0.4]])
    assert height_rmse(est, ref) == pytest.approx(0.1, abs=1e-12)
    assert height_rmse(est[:, 2], ref[:, 2]) == pytest.approx(0.1, abs=1e-12)
    est[:, :2] += 3.0  # the plane does not count
    assert height_rmse(est, ref) == pytest.approx(0.1, abs=1e-12)
