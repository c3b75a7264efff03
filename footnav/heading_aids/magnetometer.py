"""Heading drift removed with the magnetometer where the field is undisturbed: the heading aid
``magnetometer``."""

from __future__ import annotations

import numpy as np

from footnav.core.component import HeadingAid
from footnav.core.parameters import require, require_in_range, require_positive
from footnav.core.types import FusionResult, ImuData
from footnav.core.warning_log import warn
from footnav.nav.heading import turn_result
from footnav.nav.magnetic_heading import MagneticCorrection, magnetic_heading_correction

__all__ = ["MagnetometerAid"]


class MagnetometerAid(HeadingAid):
    """Heading drift removed with the magnetometer, read at stance where the field is Earth's.

    At each stance the estimated attitude turns the field into the nav frame; the change of
    its horizontal direction along the walk is the filter's heading error (Foxlin 2005), taken
    out through a running median (:mod:`footnav.nav.magnetic_heading`). Stances whose field
    strength or dip is off the walk's median (steel, electronics: Afzal et al. 2011) are left
    out and counted in ``meta["heading_aid"]``; a hard-iron offset is fitted and removed when
    the foot's attitudes allow it. When too few stances pass, nothing changes and a
    DataQualityWarning says why. Needs ``mag`` on every foot (any unit).

    Parameters
    ----------
    magnitude_tol : float
        A sample passes when its field strength is within this fraction of the walk's median.
    dip_tol_deg : float
        A sample passes when its dip is also within this of the walk's median dip, deg.
    window_s : float
        Running median of the stances' heading errors over this window, s.
    min_stances : int
        Stances that must pass for the correction to apply.
    min_fraction : float
        Share of the stances that must pass (0-1).
    hard_iron : bool
        Fit and remove a constant sensor-frame offset (when the attitudes allow the fit).
    """

    name = "magnetometer"
    needs_magnetometer = True

    def __init__(
        self,
        *,
        magnitude_tol: float = 0.05,
        dip_tol_deg: float = 3.0,
        window_s: float = 20.0,
        min_stances: int = 10,
        min_fraction: float = 0.3,
        hard_iron: bool = True,
    ) -> None:
        self.magnitude_tol = magnitude_tol
        self.dip_tol_deg = dip_tol_deg
        self.window_s = window_s
        self.min_stances = min_stances
        self.min_fraction = min_fraction
        self.hard_iron = hard_iron

    def validate_params(self) -> None:
        """Check every parameter (:meth:`footnav.core.component.Component.validate_params`); raises
        InvalidParameterError."""
        require_in_range(self, "magnitude_tol", low=0.0, high=1.0, low_open=True)
        require_positive(self, "dip_tol_deg", high=90.0)
        require_positive(self, "window_s", high=3600.0)
        require_in_range(self, "min_stances", low=2, high=10**6, integer=True)
        require_in_range(self, "min_fraction", low=0.0, high=1.0)
        require(isinstance(self.hard_iron, (bool, np.bool_)), self, "hard_iron", "True or False")

    def correct(self, result: FusionResult, left: ImuData, right: ImuData | None = None) -> FusionResult:
        """Each foot turned by its own magnetic heading error; the pedestrian path by their mean."""
        self.validate_params()
        params = self.get_params()
        found: list[MagneticCorrection | None] = []
        for foot, traj, imu in (("left", result.left, left), ("right", result.right, right)):
            if traj is None or imu is None:
                found.append(None)
                continue
            one = magnetic_heading_correction(traj, imu, **params)
            if not one.applied:
                warn(
                    f"{foot} foot: heading aid 'magnetometer' not applied: {one.reason}; the heading is the "
                    "estimator's. Try a walk away from steel and electronics, or heading_aid='dominant-directions' "
                    "indoors",
                    stacklevel=3,
                )
            found.append(one)
        return turn_result(result, found, self.name)
