"""Heading drift removed along the walk's dominant directions (Borenstein et al. 2009, HDR;
Jimenez et al. 2012, iHDE): the heading aid ``dominant-directions``."""

from __future__ import annotations

import numpy as np

from footnav.core.component import HeadingAid
from footnav.core.parameters import require, require_positive
from footnav.core.types import FusionResult, ImuData
from footnav.nav.dominant_directions import dominant_direction_correction
from footnav.nav.heading import turn_result

__all__ = ["DominantDirectionsAid"]


class DominantDirectionsAid(HeadingAid):
    """Heading drift removed where the walk runs straight along a dominant direction.

    Borenstein et al. (2009) HDR and Jimenez et al. (2012) iHDE, made over the whole walk
    (:mod:`footnav.nav.dominant_directions`): the directions (``n_directions`` at equal angles)
    are learned from each foot's own straight strides, each straight stretch's heading error
    against its direction is measured, and the trajectory is turned by the error interpolated
    in time between stretches. Nothing changes on a walk without a dominant direction (open
    ground, curves: ``min_strength``). For hallway walks in buildings whose corridors meet at
    right angles; a corridor at another angle is taken for drift (docs/heading.md).

    Parameters
    ----------
    n_directions : int
        Directions of the building's grid, evenly spaced (4: right angles).
    straight_deg : float
        A stride is straight when its heading is within this of both neighbours', deg.
    gate_deg : float
        A straight stride counts when within this of its grid direction, deg.
    min_stride_m : float
        Shorter strides are never straight (turns on the spot), m.
    min_stretch_strides : int
        Straight strides a stretch needs.
    min_strength : float
        Resultant length (0-1) of the straight strides' headings on the grid below which the
        walk has no dominant direction and is left as it is.
    """

    name = "dominant-directions"

    def __init__(
        self,
        *,
        n_directions: int = 4,
        straight_deg: float = 20.0,
        gate_deg: float = 15.0,
        min_stride_m: float = 0.4,
        min_stretch_strides: int = 3,
        min_strength: float = 0.5,
    ) -> None:
        self.n_directions = n_directions
        self.straight_deg = straight_deg
        self.gate_deg = gate_deg
        self.min_stride_m = min_stride_m
        self.min_stretch_strides = min_stretch_strides
        self.min_strength = min_strength

    def validate_params(self) -> None:
        """Check every parameter (:meth:`footnav.core.component.Component.validate_params`); raises
        InvalidParameterError."""
        require(
            isinstance(self.n_directions, (int, np.integer)) and 1 <= self.n_directions <= 16,
            self,
            "n_directions",
            "an integer in [1, 16]",
        )
        require(
            isinstance(self.min_stretch_strides, (int, np.integer)) and 2 <= self.min_stretch_strides <= 1000,
            self,
            "min_stretch_strides",
            "an integer in [2, 1000]",
        )
        require_positive(self, "straight_deg", "gate_deg", high=90.0)
        require_positive(self, "min_stride_m", high=10.0)
        require(0.0 <= self.min_strength <= 1.0, self, "min_strength", "in [0, 1]")

    def correct(self, result: FusionResult, left: ImuData, right: ImuData | None = None) -> FusionResult:
        """Each foot turned by its own heading error; the pedestrian path by their mean."""
        self.validate_params()
        params = self.get_params()
        found = [
            None if traj is None else dominant_direction_correction(traj, **params)
            for traj in (result.left, result.right)
        ]
        return turn_result(result, found, self.name)
