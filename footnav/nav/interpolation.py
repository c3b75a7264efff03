"""Linear interpolation of sampled columns: the one helper every resampling in footnav uses."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

__all__ = ["interp_columns"]


def interp_columns(t_new: NDArray[np.float64], t: NDArray[np.float64], values: NDArray[np.float64]) -> NDArray[np.float64]:
    """Each column of ``values`` (N, K), sampled at increasing times ``t`` (N,), linearly
    interpolated to ``t_new`` (M,): (M, K), in the columns' units. No checks and, as
    ``numpy.interp``, no extrapolation: times outside ``t`` take the end values; callers check
    their spans."""
    return np.column_stack([np.interp(t_new, t, values[:, k]) for k in range(values.shape[1])])
