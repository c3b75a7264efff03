"""What a stance detector finds in one foot's recording (:class:`StanceResult`), and its stance runs."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from footnav.core.errors import InvalidInputError
from footnav.core.types._arrays import _readonly

__all__ = ["StanceResult", "stance_intervals"]


def stance_intervals(mask: NDArray[np.bool_]) -> NDArray[np.int64]:
    """Start and stop (exclusive) indices of each run of True in ``mask``, shape (K, 2)."""
    m = np.asarray(mask, dtype=bool)
    if m.size == 0:
        return np.empty((0, 2), dtype=np.int64)
    d = np.diff(np.concatenate(([False], m, [False])).astype(np.int8))
    starts = np.flatnonzero(d == 1)
    stops = np.flatnonzero(d == -1)
    return np.stack([starts, stops], axis=1).astype(np.int64)


@dataclass(frozen=True, eq=False)
class StanceResult:
    """What a stance detector found in one foot's recording (sample-aligned with its ImuData).

    Parameters
    ----------
    mask
        True where the foot is at zero velocity (stance), shape (N,).
    events
        Gait events as sample indices, e.g. ``{"heel_strike": ..., "foot_flat": ..., "heel_off": ...,
        "toe_off": ...}``; each value int array. Detectors give those they can.
    phases
        Per-sample phase label (int, detector-defined, names in ``meta["phase_names"]``), or None.
    score
        Per-sample detector statistic or stance probability (N,), or None.
    meta
        Detector name, parameters and diagnostics.
    """

    mask: NDArray[np.bool_]
    events: Mapping[str, NDArray[np.int64]] = field(default_factory=dict)
    phases: NDArray[np.int64] | None = None
    score: NDArray[np.float64] | None = None
    meta: Mapping[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        mask = np.asarray(self.mask)
        if mask.ndim != 1:
            raise InvalidInputError(f"expected shape (N,), got {mask.shape}", field="mask")
        object.__setattr__(self, "mask", _readonly(mask.astype(bool)))
        object.__setattr__(
            self, "events", {k: _readonly(np.asarray(v, dtype=np.int64)) for k, v in dict(self.events or {}).items()}
        )
        n = len(mask)
        for name in ("phases", "score"):
            val = getattr(self, name)
            if val is not None:
                arr = np.asarray(val)
                if arr.shape != (n,):
                    raise InvalidInputError(f"expected shape ({n},), got {arr.shape}", field=name)
                object.__setattr__(self, name, _readonly(arr))
        object.__setattr__(self, "meta", dict(self.meta))

    @property
    def intervals(self) -> NDArray[np.int64]:
        """(K, 2) start/stop indices of each stance phase."""
        return stance_intervals(self.mask)

    @property
    def n_stances(self) -> int:
        """Number of stance intervals."""
        return len(self.intervals)
