"""The closed steps of one foot's final samples in an online stream (:mod:`footnav.pipeline.online`).

:class:`StepTracker` takes a foot's final (smoothed) samples in order, as they become final, and
returns a :class:`~footnav.pipeline.online_io.ClosedStep` per stance that ended: its footprint
(the mean position over the stance, as :attr:`footnav.core.types.FootTrajectory.footprints`), the
stride from the previous footprint and its heading. Where the nav frame's heading is that of
the foot's first step (``heading="first-step"``), the footprints are held until the first step
longer than :data:`~footnav.nav.heading.MIN_FIRST_STEP_M` has closed, then turned by it.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from footnav.nav.heading import MIN_FIRST_STEP_M
from footnav.pipeline.online_io import ClosedStep

__all__ = ["StepTracker", "stance_runs"]


def stance_runs(mask: NDArray[np.bool_]) -> list[tuple[int, int]]:
    """:func:`~footnav.core.types.stance_intervals` as a list of (start, stop) ints: the few runs of a
    push's final samples, with a third of its numpy calls."""
    if len(mask) == 0:
        return []
    bounds = [0, *(np.flatnonzero(mask[1:] != mask[:-1]) + 1).tolist(), len(mask)]
    return [(bounds[i], bounds[i + 1]) for i in range(0 if mask[0] else 1, len(bounds) - 1, 2)]


class StepTracker:
    """Footprints and closed steps of one foot, from its final samples in order.

    Parameters
    ----------
    foot
        ``"left"`` or ``"right"``.
    psi
        The turn (rad about z) from the samples' frame to the output frame when known (0 when
        the samples are in it already), or None: the heading of the first step, found here
        (:func:`footnav.nav.heading.heading_of_first_step`'s rule).

    Attributes
    ----------
    pending
        The closed steps not yet taken by the stream, in order.
    collect
        Keep the closed steps in :attr:`pending` (False: only the heading is found, for a foot
        whose steps someone else reports).
    """

    def __init__(self, foot: str, psi: float | None) -> None:
        self.foot = foot
        self.psi = psi
        self.pending: list[ClosedStep] = []
        self.collect = True
        self._sum = np.zeros(3)
        self._n = 0
        self._unturned: list[NDArray] = []  # footprints before the heading is known
        self._waiting: list[tuple[float, int, NDArray]] = []  # (t, index, footprint) awaiting the heading
        self._last: NDArray | None = None
        self.n_steps = 0

    @property
    def first_waiting_s(self) -> float:
        """The end (s) of the first step held for the heading, or inf."""
        return self._waiting[0][0] if self._waiting else math.inf

    def add(self, t: NDArray, pos: NDArray, mask: NDArray, next_stance: bool) -> None:
        """Samples that became final (time s, position m, stance), in order; ``next_stance``: the
        stance decision of the sample after them (False at the end)."""
        for s, e in stance_runs(mask):
            self._sum += pos[s:e].sum(axis=0)
            self._n += int(e - s)
            if e < len(mask) or not next_stance:
                self._close(float(t[e - 1]))

    def finish(self) -> None:
        """The end: without a first step long enough, the samples' own heading."""
        if self.psi is None:
            self.psi = 0.0
            self._release()

    def _close(self, t_end: float) -> None:
        fp = self._sum / max(self._n, 1)
        self._sum = np.zeros(3)
        self._n = 0
        self._waiting.append((t_end, self.n_steps, fp))
        self.n_steps += 1
        if self.psi is None:
            self._unturned.append(fp)
            self._find_heading()
        if self.psi is not None:
            self._release()

    def _find_heading(self) -> None:
        first = self._unturned[0]
        for fp in self._unturned[1:]:
            d = fp - first
            if np.hypot(d[0], d[1]) > MIN_FIRST_STEP_M:
                self.psi = float(np.arctan2(d[1], d[0]))
                self._unturned = []
                return

    def _release(self) -> None:
        if not self.collect:
            self._waiting.clear()
            return
        c, s = math.cos(-self.psi), math.sin(-self.psi)
        for t_end, idx, fp in self._waiting:
            p = np.array([c * fp[0] - s * fp[1], s * fp[0] + c * fp[1], fp[2]])
            if self._last is None:
                length, heading = 0.0, math.nan
            else:
                d = p - self._last
                length, heading = float(np.hypot(d[0], d[1])), float(math.atan2(d[1], d[0]))
            self._last = p
            self.pending.append(ClosedStep(t_end, self.foot, p, length, heading, idx))
        self._waiting.clear()
