"""What every windowed stance detector shares: centred moving sums and turning a mask into a
StanceResult (minimum stance duration, foot-flat / heel-off events)."""

from __future__ import annotations

from typing import Any, Mapping

import numpy as np
from numpy.typing import NDArray

from footnav.core.types import StanceResult, stance_intervals

__all__ = ["window_samples", "centred_mean", "stance_result"]


def window_samples(window_s: float, rate_hz: float) -> int:
    """Window length in samples for ``window_s`` seconds at ``rate_hz`` (at least 1)."""
    return max(1, int(round(window_s * rate_hz)))


def centred_mean(x: NDArray[np.float64], win: int) -> NDArray[np.float64]:
    """Mean of ``x`` (N, ...) over a centred window of ``win`` samples, shrunk at the ends.

    O(N) by cumulative sums; sample k averages ``x[k - win//2 : k - win//2 + win]`` clipped to the
    recording, so the statistic never looks past the data.
    """
    n = len(x)
    c = np.concatenate([np.zeros((1,) + x.shape[1:]), np.cumsum(x, axis=0)])
    lo = np.clip(np.arange(n) - win // 2, 0, n)
    hi = np.clip(lo + win, 0, n)
    counts = (hi - lo).reshape((n,) + (1,) * (x.ndim - 1))
    return (c[hi] - c[lo]) / counts


def stance_result(
    mask: NDArray[np.bool_],
    rate_hz: float,
    min_stance_s: float,
    score: NDArray[np.float64],
    meta: Mapping[str, Any],
) -> StanceResult:
    """Drop stance runs shorter than ``min_stance_s`` and mark each run's first sample as
    ``foot_flat`` and its last as ``heel_off``."""
    mask = np.array(mask, dtype=bool)
    min_len = int(round(min_stance_s * rate_hz))
    for a, b in stance_intervals(mask):
        if b - a < min_len:
            mask[a:b] = False
    runs = stance_intervals(mask)
    return StanceResult(
        mask=mask,
        events={"foot_flat": runs[:, 0], "heel_off": runs[:, 1] - 1},
        score=score,
        meta=dict(meta),
    )
