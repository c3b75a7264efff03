"""Gait cycles in a foot's angular rate: one swing peak per stride, found without stance labels.

Every stride of a foot holds one swing, the most energetic moment of its gait cycle, and one stance
between consecutive swings. The swings are the unmistakable part of the signal at every pace: the
windowed RMS angular rate over ~0.2 s (about half a swing) has one broad hump per swing, 5-15 rad/s
in walking and running, ~1 rad/s in shuffling or crawling, whatever the sensor's mounting (a norm).
:func:`swing_peaks` finds those humps; the stance detector :mod:`footnav.detectors.adaptive` and
the pipeline's stance self-check (:mod:`footnav.nav.stance_check`) both stand on them.

The window is long enough to merge the zero crossing of the pitch rate in mid-swing (two narrow
humps of the raw norm) into one hump, and short enough not to bridge a running stance (~0.2 s).
A hump counts when its prominence is a large share of its height (the signal falls far between
two swings, not between the halves of one) and when it is at least a fraction of the recording's
typical stride apart from a higher one.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from footnav._numba import njit
from footnav.core.types._derived import shared
from footnav.nav.order_stats import median
from footnav.nav.peaks import _select_by_distance, peak_candidates
from footnav.nav.windows import centred_gyr_rms, window_samples

__all__ = ["MAX_STRIDE_S", "SWING_ACC_MPS2", "SwingPeaks", "select_swing_peaks", "swing_peaks"]

#: A swinging foot accelerates: the RMS of ``|f| - g`` over its swing window exceeds this (m/s^2;
#: 5-20 m/s^2 in the walking and running swings of the shared recordings). A foot that turns fast
#: but stays below it pivots on the ground (turns on the spot, U-turn shuffles: 0.6-2 m/s^2).
SWING_ACC_MPS2 = 2.0

#: Peak intervals longer than this are pauses, not strides, when the typical stride is taken (s).
MAX_STRIDE_S = 2.5


@dataclass(frozen=True, eq=False)
class SwingPeaks:
    """The swing peaks of one foot's recording.

    Attributes
    ----------
    index
        Sample index of each swing peak, increasing, (K,).
    height_radps
        RMS angular rate of the ``window_samples`` window centred on each peak, rad/s, (K,).
    energy_radps
        That windowed RMS angular rate at every sample, rad/s, (N,).
    window_samples
        The window, samples.
    stride_s
        Median time between consecutive peaks closer than ``max_stride_s`` (the typical stride of
        this recording), s, or nan with fewer than two such peaks.
    """

    index: NDArray[np.int64]
    height_radps: NDArray[np.float64]
    energy_radps: NDArray[np.float64]
    window_samples: int
    stride_s: float


def swing_peaks(
    gyr: NDArray[np.float64],
    rate_hz: float,
    *,
    window_s: float = 0.2,
    min_peak_radps: float = 0.6,
    rel_prominence: float = 0.4,
    min_stride_s: float = 0.3,
    stride_fraction: float = 0.6,
    max_stride_s: float = MAX_STRIDE_S,
) -> SwingPeaks:
    """Swing peaks of the windowed RMS angular rate: one per stride of this foot.

    Parameters
    ----------
    gyr
        Angular rate, rad/s, body frame, (N, 3).
    rate_hz
        Sampling rate, Hz.
    window_s
        RMS window, s (odd number of samples, :func:`~footnav.nav.windows.window_samples`).
    min_peak_radps
        A swing peaks above this, rad/s: below it the foot is fidgeting, not stepping.
    rel_prominence
        A swing's prominence (scipy.signal.peak_prominences) is at least this share of its height.
    min_stride_s
        Peaks closer than this are one swing, s (no foot strides faster).
    stride_fraction
        Second pass: peaks closer than this fraction of the typical stride are one swing (the
        lower one goes); 0 skips it.
    max_stride_s
        Peak intervals longer than this are pauses, not strides, when the typical stride is taken.

    Returns
    -------
    SwingPeaks
        Within a pipeline run (:func:`footnav.core.types._derived.sharing`) the one computed for the
        same read-only ``gyr`` and arguments: the detector's peaks serve the stance self-check.
    """
    gyr = np.asarray(gyr, dtype=np.float64)
    args = (rate_hz, window_s, min_peak_radps, rel_prominence, min_stride_s, stride_fraction, max_stride_s)
    return shared("swing_peaks", (gyr,), args, lambda: _swing_peaks(gyr, *args))


def _swing_peaks(
    gyr: NDArray[np.float64],
    rate_hz: float,
    window_s: float,
    min_peak_radps: float,
    rel_prominence: float,
    min_stride_s: float,
    stride_fraction: float,
    max_stride_s: float,
) -> SwingPeaks:
    n = len(gyr)
    win = window_samples(window_s, rate_hz, n)
    energy = centred_gyr_rms(gyr, win)
    idx, stride_s = select_swing_peaks(
        energy, rate_hz, min_peak_radps, rel_prominence, min_stride_s, stride_fraction, max_stride_s
    )
    return SwingPeaks(idx, energy[idx], energy, win, stride_s)


def select_swing_peaks(
    energy: NDArray[np.float64],
    rate_hz: float,
    min_peak_radps: float,
    rel_prominence: float,
    min_stride_s: float,
    stride_fraction: float,
    max_stride_s: float,
) -> tuple[NDArray[np.int64], float]:
    """The swing peaks of the windowed RMS angular rate ``energy`` (rad/s, (N,)) and the typical
    stride (s): :func:`swing_peaks` after its window, for a caller that has the energy (the
    adaptive detector online, :mod:`footnav.detectors.adaptive`). Arguments as :func:`swing_peaks`'s."""
    # scipy.signal.find_peaks(energy, height=min_peak_radps, prominence=0.0, distance=...) kept
    # when the prominence is at least rel_prominence x the height, for both passes at the cost of
    # one (footnav.nav.peaks)
    c = peak_candidates(energy, min_peak_radps)
    return _select_swings(
        c.index,
        c.height,
        c.prominence,
        c.order,
        float(rate_hz),
        float(min_stride_s),
        float(stride_fraction),
        float(max_stride_s),
        float(rel_prominence),
    )


@njit(cache=True)
def _kept(index, first, second):  # pragma: no cover - compiled
    """``index[first & second]``."""
    k = 0
    for i in range(len(index)):
        k += first[i] and second[i]
    out = np.empty(k, dtype=np.int64)
    k = 0
    for i in range(len(index)):
        if first[i] and second[i]:
            out[k] = index[i]
            k += 1
    return out


@njit(cache=True)
def _select_swings(
    index: NDArray[np.int64],
    height: NDArray[np.float64],
    prominence: NDArray[np.float64],
    order: NDArray[np.int64],
    rate_hz: float,
    min_stride_s: float,
    stride_fraction: float,
    max_stride_s: float,
    rel_prominence: float,
) -> tuple[NDArray[np.int64], float]:
    # both passes of PeakCandidates.select and the median stride in one compiled call: online it
    # runs on every detection window, where a dozen numpy calls cost more than the work. Loops,
    # not array expressions, np.diff or np.sort: numba compiles those for seconds
    n = len(index)
    prominent = np.empty(n, dtype=np.bool_)
    for i in range(n):
        prominent[i] = prominence[i] >= rel_prominence * height[i]
    idx = _kept(index, _select_by_distance(index, order, max(1, int(min_stride_s * rate_hz))), prominent)
    intervals = np.empty(max(len(idx) - 1, 0))
    m = np.int64(0)  # not a literal 0: numba would compile median for it as well
    for i in range(1, len(idx)):
        if idx[i] - idx[i - 1] < max_stride_s * rate_hz:
            intervals[m] = idx[i] - idx[i - 1]
            m += 1
    stride_s = np.nan
    if m:
        stride_s = median(intervals, m) / rate_hz  # np.median's value
    if stride_fraction > 0 and m >= 3:
        # the typical stride separates the halves of one swing that the first pass took as two
        distance = max(int(min_stride_s * rate_hz), int(stride_fraction * stride_s * rate_hz))
        idx = _kept(index, _select_by_distance(index, order, max(1, distance)), prominent)
    return idx, stride_s
