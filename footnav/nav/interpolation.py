"""Linear interpolation of sampled columns: the one helper every resampling in footnav uses."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

__all__ = ["interp_columns"]


def interp_columns(
    t_new: NDArray[np.float64], t: NDArray[np.float64], values: NDArray[np.float64]
) -> NDArray[np.float64]:
    """Each column of ``values`` (N, K), sampled at increasing times ``t`` (N,), linearly
    interpolated to ``t_new`` (M,): (M, K), in the columns' units. No checks and, as
    ``numpy.interp``, no extrapolation: times outside ``t`` take the end values; callers check
    their spans.

    When ``t_new`` is a run of consecutive samples of ``t`` (both feet on one clock and grid, a
    span cut from a recording), those rows are copied: ``numpy.interp`` returns the sample itself
    at a time equal to a sample's, so the result is the same to the bit, without K searches."""
    m = len(t_new)
    i0 = int(np.searchsorted(t, t_new[0])) if m and len(t) else -1
    # the last time first: on different grids the whole comparison is seldom needed
    if 0 <= i0 and i0 + m <= len(t) and t[i0 + m - 1] == t_new[-1] and np.array_equal(t[i0 : i0 + m], t_new):
        return np.array(values[i0 : i0 + m], dtype=np.float64, order="C")
    return np.column_stack([np.interp(t_new, t, values[:, k]) for k in range(values.shape[1])])
