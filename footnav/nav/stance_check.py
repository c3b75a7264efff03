"""Stance plausibility: do the detected stances agree with the gait cycles in the signal?

Every estimator and fusion stands on the stance mask, and a wrong mask fails quietly: a detector
whose bound is too tight for running finds 3 stances in 30 strides, the ZUPTs are missing, and the
trajectory drifts by metres with nothing said. The gait cycles can be seen without any stance
detector: one swing peak of the windowed angular rate per stride
(:func:`footnav.nav.gait_cycles.swing_peaks`). Between two consecutive swing peaks (closer than a
pause, ``max_stride_s``, and further apart than the shortest stride, ``min_stride_s``) the foot
must have stood once; a stance holding a swing peak cannot be a
stance. :func:`check_stances` counts both and says where (times in s).

:class:`footnav.Pipeline` runs it on every foot of every run: ``result.meta["stance_check"]``
holds the counts and times, and a DataQualityWarning says what is wrong and what to try.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from footnav.core.types import ImuData, StanceResult, stance_intervals
from footnav.nav.gait_cycles import SWING_ACC_MPS2, swing_peaks
from footnav.nav.windows import centred_acc_magnitude_rms

__all__ = ["StanceCheck", "check_stances"]

#: Times listed in a warning message (all of them are in meta).
_SHOWN = 5
#: A warning needs at least this many odd cycles, and this share of all cycles.
_MIN_WARN = 2
_WARN_FRACTION = 0.05


@dataclass(frozen=True, eq=False)
class StanceCheck:
    """Agreement of one foot's stances with its gait cycles.

    Attributes
    ----------
    n_cycles
        Gait cycles seen in the signal: intervals between consecutive swing peaks from
        ``min_stride_s`` to ``max_stride_s`` apart, both where the foot accelerates (RMS of
        ``|f| - g`` over the swing window at least :data:`~footnav.nav.gait_cycles.SWING_ACC_MPS2`).
    n_stances
        Detected stance phases.
    missed_s
        Mid-times (s, the recording's clock) of the cycles with no stance sample between their
        two swing peaks.
    over_swing_s
        Times (s) of the swing peaks that lie inside a detected stance while the foot accelerates
        (RMS of ``|f| - g`` over the swing window at least
        :data:`~footnav.nav.gait_cycles.SWING_ACC_MPS2`; a pivot on the ground is a stance).
    stride_s
        The recording's typical stride (s), nan when too few swings were seen.
    """

    n_cycles: int
    n_stances: int
    missed_s: NDArray[np.float64]
    over_swing_s: NDArray[np.float64]
    stride_s: float

    @property
    def ok(self) -> bool:
        """No cycle without a stance and no stance over a swing."""
        return len(self.missed_s) == 0 and len(self.over_swing_s) == 0

    @property
    def suspicious(self) -> bool:
        """Enough disagreement to warn: at least ``max(2, 5 %)`` of the gait cycles.

        A single odd cycle in a long walk (a stumble, a swing peak of a turn on the spot) is
        recorded but not warned about; a detector that misses the stances of a gait misses many.
        """
        bad = len(self.missed_s) + len(self.over_swing_s)
        return bad >= max(_MIN_WARN, _WARN_FRACTION * self.n_cycles)

    def as_meta(self) -> dict[str, Any]:
        """Plain values for a result's meta (JSON-able)."""
        return {
            "ok": self.ok,
            "suspicious": self.suspicious,
            "gait_cycles": self.n_cycles,
            "stances": self.n_stances,
            "cycles_without_stance": len(self.missed_s),
            "cycles_without_stance_at_s": [round(float(t), 3) for t in self.missed_s],
            "stances_over_swing": len(self.over_swing_s),
            "stances_over_swing_at_s": [round(float(t), 3) for t in self.over_swing_s],
            "stride_s": None if np.isnan(self.stride_s) else round(float(self.stride_s), 3),
        }

    def message(self, foot: str, detector: str) -> str:
        """What is wrong, where, and what to try; '' when nothing is."""
        parts = []
        if len(self.missed_s):
            parts.append(
                f"{len(self.missed_s)} of {self.n_cycles} gait cycles have no stance (at {_times(self.missed_s)}): "
                "no zero-velocity update there, so the trajectory drifts"
            )
        if len(self.over_swing_s):
            parts.append(
                f"{len(self.over_swing_s)} stances hold a swing (at {_times(self.over_swing_s)}): "
                "zero-velocity updates while the foot swings pull the trajectory back"
            )
        if not parts:
            return ""
        hint = (
            "try the default detector 'adaptive', which sets its bound per gait cycle"
            if detector != "adaptive"
            else "check the units and the sampling rate, or give the detector's bounds explicitly"
        )
        return f"{foot} foot, detector {detector!r}: " + "; ".join(parts) + f". The result is probably wrong: {hint}"


def _times(t: NDArray[np.float64]) -> str:
    shown = ", ".join(f"{x:.1f} s" for x in t[:_SHOWN])
    return shown + (f" and {len(t) - _SHOWN} more" if len(t) > _SHOWN else "")


def check_stances(
    imu: ImuData, stance: StanceResult, *, min_stride_s: float = 0.55, max_stride_s: float = 2.5
) -> StanceCheck:
    """Compare one foot's stances with the gait cycles of its angular rate.

    Parameters
    ----------
    imu
        The foot's recording (angular rate in rad/s).
    stance
        The detector's result for it (same samples).
    min_stride_s
        Swing peaks closer than this are not a stride, s: no foot runs a stride in less, but some
        mountings see two humps per stride about half a stride apart (IPOL subject 7's left foot:
        0.4-0.5 s in a 1 s stride), and a stance between them is not to be expected.
    max_stride_s
        Swing peaks further apart than this are a pause, not one stride, s: the foot may stand
        any number of times between them, and the cycle is not checked.

    Returns
    -------
    StanceCheck
    """
    peaks = swing_peaks(imu.gyr, imu.rate_hz)
    idx = peaks.index
    mask = np.asarray(stance.mask, dtype=bool)
    # stance samples before index i: a cycle (a, b) holds a stance when the count grows inside it
    # only a foot that accelerates swings: a pivot on the ground (turning on the spot) or a
    # dragged foot (crawling) turns as fast, and may stand throughout
    acc_dev = centred_acc_magnitude_rms(imu.acc, peaks.window_samples)
    swinging = acc_dev[idx] >= SWING_ACC_MPS2
    count = np.concatenate([[0], np.cumsum(mask)])
    a, b = idx[:-1], idx[1:]
    stride = ((b - a) >= min_stride_s * imu.rate_hz) & ((b - a) <= max_stride_s * imu.rate_hz)
    stride &= swinging[:-1] & swinging[1:]
    a, b = a[stride], b[stride]
    missed = (count[b] - count[a + 1]) == 0
    t = imu.t
    missed_s = 0.5 * (t[a[missed]] + t[b[missed]])
    over_swing_s = t[idx[swinging & mask[idx]]]
    return StanceCheck(
        n_cycles=len(a),
        n_stances=len(stance_intervals(mask)),
        missed_s=missed_s,
        over_swing_s=over_swing_s,
        stride_s=peaks.stride_s,
    )
