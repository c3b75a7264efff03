"""Dual-gait stance detection: both feet analysed together (seed 001 section III-A, Zhao 2019).

Per foot, a *flat zone* (angular rate near zero, specific force near g over a short window) delimits
the zero-velocity (ZUPT) period, and the heel strike (HS) is the specific-force peak that opens the
stance: "The measurements exhibit sudden spikes when the HS events occur ... A peak detection method
is used to detect the HS events, whereas a flat zone detection method is used to delimit the ZUPT
periods." The two feet are then joined: "a stance phase starts with the HS event of supporting
foot, but ends with the HS event of contralateral foot" (because "the HO events of rear foot always
coincide with the HS events of the front foot").

footnav's reading: the heel strike of each flat zone is the largest |f| peak (scipy ``find_peaks``)
above ``hs_min_acc_mps2`` in the ``hs_search_s`` before the zone starts; the *support interval* of a foot runs from its heel
strike to the next heel strike of the other foot; the ZUPT mask is the flat zone inside the support
interval (and the flat zones before the foot's first heel strike: the initial standstill).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray
from scipy.signal import find_peaks

from footnav.core.component import StanceDetector, require
from footnav.core.errors import CompositionError, InvalidInputError
from footnav.core.types import ImuData, StanceResult, stance_intervals
from footnav.detectors.threshold import ThresholdDetector

__all__ = ["DualGaitDetector", "PHASE_NAMES"]

#: Per-sample phase labels of the result (``phases``): ZUPT stance, the rest of the support
#: interval (heel strike to foot flat, heel off to the other foot's heel strike), swing.
PHASE_NAMES = ("zupt", "support", "swing")
_ZUPT, _SUPPORT, _SWING = range(len(PHASE_NAMES))


class DualGaitDetector(StanceDetector):
    """Heel-strike peaks + flat-zone ZUPT per foot, stance bounded by the other foot's heel strike.

    Needs both feet on one clock (``needs_two_feet``); the pipeline calls ``detect_pair``.

    Parameters
    ----------
    window_s : float
        Window of the flat-zone statistics, s.
    gyr_threshold_radps : float
        Flat zone needs the windowed RMS of |w| below this, rad/s (the "threshold" detector's test).
    acc_tolerance_mps2 : float
        Flat zone needs the windowed RMS of |f| - g below this, m/s^2.
    min_stance_s : float
        Flat zones shorter than this are discarded, s.
    hs_search_s : float
        A flat zone's heel strike is the largest |f| peak this long before it starts, s.
    hs_min_acc_mps2 : float
        A heel-strike peak must reach this |f|, m/s^2 (a spike above gravity).
    """

    name = "dual-gait"
    needs_two_feet = True

    def __init__(
        self,
        *,
        window_s: float = 0.05,
        gyr_threshold_radps: float = 0.6,
        acc_tolerance_mps2: float = 1.5,
        min_stance_s: float = 0.05,
        hs_search_s: float = 0.3,
        hs_min_acc_mps2: float = 11.0,
    ) -> None:
        self.window_s = window_s
        self.gyr_threshold_radps = gyr_threshold_radps
        self.acc_tolerance_mps2 = acc_tolerance_mps2
        self.min_stance_s = min_stance_s
        self.hs_search_s = hs_search_s
        self.hs_min_acc_mps2 = hs_min_acc_mps2

    def validate_params(self) -> None:
        for name, value in self.get_params().items():
            lower = "a number >= 0" if name == "min_stance_s" else "a positive number"
            ok = isinstance(value, (int, float)) and np.isfinite(value) and (value >= 0 if name == "min_stance_s" else value > 0)
            require(ok, self, name, lower)

    def detect(self, imu: ImuData) -> StanceResult:
        raise CompositionError(
            "detector 'dual-gait' needs both feet: call detect_pair(left, right) or run it in a pipeline with right=..."
        )

    def _flat_zone(self, imu: ImuData) -> StanceResult:
        return ThresholdDetector(
            window_s=self.window_s,
            gyr_threshold_radps=self.gyr_threshold_radps,
            acc_tolerance_mps2=self.acc_tolerance_mps2,
            min_stance_s=self.min_stance_s,
        ).detect(imu)

    def _heel_strikes(self, imu: ImuData, flat: NDArray[np.int64]) -> NDArray[np.int64]:
        """One heel strike per flat zone: the largest |f| peak in the search window before it."""
        acc_norm = np.linalg.norm(imu.acc, axis=1)
        peaks, _ = find_peaks(acc_norm, height=self.hs_min_acc_mps2)
        search = int(round(self.hs_search_s * imu.rate_hz))
        hs = []
        for start in flat[:, 0]:
            cand = peaks[(peaks >= start - search) & (peaks <= start)]
            if len(cand):
                hs.append(cand[np.argmax(acc_norm[cand])])  # the impact is the largest spike
        return np.asarray(hs, dtype=np.int64)

    def detect_pair(self, left: ImuData, right: ImuData | None) -> tuple[StanceResult, StanceResult]:
        """Stance of both feet (seed 001 section III-A); see the module docstring for the rule."""
        self.validate_params()
        if right is None:
            self.detect(left)  # raises CompositionError
        if left.t[0] > right.t[-1] or right.t[0] > left.t[-1]:
            raise InvalidInputError(
                f"the feet do not overlap in time (left {left.t[0]:.3f}-{left.t[-1]:.3f} s, right "
                f"{right.t[0]:.3f}-{right.t[-1]:.3f} s); dual-gait analysis needs both feet on one clock",
                field="t",
            )
        flats = {"left": self._flat_zone(left), "right": self._flat_zone(right)}
        imus = {"left": left, "right": right}
        hs = {foot: self._heel_strikes(imus[foot], flats[foot].intervals) for foot in imus}
        hs_time = {foot: imus[foot].t[hs[foot]] for foot in imus}
        out = []
        for foot, other in (("left", "right"), ("right", "left")):
            imu, flat = imus[foot], flats[foot]
            n = imu.n_samples
            support = np.zeros(n, dtype=bool)
            ends = []
            for k, t_hs in zip(hs[foot], hs_time[foot]):
                later = hs_time[other][hs_time[other] > t_hs]
                stop = n if len(later) == 0 else int(np.searchsorted(imu.t, later[0]))
                support[k:stop] = True
                ends.append(stop)
            first_hs = hs[foot][0] if len(hs[foot]) else n
            mask = flat.mask & (support | (np.arange(n) < first_hs))
            phases = np.full(n, _SWING, dtype=np.int64)
            phases[support] = _SUPPORT
            phases[mask] = _ZUPT
            runs = stance_intervals(mask)
            out.append(
                StanceResult(
                    mask=mask,
                    events={
                        "heel_strike": hs[foot],
                        "foot_flat": runs[:, 0],
                        "heel_off": runs[:, 1] - 1,
                    },
                    phases=phases,
                    score=flat.score,
                    meta={
                        "detector": self.describe(),
                        "phase_names": PHASE_NAMES,
                        "support_intervals": np.column_stack([hs[foot], np.asarray(ends, dtype=np.int64)]).reshape(-1, 2),
                    },
                )
            )
        return out[0], out[1]
