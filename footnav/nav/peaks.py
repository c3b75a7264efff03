"""``scipy.signal.find_peaks(x, height=h, prominence=0.0, distance=d)``, bit for bit, for several
distances at the cost of one.

:func:`footnav.nav.gait_cycles.swing_peaks` asks for the peaks of one signal twice (the second
time with a distance from the first pass's typical stride), and scipy's prominence search walks
from every peak to the next higher sample on either side: for the tallest swings of an hour's
walk that is most of the recording, per peak. Here the local maxima, their heights and their
prominences are found once (:func:`peak_candidates`; the prominences by one monotonic-stack pass
each way, O(N)), and each distance only re-runs scipy's greedy selection
(:meth:`PeakCandidates.select`).

Every step is scipy's own rule (``scipy/signal/_peak_finding_utils.pyx``: ``_local_maxima_1d``,
``_select_by_peak_distance``, ``_peak_prominences``): a flat peak's index is the middle of its
plateau (rounded down), the distance selection keeps peaks in the order of ``np.argsort`` of
their heights (the same call, so ties go the same way), and a prominence is the peak's height
less the higher of the two lowest values between it and the nearest strictly higher sample on
either side (or the signal's end). Minima and one subtraction are exact, so the prominences are
scipy's to the bit.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from footnav._numba import njit

__all__ = ["PeakCandidates", "peak_candidates"]


@njit(cache=True)
def _local_maxima(x: NDArray[np.float64]) -> NDArray[np.int64]:
    # scipy's _local_maxima_1d: a sample above its left neighbour, then equal samples, then a
    # lower one; the peak is the middle of that plateau
    out = np.empty(x.shape[0] // 2 + 1, dtype=np.int64)
    m = 0
    i = 1
    i_max = x.shape[0] - 1
    while i < i_max:
        if x[i - 1] < x[i]:
            i_ahead = i + 1
            while i_ahead < i_max and x[i_ahead] == x[i]:
                i_ahead += 1
            if x[i_ahead] < x[i]:
                out[m] = (i + i_ahead - 1) // 2
                m += 1
                i = i_ahead
        i += 1
    return out[:m]


@njit(cache=True)
def _base_minima(x: NDArray[np.float64], peaks: NDArray[np.int64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Lowest value from each peak (increasing indices) back to the nearest strictly higher
    sample, and forward to the next one (or the ends): scipy's ``left_min``, ``right_min``."""
    n = x.shape[0]
    left = np.empty(peaks.shape[0])
    right = np.empty(peaks.shape[0])
    stack = np.empty(n, dtype=np.int64)  # indices of decreasing values ...
    low = np.empty(n)  # ... each with the minimum since the entry below it
    for direction in (1, -1):
        top = 0
        j = 0 if direction == 1 else peaks.shape[0] - 1
        for step in range(n):
            i = step if direction == 1 else n - 1 - step
            m = x[i]
            # samples not above x[i] are inside its search: their stretches' minima join its own
            while top > 0 and x[stack[top - 1]] <= x[i]:
                m = min(m, low[top - 1])
                top -= 1
            stack[top] = i
            low[top] = m
            top += 1
            if 0 <= j < peaks.shape[0] and peaks[j] == i:
                if direction == 1:
                    left[j] = m
                else:
                    right[j] = m
                j += direction
    return left, right


@njit(cache=True)
def _select_by_distance(peaks: NDArray[np.int64], order: NDArray[np.int64], distance: int) -> NDArray[np.bool_]:
    # scipy's _select_by_peak_distance: the highest remaining peak removes its neighbours closer
    # than ``distance``
    n = peaks.shape[0]
    keep = np.ones(n, dtype=np.bool_)
    for i in range(n - 1, -1, -1):
        j = order[i]
        if not keep[j]:
            continue
        k = j - 1
        while 0 <= k and peaks[j] - peaks[k] < distance:
            keep[k] = False
            k -= 1
        k = j + 1
        while k < n and peaks[k] - peaks[j] < distance:
            keep[k] = False
            k += 1
    return keep


@dataclass(frozen=True, eq=False)
class PeakCandidates:
    """The local maxima of a signal at least ``height`` high, with their prominences.

    Attributes
    ----------
    index
        Their sample indices, increasing, (K,).
    height
        The signal there, (K,).
    prominence
        scipy's prominence of each, (K,).
    order
        ``np.argsort(height)``: the distance selection's priority.
    """

    index: NDArray[np.int64]
    height: NDArray[np.float64]
    prominence: NDArray[np.float64]
    order: NDArray[np.int64]

    def select(self, distance: int, rel_prominence: float) -> NDArray[np.int64]:
        """The peaks of ``find_peaks(x, height=height, prominence=0.0, distance=distance)``
        whose prominence is at least ``rel_prominence`` x their height.

        Parameters
        ----------
        distance
            Minimum distance between peaks, samples (at least 1).
        rel_prominence
            Minimum prominence as a share of the peak's height.

        Returns
        -------
        NDArray[np.int64]
            Sample indices, increasing.
        """
        keep = _select_by_distance(self.index, self.order, int(distance))
        keep &= self.prominence >= rel_prominence * self.height
        return self.index[keep]


def peak_candidates(x: NDArray[np.float64], height: float) -> PeakCandidates:
    """Local maxima of ``x`` (N,) at least ``height`` high, their prominences and priority order.

    Parameters
    ----------
    x
        The signal (finite).
    height
        Lowest peak height.

    Returns
    -------
    PeakCandidates
    """
    peaks, heights, prominence = _candidates(np.ascontiguousarray(x, dtype=np.float64), float(height))
    # numpy's argsort, not numba's: equal heights must come in numpy's order
    return PeakCandidates(peaks, heights, prominence, np.argsort(heights))


@njit(cache=True)
def _candidates(
    x: NDArray[np.float64], height: float
) -> tuple[NDArray[np.int64], NDArray[np.float64], NDArray[np.float64]]:
    # the local maxima at least ``height`` high, their heights and prominences in one call (a
    # stream's detector asks for them on every window)
    peaks = _local_maxima(x)
    peaks = peaks[x[peaks] >= height]
    heights = x[peaks]
    left, right = _base_minima(x, peaks)
    return peaks, heights, heights - np.maximum(left, right)
