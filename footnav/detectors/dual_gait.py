"""Dual-gait stance detection: both feet analysed together (Zhao et al. 2019, Sec. III-A).

Zhao, Wang, Qiu et al., "Heading drift reduction for foot-mounted inertial navigation
system via multi-sensor fusion and dual-gait analysis", IEEE Sensors J. 19(19, 2019), Sec. III-A,
builds the gait phases of each foot from *both* feet:

* Heel strike by peak detection: "The measurements exhibit sudden spikes when the HS events occur,
  especially for the acceleration ... A peak detection method is used to detect the HS events".
* Zero-velocity (ZUPT) periods by a flat zone: "The HS event is followed by the FF event, from
  which the foot is flat on the ground until subsequent HO event. During this period, the angular
  rate is near to zero, while the acceleration becomes constant and remains around gravity ...
  a flat zone detection method is used to delimit the ZUPT periods."
* The dual-gait rule: "Since the HO events of rear foot always coincide with the HS events of the
  front foot, this paper detects the gait phases using the data from both feet jointly through
  dual-gait analysis. Specifically, a stance phase starts with the HS event of supporting foot, but
  ends with the HS event of contralateral foot, and vice versa."

footnav's reading, step by step (:class:`DualGaitDetector`):

1. **Flat zone** of each foot: the two-condition test of the ``threshold`` detector (windowed RMS
   angular rate below ``gyr_threshold_radps`` and windowed RMS of ``|f| - g`` below
   ``acc_tolerance_mps2``), runs shorter than ``min_flat_s`` dropped, gaps shorter than
   ``min_swing_s`` bridged.
2. **Heel strikes** of each foot: ``scipy.signal.find_peaks`` on the specific-force norm ``|f|``
   (m/s^2) with a minimum height ``hs_min_acc_mps2`` and a minimum distance ``hs_min_interval_s``
   between peaks; a peak is a heel strike when a flat zone starts within ``hs_search_s`` after it
   (the paper: "The HS event is followed by the FF event"), the last such peak before that flat zone.
   A flat zone at the very start of the recording has no heel strike (the walker was standing).
3. **Support intervals** (the paper's dual-gait stance phase) of a foot: from each of its heel
   strikes to the *contralateral* foot's next heel strike. The interval also ends at the foot's
   own next heel strike (so a missed contralateral heel strike cannot make one interval span two
   steps) and, after the last contralateral heel strike, at the end of the recording.
4. **ZUPT mask** = the flat zone inside the support intervals (``zupt_rule="clip"``, the default):
   the paper's stance phase "ends with the HS event of contralateral foot", and a zero-velocity
   update outside the stance phase would be applied to a foot that the rule says has started its
   push-off. ``zupt_rule="gate"`` reads "a flat zone detection method is used to delimit the ZUPT
   periods" as: the flat zone sets the limits, the dual-gait stance only decides which flat zones
   are stances (each flat zone that starts inside a support interval is kept whole).
5. **Standing** (footnav's addition; the paper's rule describes walking): a flat zone during which
   the other foot is also in a flat zone for at least ``standing_s`` is the walker standing on both
   feet -- neither foot is about to swing -- and is kept whole. Without this the standstill before
   the first step and after the last (the paper's own alignment standstill, Sec. V-A) and any stop
   in the walk would lose their zero-velocity updates. In walking the two feet's flat zones do not
   overlap (the rear foot's heel is off before the front foot is flat), so this never undoes step 4.

Events (sample indices of each foot): ``heel_strike`` (step 2), ``foot_flat`` / ``heel_off``
(first / last sample of each ZUPT run, where the foot stops / starts moving -- not at the
recording's ends), ``toe_off`` (the first peak of the angular-rate norm after each heel-off, before
the next heel strike: the push-off ends at the fastest toe-down rotation of the foot; on the gaitmap
recording it lies within 10 ms of the mocap toe-off on average). ``phases`` per sample:
``0`` single support (this foot on the ground, the other swinging), ``1`` double support (both feet
on the ground, standing included), ``2`` swing (from toe-off to the next heel strike).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, ClassVar, Literal, NoReturn

import numpy as np
from numpy.typing import NDArray

from footnav.core.component import StanceDetector
from footnav.core.errors import CompositionError, InvalidInputError
from footnav.core.parameters import (
    MAX_ACC_MPS2,
    MAX_DURATION_S,
    MAX_RATE_RADPS,
    require,
    require_non_negative,
    require_positive,
)
from footnav.core.types import ImuData, StanceResult, stance_intervals
from footnav.detectors.threshold import ThresholdDetector

if TYPE_CHECKING:
    from collections.abc import Mapping

__all__ = ["DualGaitDetector", "PHASE_NAMES", "ZUPT_RULES", "support_intervals"]

#: Names of the per-sample phase labels of the result (``StanceResult.phases``).
PHASE_NAMES = ("single_support", "double_support", "swing")
SINGLE_SUPPORT, DOUBLE_SUPPORT, SWING = range(len(PHASE_NAMES))

#: How the flat zone and the support intervals make the ZUPT mask (see the module docstring).
ZUPT_RULES = ("clip", "gate")

ZuptRule = Literal["clip", "gate"]

#: A toe-off peak of |w| must stand this far above its neighbouring valleys, rad/s: the push-off
#: turns the foot at several rad/s (gaitmap: 5-9 rad/s), sensor noise at rest is ~0.01 rad/s, so
#: this only rejects ripples on the slope of the push-off.
_TOE_OFF_MIN_PROMINENCE_RADPS = 1.0

#: Samples in the flat zone per foot and the feet's names, in detect_pair's order.
_FEET = ("left", "right")


def _at_times(mask: NDArray[np.bool_], t_from: NDArray[np.float64], t_to: NDArray[np.float64]) -> NDArray[np.bool_]:
    """``mask`` (sampled at ``t_from``) at the times ``t_to``: the latest sample at or before each
    time; False outside ``t_from``'s span (nothing is known there)."""
    idx = np.searchsorted(t_from, t_to, side="right") - 1
    inside = (idx >= 0) & (t_to <= t_from[-1])
    return inside & mask[np.clip(idx, 0, len(mask) - 1)]


def _interval_mask(starts: NDArray[np.int64], stops: NDArray[np.int64], n: int) -> NDArray[np.bool_]:
    """True on every ``[start, stop)``, by a difference array (intervals may touch or overlap)."""
    d = np.zeros(n + 1, dtype=np.int64)
    np.add.at(d, starts, 1)
    np.add.at(d, stops, -1)
    return np.cumsum(d[:n]) > 0


def _run_sums(x: NDArray[np.bool_], runs: NDArray[np.int64]) -> NDArray[np.int64]:
    """Number of True samples of ``x`` inside each ``[start, stop)`` of ``runs`` (K, 2)."""
    c = np.concatenate(([0], np.cumsum(x, dtype=np.int64)))
    return c[runs[:, 1]] - c[runs[:, 0]]


def support_intervals(
    t: NDArray[np.float64], heel_strike: NDArray[np.int64], t_contra_heel_strike: NDArray[np.float64]
) -> NDArray[np.int64]:
    """Support intervals of one foot, Zhao et al. (2019), Sec. III-A: each heel strike to the contralateral one.

    "a stance phase starts with the HS event of supporting foot, but ends with the HS event of
    contralateral foot". Interval k is ``[heel_strike[k], stop_k)`` with ``stop_k`` the first
    sample at or after the contralateral foot's first heel strike later than ``t[heel_strike[k]]``;
    it never runs past the foot's own next heel strike, and without a later contralateral heel
    strike it runs to the end of the recording.

    Parameters
    ----------
    t
        Sample times of the foot, s, (N,).
    heel_strike
        The foot's heel strikes, sample indices, increasing, (K,).
    t_contra_heel_strike
        The other foot's heel strikes as times on the same clock, s, increasing, (L,).

    Returns
    -------
    NDArray[np.int64]
        (K, 2) ``[start, stop)`` sample indices.
    """
    n = len(t)
    hs = np.asarray(heel_strike, dtype=np.int64)
    if len(hs) == 0:
        return np.empty((0, 2), dtype=np.int64)
    contra = np.asarray(t_contra_heel_strike, dtype=float)
    j = np.searchsorted(contra, t[hs], side="right")  # first contralateral HS after
    # (none at all: every interval runs to the foot's own next heel strike)
    t_stop = (
        np.where(j < len(contra), contra[np.minimum(j, len(contra) - 1)], np.inf)
        if len(contra)
        else np.full(len(hs), np.inf)
    )
    stop = np.searchsorted(t, t_stop, side="left")  # first own sample at or after it (n if none)
    stop = np.minimum(stop, np.append(hs[1:], n))
    return np.column_stack([hs, stop]).astype(np.int64)


class DualGaitDetector(StanceDetector):
    """Heel-strike peaks and flat zones of both feet; a stance ends at the other foot's heel strike.

    Zhao et al. (2019), Sec. III-A (Zhao et al. 2019): the heel strike (HS) of each foot is a peak of the
    specific-force norm, the zero-velocity period a flat zone (angular rate near zero, specific
    force near g), and "a stance phase starts with the HS event of supporting foot, but ends with
    the HS event of contralateral foot". The ZUPT mask is the flat zone inside that stance phase;
    the module docstring gives every step and what footnav adds (standstills). Needs both feet on
    one clock (``needs_two_feet``): call :meth:`detect_pair`, as the pipeline does.

    Parameters
    ----------
    window_s : float
        Window of the flat-zone statistics, s; W = window_s x rate, rounded to an odd number.
    gyr_threshold_radps : float
        Flat zone: the windowed RMS angular rate must be below this, rad/s.
    acc_tolerance_mps2 : float
        Flat zone: the windowed RMS of |f| - g must be below this, m/s^2.
    min_flat_s : float
        Flat zones (and ZUPT runs after the dual-gait rule) shorter than this are dropped, s.
    min_swing_s : float
        Gaps shorter than this between two flat zones are bridged (one flat zone), s.
    hs_min_acc_mps2 : float
        Minimum height of a heel-strike peak of |f|, m/s^2 (the impact spike; g is 9.81).
    hs_min_interval_s : float
        Minimum distance between two |f| peaks, s (find_peaks keeps the highest within it).
    hs_search_s : float
        A peak is a heel strike when a flat zone starts at most this long after it, s.
    standing_s : float
        A flat zone during which the other foot is flat this long is standing, kept whole, s.
    zupt_rule : str
        "clip": ZUPT = flat zone inside the support intervals (the paper's rule); "gate": each
        flat zone that starts inside a support interval, whole.

    Notes
    -----
    Support interval of foot A (the paper's stance phase; ``meta["support_intervals"]``)::

        [HS_A[k], min(first HS_B after HS_A[k], HS_A[k+1]))      (end of recording if none)

    ZUPT mask (``mask``): ``flat_A & (support_A | standing_A)`` with ``zupt_rule="clip"``.

    Defaults. The flat zone uses the ``threshold`` detector's tested bounds (0.04 s window, 0.5
    rad/s, 1.5 m/s^2, 0.2 s bridging). ``hs_min_acc_mps2 = 15`` (1.5 g): a heel strike's impact
    reaches 3-5 g on gaitmap's heel-mounted sensors; 1.5 g rejects the small bumps of a foot
    shuffling in place. ``hs_min_interval_s = 0.4``: the heel strikes of one foot are a stride
    apart (0.8-1.4 s walking), and within 0.4 s of an impact the impact is the highest peak.
    ``hs_search_s = 0.3``: the foot is flat 0.1-0.15 s after the heel strike (simulator 0.1 s,
    gaitmap 0.13 s median). ``standing_s = 0.5``: in walking the two flat zones never overlap;
    half a second of both feet flat is standing.

    Heel-strike timing: on gaitmap (heel-mounted NilsPods, mocap initial contact) the |f| spike
    comes 23 ms after the mocap contact on average (28 ms mean absolute). On the simulator (its
    4 g heel-strike impact) every heel strike is found at the true sample.

    Examples
    --------
    >>> rec = footnav.simulate("straight", distance_m=20.0)  # doctest: +SKIP
    >>> left, right = DualGaitDetector().detect_pair(rec.left, rec.right)  # doctest: +SKIP
    >>> left.events["heel_strike"], left.meta["support_intervals"]  # doctest: +SKIP
    """

    name = "dual-gait"
    needs_two_feet: ClassVar[bool] = True
    #: Online (:mod:`footnav.pipeline.online_pair`): both feet decided together in blocks of
    #: this length, s, each on a window of both feet reaching ``latency_s`` - ``online_block_s``
    #: past it.
    online_block_s: ClassVar[float] = 0.25
    #: Online decisions are those of a window of a few seconds: a stance the window cannot see
    #: the start of (one foot flat longer than the window's margin, the other moving) may differ
    #: from the whole recording's, so ``close()`` reruns offline.
    online_exact: ClassVar[bool] = False

    def __init__(
        self,
        *,
        window_s: float = 0.04,
        gyr_threshold_radps: float = 0.5,
        acc_tolerance_mps2: float = 1.5,
        min_flat_s: float = 0.05,
        min_swing_s: float = 0.2,
        hs_min_acc_mps2: float = 15.0,
        hs_min_interval_s: float = 0.4,
        hs_search_s: float = 0.3,
        standing_s: float = 0.5,
        zupt_rule: ZuptRule = "clip",
    ) -> None:
        self.window_s = window_s
        self.gyr_threshold_radps = gyr_threshold_radps
        self.acc_tolerance_mps2 = acc_tolerance_mps2
        self.min_flat_s = min_flat_s
        self.min_swing_s = min_swing_s
        self.hs_min_acc_mps2 = hs_min_acc_mps2
        self.hs_min_interval_s = hs_min_interval_s
        self.hs_search_s = hs_search_s
        self.standing_s = standing_s
        self.zupt_rule = zupt_rule

    # -- parameters ---------------------------------------------------------------------------
    def validate_params(self) -> None:
        """Check every parameter (:meth:`footnav.core.component.Component.validate_params`); raises
        InvalidParameterError."""
        # Upper bounds (footnav.core.component): durations multiply into sample counts,
        # thresholds overflow when squared.
        require_positive(self, "window_s", "hs_min_interval_s", "hs_search_s", "standing_s", high=MAX_DURATION_S)
        require_positive(self, "gyr_threshold_radps", high=MAX_RATE_RADPS)
        require_positive(self, "acc_tolerance_mps2", high=MAX_ACC_MPS2)
        require_non_negative(self, "min_flat_s", "min_swing_s", high=MAX_DURATION_S)
        require_non_negative(self, "hs_min_acc_mps2", high=MAX_ACC_MPS2)
        require(
            isinstance(self.zupt_rule, str) and self.zupt_rule in ZUPT_RULES,
            self,
            "zupt_rule",
            " or ".join(repr(r) for r in ZUPT_RULES),
        )

    @property
    def latency_s(self) -> float:
        """How long after a sample its decision is final online, s: a flat zone is known
        ``window_s / 2 + min_flat_s + min_swing_s`` after a sample (the ``threshold`` test, its
        short runs dropped and gaps bridged); a heel strike ``hs_search_s`` after its peak plus
        that (the flat zone it opens), a standing flat zone ``standing_s`` plus that; then two
        ``hs_min_interval_s``: a peak is a heel strike only if no higher peak within that
        distance survives find_peaks' rule, which a still higher one after that can undo (a
        longer chain of ever higher peaks is possible in principle: ``online_exact`` False);
        then the block (``online_block_s``)."""
        flat = self.window_s / 2 + self.min_flat_s + self.min_swing_s
        reach = max(self.hs_search_s, self.standing_s) + flat + 2 * self.hs_min_interval_s
        return float(reach + self.online_block_s)

    # -- action -------------------------------------------------------------------------------
    def detect(self, imu: ImuData) -> NoReturn:
        """Not available: the dual-gait rule needs the other foot. Raises CompositionError."""
        raise CompositionError(
            f"detector {self.name!r} needs both feet: a stance ends at the other foot's heel strike "
            "(Zhao et al. (2019), Sec. III-A); call detect_pair(left, right), or run a pipeline with right=..."
        )

    def detect_pair(self, left: ImuData, right: ImuData | None) -> tuple[StanceResult, StanceResult]:
        """Stance of both feet by dual-gait analysis (Zhao et al. (2019), Sec. III-A).

        Parameters
        ----------
        left, right
            The two feet's recordings on one clock (their time spans must overlap); each may have
            its own sampling rate.

        Returns
        -------
        tuple of StanceResult
            Left and right: ``mask`` the ZUPT samples; ``events`` ``heel_strike``, ``foot_flat``,
            ``heel_off``, ``toe_off``; ``phases`` (names in ``meta["phase_names"]``); ``score``
            the flat-zone statistic of the ``threshold`` detector (< 1 is flat, dimensionless);
            ``meta["support_intervals"]`` (K, 2) ``[start, stop)`` sample indices,
            ``meta["standing_intervals"]``, ``meta["flat_zones"]``.

        A recording without any flat zone gives an all-False mask and no events; one still
        throughout gives one stance over the whole recording and no heel strike.

        Raises
        ------
        CompositionError
            ``right`` is None.
        InvalidInputError
            The two feet's time spans do not overlap (not one clock).
        """
        self.validate_params()
        if right is None:
            self.detect(left)  # raises CompositionError with the reason
        if left.t[0] > right.t[-1] or right.t[0] > left.t[-1]:
            raise InvalidInputError(
                f"the feet's recordings do not overlap in time (left {left.t[0]:.6g} to {left.t[-1]:.6g} s, "
                f"right {right.t[0]:.6g} to {right.t[-1]:.6g} s); dual-gait analysis needs both feet on one "
                "clock: give both time stamps from the same clock (or shift one onto the other's)",
                field="t",
            )
        imus = {"left": left, "right": right}
        flats, hs, support, masks, standing = self._rule(imus)
        toe_off = {foot: self._toe_offs(imus[foot], masks[foot], hs[foot]) for foot in _FEET}
        swings = {foot: self._swing_mask(imus[foot].n_samples, hs[foot], toe_off[foot], masks[foot]) for foot in _FEET}
        out = []
        for foot, other in zip(_FEET, _FEET[::-1]):
            imu, mask = imus[foot], masks[foot]
            other_swing = _at_times(swings[other], imus[other].t, imu.t)
            phases = np.where(swings[foot], SWING, np.where(other_swing, SINGLE_SUPPORT, DOUBLE_SUPPORT)).astype(
                np.int64
            )
            runs = stance_intervals(mask)
            out.append(
                StanceResult(
                    mask=mask,
                    events={
                        "heel_strike": hs[foot],
                        # where the foot stops / starts moving, not the recording's own ends
                        "foot_flat": runs[runs[:, 0] > 0, 0],
                        "heel_off": runs[runs[:, 1] < imu.n_samples, 1] - 1,
                        "toe_off": toe_off[foot],
                    },
                    phases=phases,
                    score=flats[foot].score,
                    meta={
                        "detector": self.describe(),
                        "foot": foot,
                        "rate_hz": imu.rate_hz,
                        "phase_names": PHASE_NAMES,
                        "support_intervals": support[foot],
                        "standing_intervals": standing[foot],
                        "flat_zones": flats[foot].intervals,
                        "zupt_rule": self.zupt_rule,
                    },
                )
            )
        return out[0], out[1]

    def window_masks(self, left: ImuData | None, right: ImuData | None) -> dict[str, NDArray[np.bool_]]:
        """The ZUPT masks of :meth:`detect_pair` alone, for windows of a live stream
        (:mod:`footnav.pipeline.online_pair`); a foot given as None has no samples in the window
        (as offline, where one foot's recording starts later or ends earlier): the other's
        stances are then its own heel strikes' support intervals."""
        return self._rule({"left": left, "right": right})[3]

    def _rule(self, imus: Mapping[str, ImuData | None]) -> tuple[dict, dict, dict, dict, dict]:
        """Steps 1-5 on the feet present in ``imus``: flat zones, heel strikes, support
        intervals, ZUPT masks and standing intervals, per foot."""
        given = {foot: imu for foot in _FEET if (imu := imus[foot]) is not None}
        present = list(given)
        flats = {foot: self._flat_zone(given[foot]) for foot in present}
        hs = {foot: self._heel_strikes(given[foot], flats[foot]) for foot in present}
        none = np.empty(0)
        support, masks, standing = {}, {}, {}
        for foot, other in zip(_FEET, _FEET[::-1]):
            if foot not in present:
                continue
            imu, there = given[foot], other in present
            support[foot] = support_intervals(imu.t, hs[foot], given[other].t[hs[other]] if there else none)
            masks[foot], standing[foot] = self._zupt_mask(
                imu,
                flats[foot].mask,
                support[foot],
                given[other] if there else None,
                flats[other].mask if there else None,
            )
        return flats, hs, support, masks, standing

    # -- steps ----------------------------------------------------------------------------------
    def _flat_zone(self, imu: ImuData) -> StanceResult:
        """Step 1: angular rate near zero and |f| near g (the threshold detector's test)."""
        return ThresholdDetector(
            window_s=self.window_s,
            gyr_threshold_radps=self.gyr_threshold_radps,
            acc_tolerance_mps2=self.acc_tolerance_mps2,
            combine="center",
            min_stance_s=self.min_flat_s,
            min_swing_s=self.min_swing_s,
        ).detect(imu)

    def _heel_strikes(self, imu: ImuData, flat: StanceResult) -> NDArray[np.int64]:
        """Step 2: the last |f| peak at most ``hs_search_s`` before each flat zone starts."""
        acc_norm = np.linalg.norm(imu.acc, axis=1)
        rate = imu.rate_hz
        distance = max(1, int(round(self.hs_min_interval_s * rate)))
        from scipy.signal import find_peaks  # here: scipy.signal takes ~0.3 s to import

        peaks, _ = find_peaks(acc_norm, height=self.hs_min_acc_mps2, distance=distance)
        starts = flat.intervals[:, 0]
        starts = starts[starts > 0]  # a flat zone opening the recording: standing, not a landing
        if len(peaks) == 0 or len(starts) == 0:
            return np.empty(0, dtype=np.int64)
        j = np.searchsorted(peaks, starts, side="right") - 1  # last peak at or before the start
        found = (j >= 0) & (imu.t[starts] - imu.t[peaks[np.maximum(j, 0)]] <= self.hs_search_s)
        # two flat zones split by a short motion can share a peak: one landing, one heel strike
        return np.unique(peaks[j[found]]).astype(np.int64)

    def _zupt_mask(
        self,
        imu: ImuData,
        flat: NDArray[np.bool_],
        support: NDArray[np.int64],
        other: ImuData | None,
        other_flat: NDArray[np.bool_] | None,
    ) -> tuple[NDArray[np.bool_], NDArray[np.int64]]:
        """Steps 4-5: flat zone inside the support intervals, standing flat zones whole (none
        where the other foot has no samples: ``other`` None)."""
        n = imu.n_samples
        rate = imu.rate_hz
        in_support = _interval_mask(support[:, 0], support[:, 1], n)
        runs = stance_intervals(flat)
        if other is not None:
            assert other_flat is not None  # given with ``other`` (_rule)
            both_flat = flat & _at_times(other_flat, other.t, imu.t)
        else:
            both_flat = np.zeros(n, dtype=bool)
        is_standing = _run_sums(both_flat, runs) >= self.standing_s * rate
        standing = runs[is_standing]
        if self.zupt_rule == "clip":
            mask = flat & in_support
        else:  # "gate": the flat zones that start inside a support interval, whole
            keep = runs[in_support[runs[:, 0]]] if len(runs) else runs
            mask = _interval_mask(keep[:, 0], keep[:, 1], n)
        mask |= _interval_mask(standing[:, 0], standing[:, 1], n)
        # clipping at a heel strike can leave a sliver of a flat zone: no foot stands that briefly
        pieces = stance_intervals(mask)
        short = pieces[pieces[:, 1] - pieces[:, 0] < int(round(self.min_flat_s * rate))]
        mask &= ~_interval_mask(short[:, 0], short[:, 1], n)
        return mask, standing

    def _toe_offs(self, imu: ImuData, mask: NDArray[np.bool_], hs: NDArray[np.int64]) -> NDArray[np.int64]:
        """The first |w| peak after each heel-off (ZUPT end) and before the next heel strike."""
        n = imu.n_samples
        ends = stance_intervals(mask)[:, 1]
        ends = ends[ends < n]  # the foot moves after these
        gyr_norm = np.linalg.norm(imu.gyr, axis=1)
        from scipy.signal import find_peaks

        peaks, _ = find_peaks(gyr_norm, height=self.gyr_threshold_radps, prominence=_TOE_OFF_MIN_PROMINENCE_RADPS)
        if len(ends) == 0 or len(peaks) == 0:
            return np.empty(0, dtype=np.int64)
        j = np.searchsorted(peaks, ends, side="left")  # first peak at or after the heel-off
        next_hs = np.searchsorted(hs, ends, side="left")
        limit = np.where(next_hs < len(hs), hs[np.minimum(next_hs, max(len(hs) - 1, 0))] if len(hs) else n, n)
        found = (j < len(peaks)) & (peaks[np.minimum(j, len(peaks) - 1)] < limit)
        return np.unique(peaks[j[found]]).astype(np.int64)

    @staticmethod
    def _swing_mask(
        n: int, hs: NDArray[np.int64], toe_off: NDArray[np.int64], mask: NDArray[np.bool_]
    ) -> NDArray[np.bool_]:
        """Swing: from each toe-off to the foot's next heel strike (or the next ZUPT run, or the
        end); a heel-off whose toe-off was not found swings from the heel-off."""
        runs = stance_intervals(mask)
        heel_off_next = runs[runs[:, 1] < n, 1]
        # each swing starts at the toe-off after a heel-off, else just after the heel-off
        j = np.searchsorted(toe_off, heel_off_next, side="left")
        next_start_of_run = np.searchsorted(runs[:, 0], heel_off_next, side="left")
        run_after = np.where(next_start_of_run < len(runs), runs[np.minimum(next_start_of_run, len(runs) - 1), 0], n)
        k = np.searchsorted(hs, heel_off_next, side="left")
        hs_after = np.where(k < len(hs), hs[np.minimum(k, max(len(hs) - 1, 0))] if len(hs) else n, n)
        stop = np.minimum(hs_after, run_after)
        to_after = np.where(
            j < len(toe_off), toe_off[np.minimum(j, max(len(toe_off) - 1, 0))] if len(toe_off) else n, n
        )
        start = np.where(to_after < stop, to_after, heel_off_next)
        return _interval_mask(start, stop, n)
