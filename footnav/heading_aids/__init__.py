"""Heading aids: components that correct the heading of a run's final trajectories.

``none`` (the default) changes nothing; ``dominant-directions`` removes heading drift along a
building's dominant directions (:mod:`footnav.nav.dominant_directions`); ``magnetometer`` with
the magnetometer where the field is undisturbed (:mod:`footnav.nav.magnetic_heading`).
"""

from footnav.heading_aids.dominant_directions import DominantDirectionsAid
from footnav.heading_aids.magnetometer import MagnetometerAid
from footnav.heading_aids.none import NoHeadingAid

__all__ = ["DominantDirectionsAid", "MagnetometerAid", "NoHeadingAid"]
