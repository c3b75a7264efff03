"""Both feet's stance decided together on a live stream: a detector that needs both feet
(``needs_two_feet``, e.g. ``dual-gait``: a stance ends at the other foot's heel strike, Zhao et
al. 2019, Sec. III-A) online (:mod:`footnav.pipeline.online`).

The per-foot streams (:class:`~footnav.pipeline.online_foot.FootStream`) keep each foot's
samples and filter what is decided; :class:`PairDetection` decides, in blocks of
``online_block_s`` on the common clock:

1. **Blocks.** Block k holds the samples of either foot with times in ``[t0 + (k - 1) b,
   t0 + k b)`` (``t0`` the earlier foot's first sample, ``b`` the block). It is decided once both
   feet have a sample ``latency_s - b`` past its end (the detector's reach), or at ``close``.
2. **Window.** Each foot's samples from ``margin`` samples before its first undecided one (the
   per-foot stream keeps them) to ``latency_s - b`` past the block, the detector's
   ``window_masks`` on both (a foot without samples there is absent, as offline where a foot's
   recording starts later); the block's samples take the window's decisions. Windows are fixed
   by the block's times and the samples, so the decisions are the same however the samples are
   chunked.
3. **The end.** ``close`` decides everything left on one window per foot from its margin on.

While one foot is silent nothing of either is decided: the other foot's heel strikes are part
of every decision. A stance that outlasts the margin on one foot while the other moves can be
decided otherwise than on the whole recording (the window sees no heel strike opening it), so
the detector is not ``online_exact`` and ``close`` reruns offline.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from footnav.core.types import ImuData
from footnav.core.warning_log import recording
from footnav.pipeline.online_foot import FootStream

__all__ = ["PairDetection"]


class PairDetection:
    """Stance of both feet decided together on their windows (module docstring).

    Parameters
    ----------
    stream
        The :class:`~footnav.pipeline.online.OnlineStream` (its pipeline's detector, its latency).
    feet
        Its left and right foot streams.
    """

    def __init__(self, stream: Any, feet: list[FootStream]) -> None:
        self.detector = stream.pipeline.detector
        self.feet = feet
        for f in feet:
            f.paired = True
        self.block_s = float(self.detector.online_block_s)
        self.reach_s = float(stream.latency_s) - self.block_s
        self.t0: float | None = None
        self.k = 0  # blocks decided
        self._grids: list[ImuData | None] = [None, None]  # each foot's sampling interval (the stream's rate)

    def advance(self) -> None:
        """Decide every block both feet have arrived far enough past; filter what was decided."""
        if any(f.rate_hz is None or f.input.end == 0 for f in self.feet):
            return
        if self.t0 is None:
            self.t0 = min(f.first_t for f in self.feet)
        newest = min(f.t_last for f in self.feet)
        # block k ends at t0 + k b and is decided when both feet have reached its end + the reach
        while newest >= self.t0 + (self.k + 1) * self.block_s + self.reach_s:
            self.k += 1
            end = self.t0 + self.k * self.block_s
            self._decide([self._count_before(f, end) for f in self.feet], [end + self.reach_s] * 2)
        for f in self.feet:
            f._filter(final=False)

    def finish(self) -> dict[str, BaseException]:
        """The end: every sample of the feet that passed their end checks decided on one window
        per foot (a foot that failed them is absent from it, as offline where one foot has no
        samples), then each foot finished. Returns the failure of each foot that could not end
        (its own error, as a foot alone gives it); the others end whole."""
        ready = []
        for f in self.feet:
            try:
                f.end_input()
            except Exception:  # raised again by its finish below, and returned
                continue
            ready.append(f)
        if ready:
            self.t0 = min(f.first_t for f in ready) if self.t0 is None else self.t0
            self._decide([f.input.end if f in ready else f.n_final for f in self.feet], [math.inf, math.inf])
        failures: dict[str, BaseException] = {}
        for f in self.feet:
            try:
                f.finish()
            except Exception as exc:
                failures[f.foot] = exc
        return failures

    def _count_before(self, f: FootStream, t: float) -> int:
        """Global index of the foot's first sample at or after ``t`` (s)."""
        times = f.input.rows(f.n_final, f.input.end)[0]
        return f.n_final + int(np.searchsorted(times, t, side="left"))

    def _decide(self, frontiers: list[int], reach: list[float]) -> None:
        """Make each foot's decisions final up to (not at) global index ``frontiers[f]``, on the
        window of its samples from ``margin`` before its first undecided one up to time ``reach[f]``."""
        if all(fr <= f.n_final for f, fr in zip(self.feet, frontiers)):
            return
        windows: list[ImuData | None] = []
        starts = []
        for i, f in enumerate(self.feet):
            a = max(f.n_final - f.margin, f.input.start)
            t, acc, gyr, _ = f.input.rows(a, f.input.end)
            stop = int(np.searchsorted(t, reach[i], side="right"))
            starts.append(a)
            windows.append(self._window(i, t[:stop], acc[:stop], gyr[:stop]) if stop >= 2 else None)
        with recording(quiet=True):  # a window's gaps were warned about with the recording
            masks = self.detector.window_masks(*windows)
        for i, (f, fr) in enumerate(zip(self.feet, frontiers)):
            if fr > f.n_final:
                mask = masks.get(f.foot)  # none: a single sample in its window, no stance
                f.decide(
                    mask[f.n_final - starts[i] : fr - starts[i]]
                    if mask is not None
                    else np.zeros(fr - f.n_final, dtype=bool)
                )

    def _window(self, i: int, t: np.ndarray, acc: np.ndarray, gyr: np.ndarray) -> ImuData:
        """The foot's window as an ImuData on the stream's sampling interval (the detector counts
        samples at that rate) with the samples' own times (the feet meet on the common clock)."""
        grid = self._grids[i]
        if grid is None:
            rate = self.feet[i].rate_hz
            grid = self._grids[i] = ImuData(
                t=np.arange(2) / rate, acc=np.tile([0.0, 0.0, 9.81], (2, 1)), gyr=np.zeros((2, 3))
            )
        return grid.same_grid(t.copy(), acc.copy(), gyr.copy())
