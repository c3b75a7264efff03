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
5. The cleaning of :func:`footnav.detectors.threshold.stance_result` drops stances shorter than ``min_stance_s``,
   bridges swings shorter than ``min_swing_s`` and marks ``foot_flat`` / ``heel_off``.

Online (:mod:`footnav.pipeline.online`, ``latency_s`` = ``online_lookahead_s`` +
``online_block_s`` = 2.75 s) the detector runs on a window of ~10 s ending 2.5 s past the
decisions it makes final. Its decisions are the offline ones except where the window cannot see
what the whole walk shows: a gait cycle longer than the look-ahead (taken with the base bounds,
as a recording's last cycle), and the typical stride (``stride_fraction``), which is that of the
window's ~8 strides rather than the whole walk's. On the shared recordings 109 of 121 feet get
the offline mask; docs/online.md gives the others. A stream runs the windows through
:class:`AdaptiveWindows` (:meth:`AdaptiveDetector.online_windows`): the same rule
(:func:`_decide`, compiled, which ``detect`` runs too) on per-sample quantities kept as the
samples arrive, the parameters checked once.

The result's ``score`` is ``s / scale`` (a sample is still when it is below 1), ``meta`` holds
the swing peaks, the typical stride, each cycle's scale and the pivots' start times.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from footnav._numba import njit
from footnav.core.component import StanceDetector
from footnav.core.parameters import (
    MAX_ACC_MPS2,
    MAX_DURATION_S,
    MAX_RATE_RADPS,
    require_in_range,
    require_non_negative,
    require_positive,
)
from footnav.core.types import GRAVITY_MPS2, ImuData, StanceResult
from footnav.core.types._arrays import _readonly
from footnav.core.types._derived import sharing
from footnav.detectors.threshold import _clean_runs, window_events
from footnav.nav.gait_cycles import MAX_STRIDE_S, SWING_ACC_MPS2, select_swing_peaks, swing_peaks
from footnav.nav.windows import (
    acc_dev_sq,
    acc_dev_sq_cumulative,
    centred_rms,
    cumulative_sum,
    gyr_sq,
    gyr_sq_cumulative,
    pairwise_sum,
    true_runs,
    window_samples,
)

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
        """Check every parameter (:meth:`footnav.core.component.Component.validate_params`); raises
        InvalidParameterError."""
        # Upper bounds (footnav.core.component): durations multiply into window lengths in
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
        stat = _statistic(
            gyr_sq_cumulative(imu.gyr),
            acc_dev_sq_cumulative(imu.acc),
            win,
            self.gyr_threshold_radps,
            self.acc_tolerance_mps2,
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
        mask, scale, cycle_scale, pivots = self._decide(stat, peaks.index, peaks.height_radps, imu.acc, imu.gyr, rate)
        meta: dict[str, Any] = {
            "detector": self.describe(),
            "window_samples": win,
            "rate_hz": rate,
            "swing_peaks": peaks.index,
            "stride_s": peaks.stride_s,
            "cycle_scale": cycle_scale,
            "pivots_s": imu.t[pivots[:, 0]] if len(pivots) else np.empty(0),
        }
        return StanceResult(mask=mask, events=window_events(mask), score=stat / scale, meta=meta)

    def _decide(
        self, stat: np.ndarray, peaks: np.ndarray, height: np.ndarray, acc: np.ndarray, gyr: np.ndarray, rate: float
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Steps 3-5 (the rule, offline and online): the cleaned mask (N,), each sample's scale
        (N,), each cycle's scale (K-1,) and the pivots' (start, stop), from the statistic and the
        swing peaks (sample index, height rad/s)."""
        return _decide(
            stat,
            np.asarray(peaks, dtype=np.int64),
            height,
            _readonly(acc),  # a stream's window arrays too: one compiled signature
            _readonly(gyr),
            self.gyr_threshold_radps,
            self.stance_factor,
            self.swing_fraction,
            self.min_scale,
            self.base_stance_s * rate,
            round(self.min_stance_s * rate),
            round(self.min_swing_s * rate),
            self.pivot_yaw_share,
            self.pivot_acc_mps2**2,
            self.max_pivot_s * rate,
        )

    def online_windows(self) -> AdaptiveWindows | None:
        """The detector for a stream's windows (:mod:`footnav.pipeline.online_foot`), its
        parameters checked once (when the stream starts): per-sample quantities as the samples
        arrive, one window's mask. None for a subclass with its own ``detect``."""
        if type(self).detect is not AdaptiveDetector.detect or type(self)._detect is not AdaptiveDetector._detect:
            return None
        self.validate_params()
        return AdaptiveWindows(self)


class AdaptiveWindows:
    """:class:`AdaptiveDetector` on a stream's detection windows, the mask of :meth:`detect`
    without its per-window costs.

    A stream (:mod:`footnav.pipeline.online_foot`) keeps each sample's ``|w|^2`` and
    ``(|f| - g)^2`` (:meth:`features`, once per sample as it arrives) and asks for the mask of
    each window of them (:meth:`mask`): the rule is the detector's own (:meth:`AdaptiveDetector._decide`)
    on the statistic and swing peaks of the window. Those are taken from the window's own
    cumulative sums, as :meth:`AdaptiveDetector.detect` on the window takes them: a sum kept from
    the stream's start would change their last bits (and, over hours, lose ~1e-7 of a stance's
    statistic), hence possibly a decision; it costs one pass over the window's ~1000 samples.
    """

    #: Per-sample quantities :meth:`features` gives.
    n_features = 2

    def __init__(self, detector: AdaptiveDetector) -> None:
        self.detector = detector

    @staticmethod
    def features(acc: np.ndarray, gyr: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``|w|^2`` and ``(|f| - g)^2`` of each sample, (M,) each: what the windows sum."""
        return gyr_sq(gyr), acc_dev_sq(acc)

    def mask(
        self, acc: np.ndarray, gyr: np.ndarray, gyr_sq_w: np.ndarray, acc_dev_sq_w: np.ndarray, rate: float
    ) -> np.ndarray:
        """The stance mask of :meth:`AdaptiveDetector.detect` on the window of these samples,
        (N,) bool, at sampling rate ``rate`` (Hz); the last two arrays are :meth:`features`'."""
        d, n = self.detector, len(acc)
        stat, energy = _window_statistics(
            gyr_sq_w,
            acc_dev_sq_w,
            window_samples(d.window_s, rate, n),
            window_samples(d.swing_window_s, rate, n),
            d.gyr_threshold_radps,
            d.acc_tolerance_mps2,
        )
        idx, _ = select_swing_peaks(
            energy, rate, d.min_swing_peak_radps, d.swing_prominence, d.min_stride_s, d.stride_fraction, MAX_STRIDE_S
        )
        return d._decide(stat, idx, energy[idx], acc, gyr, rate)[0]


@njit(cache=True)
def _statistic(gyr_sq_c, acc_dev_sq_c, win, gyr_threshold, acc_tolerance):
    """``s`` of every sample (N,) from the cumulative sums of ``|w|^2`` and ``(|f| - g)^2`` (N + 1,)."""
    return np.maximum(centred_rms(gyr_sq_c, win) / gyr_threshold, centred_rms(acc_dev_sq_c, win) / acc_tolerance)


@njit(cache=True)
def _window_statistics(gyr_sq_w, acc_dev_sq_w, win, swing_win, gyr_threshold, acc_tolerance):
    # a window's statistic and swing energy from its own cumulative sums, in one call
    c = cumulative_sum(gyr_sq_w)
    return _statistic(c, cumulative_sum(acc_dev_sq_w), win, gyr_threshold, acc_tolerance), centred_rms(c, swing_win)


@njit(cache=True)
def _decide(stat, peaks, height, acc, gyr, gyr_threshold, stance_factor, swing_fraction, min_scale,
            base_stance, min_stance, min_swing, pivot_yaw_share, pivot_acc_sq, max_pivot):  # fmt: skip
    # AdaptiveDetector._decide, in one compiled call: online it runs on every window, where the
    # three dozen numpy calls it took cost far more than the work (durations in samples here)
    n = len(stat)
    scale = np.ones(n)
    k_cycles = max(len(peaks) - 1, 0)
    cycle_scale = np.ones(k_cycles)
    if len(peaks) >= 2:
        longest = _longest_run_per_cycle(stat, peaks)
        for k in range(k_cycles):
            a, b = peaks[k], peaks[k + 1]
            stillest = stat[a]
            for i in range(a + 1, b):
                stillest = min(stillest, stat[i])
            ceiling = swing_fraction * min(height[k], height[k + 1]) / gyr_threshold
            raised = max(stance_factor * stillest, 1.0)
            if longest[k] >= base_stance:  # the foot stands still under the base bounds: they stay
                raised = 1.0
            cycle_scale[k] = max(min(raised, ceiling), min_scale)
            for i in range(a, b):
                scale[i] = cycle_scale[k]
    mask = stat < scale
    clean = mask.copy()
    _clean_runs(clean, min_stance, min_swing)
    pivots = _pivots(clean, acc, gyr, pivot_yaw_share, pivot_acc_sq, max_pivot)
    for j in range(len(pivots)):
        for i in range(pivots[j, 0], pivots[j, 1]):
            mask[i] = True
    _clean_runs(mask, min_stance, min_swing)  # stance_result's cleaning
    return mask, scale, cycle_scale, pivots


@njit(cache=True)
def _longest_run_per_cycle(stat, idx):
    """Longest run of ``stat < 1`` (samples) in each cycle ``idx[k] .. idx[k+1] - 1``, (K-1,).

    The runs are those of ``stat[idx[0]:idx[-1]] < 1``: a run crossing a swing peak counts,
    cut there, for the cycle it starts in."""
    still = stat < 1.0
    runs = true_runs(still, idx[0], idx[-1])
    longest = np.zeros(len(idx) - 1, dtype=np.int64)
    k = 0
    for r in range(len(runs)):
        while idx[k + 1] <= runs[r, 0]:
            k += 1
        longest[k] = max(longest[k], min(runs[r, 1], idx[k + 1]) - runs[r, 0])
    return longest


@njit(cache=True)
def _pivots(mask, acc, gyr, pivot_yaw_share, pivot_acc_sq, max_pivot):
    """(start, stop) of the gaps between two stances where the foot pivots on the ground.

    In a turn on the spot the foot stays down and turns about the vertical, at up to 5-10
    rad/s: a swing by its angular rate, a stance by everything else. Such a gap turns about
    gravity (the direction of the specific force in the preceding stance, body frame) for at
    least ``pivot_yaw_share`` of its squared angular rate, where a swing turns mostly in
    pitch (< 0.2 on the IPOL and pyshoe recordings), and its ``|f| - g`` stays small (RMS
    below ``pivot_acc_mps2``; a swing's is 5-20 m/s^2). Each gap's sums are np.add.reduce's
    of its samples' terms (the first term, then the pairwise sum of the others), and each
    term numpy's (``np.einsum("ij,ij->i")`` sums the products of a row as (x + z) + y).
    """
    runs = true_runs(mask, np.int64(0), len(mask))  # an int64 start, as _decide's: one compilation
    n_gaps = len(runs) - 1
    if pivot_yaw_share >= 1.0 or n_gaps < 1:
        return np.empty((0, 2), dtype=np.int64)
    c = _prefix_sums_at(acc, runs.ravel())  # the cumulative sum at each run's start and stop
    out = np.empty((n_gaps, 2), dtype=np.int64)
    m = 0
    longest = 0
    for g in range(n_gaps):
        longest = max(longest, runs[g + 1, 0] - runs[g, 1])
    total_t, yaw_t, dev_t = np.empty(longest), np.empty(longest), np.empty(longest)
    for g in range(n_gaps):
        a1, b0 = runs[g, 1], runs[g + 1, 0]
        length = b0 - a1
        if not length <= max_pivot:  # the test's first condition: a longer gap needs none of its sums
            continue
        # the preceding stance's mean specific force: "up" in the body frame
        u0, u1, u2 = c[2 * g + 1, 0] - c[2 * g, 0], c[2 * g + 1, 1] - c[2 * g, 1], c[2 * g + 1, 2] - c[2 * g, 2]
        norm = max(np.sqrt((u0 * u0 + u1 * u1) + u2 * u2), 1e-12)
        u0, u1, u2 = u0 / norm, u1 / norm, u2 / norm
        for i in range(length):
            w0, w1, w2 = gyr[a1 + i, 0], gyr[a1 + i, 1], gyr[a1 + i, 2]
            total_t[i] = (w0 * w0 + w2 * w2) + w1 * w1
            y = (w0 * u0 + w2 * u2) + w1 * u1
            yaw_t[i] = y * y
        total = total_t[0] + pairwise_sum(total_t, 1, length - 1)
        yaw = yaw_t[0] + pairwise_sum(yaw_t, 1, length - 1)
        if not (total > 0 and yaw >= pivot_yaw_share * total):  # a swing turns in pitch: no |f| needed
            continue
        for i in range(length):
            f0, f1, f2 = acc[a1 + i, 0], acc[a1 + i, 1], acc[a1 + i, 2]
            dev = np.sqrt((f0 * f0 + f1 * f1) + f2 * f2) - GRAVITY_MPS2
            dev_t[i] = dev * dev
        acc_dev2 = (dev_t[0] + pairwise_sum(dev_t, 1, length - 1)) / length
        if acc_dev2 < pivot_acc_sq:
            out[m, 0] = a1
            out[m, 1] = b0
            m += 1
    return out[:m]


@njit(cache=True)
def _prefix_sums_at(x: np.ndarray, at: np.ndarray) -> np.ndarray:
    """``cumulative(x)[at]`` of a (N, 3) ``x`` for increasing ``at`` (M,): rows (M, 3), without
    the (N + 1, 3) array.

    The running sum adds the rows in order as ``np.cumsum`` does (the first row taken as it is),
    so every value is bit-identical to the cumulative sum's; the three sums are kept in
    registers (not an array, whose store and load would lengthen each add's chain).
    """
    out = np.zeros((len(at), 3))
    s0, s1, s2 = 0.0, 0.0, 0.0
    j = 0  # rows summed so far
    for m in range(len(at)):
        stop = at[m]
        if j == 0 and stop > 0:
            s0, s1, s2 = x[0, 0], x[0, 1], x[0, 2]
            j = 1
        while j < stop:
            s0 += x[j, 0]
            s1 += x[j, 1]
            s2 += x[j, 2]
            j += 1
        out[m, 0], out[m, 1], out[m, 2] = s0, s1, s2
    return out
