"""The simulated walk's centre line: straight lines and circular arcs, stairs flights along it."""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray


@dataclass(frozen=True)
class _CentreLine:
    """Straight lines and circular arcs joined end to end, starting at the origin heading +x.

    Each piece ``i`` starts at arc length ``start[i]`` (m), point ``xy[i]`` (m) and heading
    ``heading[i]`` (rad, unwrapped) and has curvature ``curvature[i]`` (1/m, + = left, 0 = line).
    """

    start: NDArray[np.float64]
    xy: NDArray[np.float64]
    heading: NDArray[np.float64]
    curvature: NDArray[np.float64]
    length_m: float

    @classmethod
    def build(cls, pieces: Sequence[tuple[float, float]]) -> _CentreLine:
        """From ``(length_m, curvature_per_m)`` pieces; zero-length pieces are dropped."""
        pieces = [(l, k) for l, k in pieces if l > 0]
        start, xy, heading, curvature = [], [], [], []
        s, p, h = 0.0, np.zeros(2), 0.0
        for length, k in pieces:
            start.append(s)
            xy.append(p)
            heading.append(h)
            curvature.append(k)
            p, h = cls._advance(p, h, k, length)
            s += length
        return cls(np.array(start), np.array(xy), np.array(heading), np.array(curvature), s)

    @staticmethod
    def _advance(p: NDArray, h: Any, k: Any, ds: Any) -> tuple[NDArray, Any]:
        """Point and heading after ``ds`` along a piece of curvature ``k`` (vectorised)."""
        h1 = h + k * ds
        arc = np.abs(k) > 0
        safe_k = np.where(arc, k, 1.0)
        dx = np.where(arc, (np.sin(h1) - np.sin(h)) / safe_k, ds * np.cos(h))
        dy = np.where(arc, (np.cos(h) - np.cos(h1)) / safe_k, ds * np.sin(h))
        return p + np.stack([dx, dy], axis=-1), h1

    def __call__(self, s: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Point (M, 2) in m and heading (M,) in rad at arc lengths ``s`` (M,) in m."""
        i = np.clip(np.searchsorted(self.start, s, side="right") - 1, 0, len(self.start) - 1)
        return self._advance(self.xy[i], self.heading[i], self.curvature[i], s - self.start[i])


def _centre_line(scenario: str, opts: dict[str, Any]) -> tuple[_CentreLine, dict[str, Any]]:
    """The scenario's centre line and a description of it for the truth's meta."""
    r = opts["turn_radius_m"]
    if scenario == "straight":
        pieces = [(opts["distance_m"], 0.0)]
        return _CentreLine.build(pieces), {"waypoints_m": _waypoints(pieces)}
    if scenario == "rectangle":
        w, h = opts["width_m"], opts["height_m"]
        sign = 1.0 if opts["direction"] == "ccw" else -1.0
        quarter = np.pi / 2 * r
        # Start in the middle of a long side so the walk ends exactly where and as it started
        # (same heading, same footprints) after four corners rounded with the turn radius.
        pieces = [(w / 2 - r, 0.0)]
        for side in (h, w, h):
            pieces += [(quarter, sign / r), (side - 2 * r, 0.0)]
        pieces += [(quarter, sign / r), (w / 2 - r, 0.0)]
        y0, y1 = (0.0, h) if sign > 0 else (-h, 0.0)
        corners = np.array([[-w / 2, y0], [w / 2, y0], [w / 2, y1], [-w / 2, y1]])
        return _CentreLine.build(pieces), {"rectangle_corners_m": corners, "waypoints_m": _waypoints(pieces)}
    pieces = []
    # flights of stairs: (arc length where the flight starts, n_steps, rise_m, tread_m)
    flights: list[tuple[float, int, float, float]] = []
    s = 0.0
    for seg in opts["segments"]:
        if seg[0] == "stairs":
            _, n_steps, rise, tread = seg
            flights.append((s, n_steps, rise, tread))
            pieces.append((n_steps * tread, 0.0))
            s += n_steps * tread
            continue
        distance, turn_deg = seg
        pieces.append((distance, 0.0))
        s += distance
        if turn_deg != 0:
            pieces.append((abs(math.radians(turn_deg)) * r, math.copysign(1.0 / r, turn_deg)))
            s += pieces[-1][0]
    info: dict[str, Any] = {"waypoints_m": _waypoints(pieces)}
    if flights:  # only then: a walk without stairs keeps its meta as it was
        info["stairs"] = [
            {"start_m": s0, "n_steps": n_steps, "rise_m": rise, "tread_m": tread, "height_m": n_steps * rise}
            for s0, n_steps, rise, tread in flights
        ]
    return _CentreLine.build(pieces), info


def _waypoints(pieces: list[tuple[float, float]]) -> NDArray[np.float64]:
    """Centre-line points a surveyor would mark: the apex of every turn and the end, (K, 2) m
    (for :func:`footnav.analysis.metrics.waypoint_errors`, Lee, Cho & Park 2022, Table 3)."""
    line = _CentreLine.build(pieces)
    s, marks = 0.0, []
    for length, curvature in pieces:
        if curvature != 0.0:
            marks.append(s + 0.5 * length)
        s += length
    marks.append(s)
    xy, _ = line(np.asarray(marks, dtype=float))
    return np.asarray(xy, dtype=float)
