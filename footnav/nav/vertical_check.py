"""Vertical self-check: does a foot's height trend steadily where it walks level?

A ZUPT filter does not observe height, and its usual failure there is quiet: the footprints rise
(or sink) a few centimetres per stride, a flat walk ends a metre above its start, and nothing
says so (docs/height.md). Stairs change the height in steps of a riser or more; drift changes it
a little at every stride. :func:`check_vertical` takes one foot's trajectory, splits its strides
(stance to stance) into level and stair strides as :mod:`footnav.nav.floors` does (the swing's
own rise too, where the trajectory has it), and measures
the height gained over the level strides per 100 m walked on them. A trend of at least
:data:`WARN_RATE_M_PER_100M` that adds up to :data:`WARN_TREND_M` over the walk, made by most of
the level strides rising (or falling) alike, is a DataQualityWarning.

:class:`footnav.Pipeline` runs it on every foot of every run, offline and at an online stream's
close: ``result.meta["vertical_check"]`` holds the figures.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from footnav.core.types import FootTrajectory
from footnav.nav.floors import LEVEL_RISE_MAX_M, stair_strides, stance_heights, swing_offsets

__all__ = ["WARN_RATE_M_PER_100M", "WARN_TREND_M", "VerticalCheck", "check_vertical"]

#: Height trend over level strides that warns, m per 100 m walked on them (the default filter
#: without ``vertical="floors"`` climbs 1-3 m per 100 m on the shared walks).
WARN_RATE_M_PER_100M = 0.5
#: ... when it adds up to at least this over the walk, m.
WARN_TREND_M = 0.25
#: ... and at least this share of the level strides goes the trend's way (steady, not noise).
WARN_STEADY_FRACTION = 0.6
#: Fewer level strides than this say nothing.
MIN_LEVEL_STRIDES = 8


@dataclass(frozen=True, eq=False)
class VerticalCheck:
    """The height trend of one foot's level strides.

    Attributes
    ----------
    level_strides, stair_strides
        Strides whose stance-to-stance rise is below / at least ``level_rise_max_m``.
    walked_m
        Horizontal distance of the level strides, m.
    trend_m
        Sum of the level strides' rises, m.
    rate_m_per_100m
        ``100 trend_m / walked_m``.
    steady_fraction
        Share of the level strides that rise (or fall) with the trend.
    """

    level_strides: int
    stair_strides: int
    walked_m: float
    trend_m: float
    rate_m_per_100m: float
    steady_fraction: float

    @property
    def suspicious(self) -> bool:
        """A steady trend large enough to matter (see the module's docstring)."""
        return (
            self.level_strides >= MIN_LEVEL_STRIDES
            and abs(self.rate_m_per_100m) >= WARN_RATE_M_PER_100M
            and abs(self.trend_m) >= WARN_TREND_M
            and self.steady_fraction >= WARN_STEADY_FRACTION
        )

    def as_meta(self) -> dict[str, Any]:
        """Plain values for a result's meta (JSON-able)."""
        return {
            "suspicious": self.suspicious,
            "level_strides": self.level_strides,
            "stair_strides": self.stair_strides,
            "walked_m": round(self.walked_m, 3),
            "trend_m": round(self.trend_m, 4),
            "rate_m_per_100m": round(self.rate_m_per_100m, 3),
            "steady_fraction": round(self.steady_fraction, 3),
        }

    def message(self, foot: str, estimator: str) -> str:
        """What is wrong and what to try."""
        way = "rises" if self.trend_m > 0 else "sinks"
        return (
            f"{foot} foot, estimator {estimator!r}: the height {way} {abs(self.rate_m_per_100m):.2f} m per 100 m "
            f"walked on level strides ({self.trend_m:+.2f} m over {self.walked_m:.0f} m, "
            f"{self.steady_fraction:.0%} of {self.level_strides} level strides alike) with no stair-like steps: "
            "vertical drift, not a climb. Try the ekf's vertical='floors' (the default), which holds level "
            "strides level; if the walk really is a ramp, the trend is real"
        )


def check_vertical(traj: FootTrajectory, *, level_rise_max_m: float = LEVEL_RISE_MAX_M) -> VerticalCheck:
    """Measure the height trend of one foot's level strides (stance to stance).

    Parameters
    ----------
    traj
        The foot's trajectory (nav frame, z up) with its stance intervals ``steps``.
    level_rise_max_m
        A stride rising or falling less than this is level, m
        (:data:`footnav.nav.floors.LEVEL_RISE_MAX_M`).

    Returns
    -------
    VerticalCheck
    """
    steps = np.asarray(traj.steps, dtype=np.int64).reshape(-1, 2)
    if len(steps) < 2:
        return VerticalCheck(0, 0, 0.0, 0.0, 0.0, 0.0)
    rise = np.diff(stance_heights(traj.position[:, 2], steps))
    length = np.linalg.norm(np.diff(traj.footprints[:, :2], axis=0), axis=1)
    swing = np.full(len(rise), np.nan) if traj.swing_rise_m is None else traj.swing_rise_m[1:]
    level = ~stair_strides(rise, swing + swing_offsets(rise, swing, level_rise_max_m)[0], level_rise_max_m)
    walked = float(length[level].sum())
    trend = float(rise[level].sum())
    rate = 100.0 * trend / walked if walked > 0 else 0.0
    steady = float(np.mean(np.sign(rise[level]) == np.sign(trend))) if level.any() and trend != 0 else 0.0
    return VerticalCheck(int(level.sum()), int((~level).sum()), walked, trend, rate, steady)
