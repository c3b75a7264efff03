"""Heading aids: components that correct the heading of a run's final trajectories.

``none`` (the default) changes nothing; ``dominant-directions`` removes heading drift along a
building's dominant directions (:mod:`footnav.nav.dominant_directions`).
"""

from footnav.heading_aids.dominant_directions import DominantDirectionsAid
from footnav.heading_aids.none import NoHeadingAid

__all__ = ["DominantDirectionsAid", "NoHeadingAid"]
