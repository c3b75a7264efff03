"""Gait-adaptive stance detector: one stance per gait cycle, bounds from each cycle's own energy.

No single bound serves every gait. A walking foot rests at 0.02-0.1 rad/s and a 0.5 rad/s bound
(footnav's ``threshold``) finds its stance; a running or fast-walking foot never stops turning
(0.3-1.5 rad/s at its stillest, |f| 1-2.5 m/s^2 from g), so that bound finds 3 stances in 30
strides; a crawling or shuffling foot swings at ~1 rad/s, so that bound takes its swing as
stance. Published answers adapt the bound to the motion: per motion class (Wagstaff, Peretroukhin
and Kelly, "Improving foot-mounted inertial navigation through real-time motion classification",
IPIN 2017), or per gait cycle from the cycle's own signal. This detector does the latter, with no
learned model:

1. The gait cycles: the swing peaks of the 0.2 s RMS angular rate
   (:func:`footnav.nav.gait_cycles.swing_peaks`), one per stride; a cycle runs from one swing
   peak to the next (before the first and after the last, the recording's ends).
2. The statistic of the ``threshold`` detector (Skog et al. 2010, ARE and MAG over a 0.04 s
   window), normalised by the base bounds: ``s = max(gyr RMS / gyr_threshold_radps,
   acc RMS / acc_tolerance_mps2)``; a window is still when ``s < scale`` of its cycle.
3. Each cycle's scale: 1 (the base bounds: a walking foot is detected exactly as by
   ``threshold``) when the foot stands under the base bounds for ``base_stance_s`` in the cycle;
   otherwise ``stance_factor x`` its stillest ``s`` (so the cycle's quietest stretch is stance
   even when the foot never stops), at least 1; in every cycle at most ``swing_fraction x`` the
   lower of the two swing peaks bounding the cycle in units of the gyro bound (a stance bound
   stays far below the swing), and never below ``min_scale`` (the lowest bound, for slow swings
   of ~1 rad/s whose neighbouring stances rest near 0.02 rad/s). A cycle that is not bounded by
   swings on both sides (the recording's ends, a long standstill) keeps the base bounds.
4. A gap between two stances where the foot turns about gravity without accelerating is a pivot
   on the ground (turning on the spot, the shuffles of a U-turn), not a step: it is bridged.
   While the foot pivots, its sensor moves by about its distance from the pivot point times the
   angle turned (~0.1 m for a quarter turn): the zero-velocity update there costs about what
   free integration would.
5. :func:`footnav.detectors.threshold.stance_result` drops stances shorter than ``min_stance_s``,
   bridges swings shorter than ``min_swing_s`` and marks ``foot_flat`` / ``heel_off``.

Online (:mod:`footnav.pipeline.online`, ``latency_s`` = ``online_lookahead_s`` +
``online_block_s`` = 2.75 s) the detector runs on a window of ~10 s ending 2.5 s past the
decisions it makes final. Its decisions are the offline ones except where the window cannot see
what the whole walk shows: a gait cycle longer than the look-ahead (taken with the base bounds,
as a recording's last cycle), and the typical stride (``stride_fraction``), which is that of the
window's ~8 strides rather than the whole walk's. On the shared recordings 109 of 121 feet get
the offline mask; docs/online.md gives the others.

The result's ``score`` is ``s / scale`` (a sample is still when it is below 1), ``meta`` holds
the swing peaks, the typical stride, each cycle's scale and the pivots' start times.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from footnav.component import (
    MAX_ACC_MPS2,
    MAX_DURATION_S,
    MAX_RATE_RADPS,
    StanceDetector,
    require_in_range,
    require_non_negative,
    require_positive,
)
from footnav.nav.gait_cycles import SWING_ACC_MPS2, swing_peaks
from footnav.types import GRAVITY_MPS2, ImuData, StanceResult, stance_intervals
from footnav.nav.windows import centred_acc_magnitude_rms, centred_gyr_rms, window_samples
from footnav.detectors.threshold import clean_stance_mask, stance_result
from footnav.types._derived import row_norms, sharing
from footnav._numba import njit

__all__ = ["AdaptiveDetector"]


class AdaptiveDetector(StanceDetector):
    """Stance where the windowed motion is below a bound set per gait cycle (footnav's default).

    Parameters
    ----------
    window_s : float
        Window of the stance statistic, s (as ``threshold``).
    gyr_threshold_radps : float
        Base bound on the window's RMS angular rate, rad/s: the bound of a walking foot.
    acc_tolerance_mps2 : float
        Base bound on the window's RMS of ``|f| - g``, m/s^2; scaled with the gyro bound.
    stance_factor : float
        A cycle's bound is at least this multiple of its stillest window's statistic.
    swing_fraction : float
        A cycle's gyro bound is at most this fraction of the lower of its two swing peaks.
    min_scale : float
        A cycle's bounds are never below this fraction of the base bounds.
    swing_window_s : float
        RMS window of the swing peaks, s.
    min_swing_peak_radps : float
        A swing peaks above this RMS angular rate, rad/s.
    swing_prominence : float
        A swing peak's prominence is at least this share of its height.
    min_stride_s : float
        Swing peaks closer than this are one swing, s.
    stride_fraction : float
        Swing peaks closer than this fraction of the recording's typical stride are one swing.
    base_stance_s : float
        A cycle where the foot stands this long under the base bounds keeps them, s.
    min_stance_s : float
        Stance runs shorter than this are discarded, s.
    min_swing_s : float
        Gaps shorter than this between two stance runs are bridged (one stance), s.
    pivot_yaw_share : float
        A gap between two stances where at least this share of the squared angular rate turns
        about gravity is a pivot on the ground, and bridged; 1 never bridges.
    pivot_acc_mps2 : float
        ... and where the RMS of ``|f| - g`` stays below this, m/s^2.
    max_pivot_s : float
        ... and which is shorter than this, s.

    Notes
    -----
    Defaults: the base bounds, window and durations are ``threshold``'s (so ordinary walking is
    detected as before). ``base_stance_s = 0.1``: a walking foot stands still for 0.3-0.6 s, a
    running one never under the base bounds; raising the bounds of a cycle that has a stance
    under them widens it into the heel's roll (gaitdriven_dev walking trials 0.24-0.42 m footprint
    RMSE with, 0.33-0.68 m without this rule). ``stance_factor = 3`` takes the stillest ~0.1-0.2 s of a running stance
    (its statistic rises steeply at heel strike and toe off); ``swing_fraction = 0.3`` keeps every
    bound below the dip of the angular rate in mid-swing (>= 35 % of the swing peak on the
    IPOL and pyshoe recordings); ``min_scale = 0.3`` (0.15 rad/s) separates a crawling foot's
    ~1 rad/s swings from its ~0.05 rad/s rests. The swing-peak window (0.2 s) is about half a
    swing: 0.3 s merges the swings of running into one hump, 0.15 s splits walking swings in two.
    These were chosen for physical reasons and checked on the simulator and on every shared
    recording; docs/accuracy.md gives the figures.

    Examples
    --------
    >>> stance = AdaptiveDetector().detect(imu)  # doctest: +SKIP
    >>> stance.meta["cycle_scale"]  # each gait cycle's bound / the base bound  # doctest: +SKIP
    """

    name = "adaptive"
    #: Online (:mod:`footnav.pipeline.online`) a sample's decision is taken on a window reaching
    #: this far past it (s): its cycle's bound needs the swing peak ending the cycle (one stride
    #: ahead, 0.7-1.3 s in the shared walks and runs), that peak's selection the samples up to
    #: ``stride_fraction`` of a stride after it (a higher peak closer than that removes it) and
    #: its prominence the foot's next rest (~0.3 s). A cycle longer than this is decided online
    #: as a recording's last cycle is: with the base bounds.
    online_lookahead_s = 2.5
    #: Online, decisions become final in blocks of this many seconds, each taken on the window
    #: ending ``online_lookahead_s`` after the block: the windows, hence the decisions, are the
    #: same however the samples are chunked, and a one-sample push costs no detection.
    online_block_s = 0.25
    #: Online, the first decisions wait until this much of the walk is in (s): the typical stride
    #: (``stride_fraction``) is then taken over ~8 strides, as offline over the whole walk.
    online_startup_s = 10.0
    #: Online decisions are not always the offline ones: the typical stride of a window of
    #: ~10 s is not the whole walk's (docs/online.md gives how often they differ), so a stream's
    #: ``close`` reruns the offline pipeline on the whole input.
    online_exact = False

    @property
    def latency_s(self) -> float:
        """How long after a sample arrives its decision is final online, s: the look-ahead and a
        block (after the start-up, ``online_startup_s``)."""
        return float(self.online_lookahead_s + self.online_block_s)

    def __init__(
        self,
        *,
        window_s: float = 0.04,
        gyr_threshold_radps: float = 0.5,
        acc_tolerance_mps2: float = 1.5,
        stance_factor: float = 3.0,
        swing_fraction: float = 0.3,
        min_scale: float = 0.3,
        swing_window_s: float = 0.2,
        min_swing_peak_radps: float = 0.6,
        swing_prominence: float = 0.4,
        min_stride_s: float = 0.3,
        stride_fraction: float = 0.6,
        base_stance_s: float = 0.1,
        min_stance_s: float = 0.05,
        min_swing_s: float = 0.2,
        pivot_yaw_share: float = 0.9,
        pivot_acc_mps2: float = SWING_ACC_MPS2,
        max_pivot_s: float = 1.5,
    ) -> None:
        self.window_s = window_s
        self.gyr_threshold_radps = gyr_threshold_radps
        self.acc_tolerance_mps2 = acc_tolerance_mps2
        self.stance_factor = stance_factor
        self.swing_fraction = swing_fraction
        self.min_scale = min_scale
        self.swing_window_s = swing_window_s
        self.min_swing_peak_radps = min_swing_peak_radps
        self.swing_prominence = swing_prominence
        self.min_stride_s = min_stride_s
        self.stride_fraction = stride_fraction
        self.base_stance_s = base_stance_s
        self.min_stance_s = min_stance_s
        self.min_swing_s = min_swing_s
        self.pivot_yaw_share = pivot_yaw_share
        self.pivot_acc_mps2 = pivot_acc_mps2
        self.max_pivot_s = max_pivot_s

    def validate_params(self) -> None:
        # Upper bounds (footnav.component): durations multiply into window lengths in
        # samples, rates and accelerations overflow when squared; the unitless factors and
        # fractions are kept at 1000x / 1000 their sensible range, where every sample is still
        # or none is.
        require_positive(self, "window_s", "swing_window_s", "min_stride_s", high=MAX_DURATION_S)
        require_positive(self, "gyr_threshold_radps", "min_swing_peak_radps", high=MAX_RATE_RADPS)
        require_positive(self, "acc_tolerance_mps2", high=MAX_ACC_MPS2)
        require_positive(self, "stance_factor", "swing_fraction", high=1e3)
        require_positive(self, "min_scale", high=1.0)
        require_non_negative(self, "swing_prominence", "stride_fraction", high=1e3)
        require_non_negative(self, "base_stance_s", "min_stance_s", "min_swing_s", "max_pivot_s", high=MAX_DURATION_S)
        require_non_negative(self, "pivot_acc_mps2", high=MAX_ACC_MPS2)
        require_in_range(self, "pivot_yaw_share", low=0.0, high=1.0)

    def detect(self, imu: ImuData) -> StanceResult:
        """Stance mask, ``foot_flat`` / ``heel_off`` events, ``score`` = statistic / cycle bound."""
        self.validate_params()
        # the statistic, the swing peaks and the pivots share |w|^2 and |f| (and, in a pipeline
        # run, the stance self-check shares the swing peaks): one pass each over the samples
        with sharing():
            return self._detect(imu)

    def _detect(self, imu: ImuData) -> StanceResult:
        n, rate = imu.n_samples, imu.rate_hz
        win = window_samples(self.window_s, rate, n)
        stat = np.maximum(
            centred_gyr_rms(imu.gyr, win) / self.gyr_threshold_radps,
            centred_acc_magnitude_rms(imu.acc, win) / self.acc_tolerance_mps2,
        )
        peaks = swing_peaks(
            imu.gyr,
            rate,
            window_s=self.swing_window_s,
            min_peak_radps=self.min_swing_peak_radps,
            rel_prominence=self.swing_prominence,
            min_stride_s=self.min_stride_s,
            stride_fraction=self.stride_fraction,
        )
        idx, height = peaks.index, peaks.height_radps
        scale = np.ones(n)
        cycle_scale = np.ones(max(len(idx) - 1, 0))
        if len(idx) >= 2:
            stillest = np.minimum.reduceat(stat, idx)[:-1]  # of each cycle idx[k] .. idx[k+1] - 1
            ceiling = self.swing_fraction * np.minimum(height[:-1], height[1:]) / self.gyr_threshold_radps
            raised = np.maximum(self.stance_factor * stillest, 1.0)
            # a cycle whose foot stands still under the base bounds keeps them
            raised[_longest_run_per_cycle(stat < 1.0, idx) >= self.base_stance_s * rate] = 1.0
            cycle_scale = np.maximum(np.minimum(raised, ceiling), self.min_scale)
            scale[idx[0] : idx[-1]] = np.repeat(cycle_scale, np.diff(idx))
        mask = stat < scale
        pivots = self._bridge_pivots(imu, clean_stance_mask(mask, rate, self.min_stance_s, self.min_swing_s))
        meta: dict[str, Any] = {
            "detector": self.describe(),
            "window_samples": win,
            "rate_hz": rate,
            "swing_peaks": peaks.index,
            "stride_s": peaks.stride_s,
            "cycle_scale": cycle_scale,
            "pivots_s": imu.t[pivots[:, 0]] if len(pivots) else np.empty(0),
        }
        for a, b in pivots:
            mask[a:b] = True
        return stance_result(mask, rate, self.min_stance_s, self.min_swing_s, stat / scale, meta)

    def _bridge_pivots(self, imu: ImuData, mask: np.ndarray) -> np.ndarray:
        """(start, stop) of the gaps between two stances where the foot pivots on the ground.

        In a turn on the spot the foot stays down and turns about the vertical, at up to 5-10
        rad/s: a swing by its angular rate, a stance by everything else. Such a gap turns about
        gravity (the direction of the specific force in the preceding stance, body frame) for at
        least ``pivot_yaw_share`` of its squared angular rate, where a swing turns mostly in
        pitch (< 0.2 on the IPOL and pyshoe recordings), and its ``|f| - g`` stays small (RMS
        below ``pivot_acc_mps2``; a swing's is 5-20 m/s^2).
        """
        runs = stance_intervals(mask)
        if self.pivot_yaw_share >= 1.0 or len(runs) < 2:
            return np.empty((0, 2), dtype=np.int64)
        a1, b0 = runs[:-1, 1], runs[1:, 0]
        # the preceding stance's mean specific force: "up" in the body frame
        c = _prefix_sums_at(imu.acc, runs[:, :2].ravel())
        up = c[1::2][:-1] - c[0::2][:-1]
        up /= np.maximum(np.linalg.norm(up, axis=1, keepdims=True), 1e-12)
        # every gap at once: its samples in order, each with its gap's "up", summed per gap
        length = b0 - a1
        in_gap = np.flatnonzero(~mask[a1[0] : b0[-1]]) + a1[0]
        first = np.concatenate([[0], np.cumsum(length)[:-1]])
        w = imu.gyr[in_gap]
        total = np.add.reduceat(np.einsum("ij,ij->i", w, w), first)
        yaw = np.add.reduceat(np.einsum("ij,ij->i", w, np.repeat(up, length, axis=0)) ** 2, first)
        acc_dev2 = np.add.reduceat((row_norms(imu.acc)[in_gap] - GRAVITY_MPS2) ** 2, first) / length
        pivot = (
            ((b0 - a1) <= self.max_pivot_s * imu.rate_hz)
            & (total > 0)
            & (yaw >= self.pivot_yaw_share * total)
            & (acc_dev2 < self.pivot_acc_mps2**2)
        )
        return np.stack([a1[pivot], b0[pivot]], axis=1).astype(np.int64)


def _longest_run_per_cycle(still: np.ndarray, idx: np.ndarray) -> np.ndarray:
    """Longest run of ``still`` (samples) inside each cycle ``idx[k] .. idx[k+1] - 1``, (K-1,)."""
    runs = stance_intervals(still[idx[0] : idx[-1]]) + idx[0]
    longest = np.zeros(len(idx) - 1, dtype=np.int64)
    if len(runs):
        # a run crossing a swing peak is cut there: only the part inside each cycle counts
        k = np.searchsorted(idx, runs[:, 0], side="right") - 1
        np.maximum.at(longest, k, np.minimum(runs[:, 1], idx[k + 1]) - runs[:, 0])
    return longest


@njit(cache=True)
def _prefix_sums_at(x: np.ndarray, at: np.ndarray) -> np.ndarray:
    """``cumulative(x)[at]`` for increasing ``at`` (M,): rows (M, 3), without the (N + 1, 3) array.

    The running sum adds the rows in order as ``np.cumsum`` does (the first row taken as it is),
    so every value is bit-identical to the cumulative sum's.
    """
    out = np.zeros((len(at), x.shape[1]))
    s = np.zeros(x.shape[1])
    j = 0  # rows summed so far
    for m in range(len(at)):
        while j < at[m]:
            for k in range(x.shape[1]):
                s[k] = x[j, k] if j == 0 else s[k] + x[j, k]
            j += 1
        for k in range(x.shape[1]):  # not out[m] = s: that compiles numba's shape-mismatch error
            out[m, k] = s[k]
    return out
