"""Estimated motion in the nav frame: one foot's (:class:`FootTrajectory`) and the pedestrian's (:class:`Path`)."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from footnav.core.errors import InvalidInputError
from footnav.core.types._arrays import _readonly

__all__ = ["FootTrajectory", "Path"]


@dataclass(frozen=True, eq=False)
class FootTrajectory:
    """One foot's estimated motion in the nav frame (z up, x initial walking direction).

    Parameters
    ----------
    t
        Times in s, shape (N,).
    position
        Position of the sensor in m, nav frame, (N, 3).
    velocity
        Velocity in m/s, nav frame, (N, 3).
    quaternion
        Orientation [w, x, y, z], body -> nav, (N, 4), unit norm.
    position_std
        1-sigma position uncertainty per axis in m, (N, 3) (diagonal of the filter covariance).
    steps
        (K, 2) start/stop sample indices of each stance phase used (the footprints).
    meta
        Estimator name, parameters, diagnostics.
    swing_rise_m
        (K,) the strapdown's own height change over the swing before each stance, m (the forward
        filter's, before that stance's first zero-velocity update: :func:`footnav.nav.floors.swing_rises`);
        NaN where unknown (the first stance); None when the estimator gives none.
    """

    t: NDArray[np.float64]
    position: NDArray[np.float64]
    velocity: NDArray[np.float64]
    quaternion: NDArray[np.float64]
    position_std: NDArray[np.float64]
    steps: NDArray[np.int64]
    meta: Mapping[str, Any] = field(default_factory=dict)
    frame: str = "nav"
    swing_rise_m: NDArray[np.float64] | None = None

    def __post_init__(self) -> None:
        n = len(self.t)
        for name, cols in (("position", 3), ("velocity", 3), ("quaternion", 4), ("position_std", 3)):
            arr = np.asarray(getattr(self, name), dtype=np.float64)
            if arr.shape != (n, cols):
                raise InvalidInputError(f"expected shape ({n}, {cols}), got {arr.shape}", field=name)
            object.__setattr__(self, name, _readonly(arr))
        object.__setattr__(self, "t", _readonly(np.asarray(self.t, dtype=np.float64)))
        steps = np.asarray(self.steps, dtype=np.int64).reshape(-1, 2)
        object.__setattr__(self, "steps", _readonly(steps))
        if self.swing_rise_m is not None:
            rise = np.asarray(self.swing_rise_m, dtype=np.float64)
            if rise.shape != (len(steps),):
                raise InvalidInputError(
                    f"expected shape ({len(steps)},) (one per step), got {rise.shape}", field="swing_rise_m"
                )
            object.__setattr__(self, "swing_rise_m", _readonly(rise))
        object.__setattr__(self, "meta", dict(self.meta))

    @property
    def footprints(self) -> NDArray[np.float64]:
        """Mean position over each stance phase, (K, 3) in m."""
        if len(self.steps) == 0:
            return np.empty((0, 3))
        return np.stack([self.position[a:b].mean(axis=0) for a, b in self.steps])

    @property
    def path_length_m(self) -> float:
        """Horizontal distance travelled, summed over footprints (m); over samples if no steps."""
        pts = self.footprints if len(self.steps) > 1 else self.position
        return float(np.linalg.norm(np.diff(pts[:, :2], axis=0), axis=1).sum())


@dataclass(frozen=True, eq=False)
class Path:
    """The pedestrian's path in the nav frame: position (N, 3) in m at times t (N,) in s."""

    t: NDArray[np.float64]
    position: NDArray[np.float64]
    meta: Mapping[str, Any] = field(default_factory=dict)
    frame: str = "nav"

    def __post_init__(self) -> None:
        t = np.asarray(self.t, dtype=np.float64)
        pos = np.asarray(self.position, dtype=np.float64)
        if pos.shape != (len(t), 3):
            raise InvalidInputError(f"expected shape ({len(t)}, 3), got {pos.shape}", field="position")
        object.__setattr__(self, "t", _readonly(t))
        object.__setattr__(self, "position", _readonly(pos))
        object.__setattr__(self, "meta", dict(self.meta))
