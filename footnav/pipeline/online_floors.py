"""The floors' height hold of a live stream (``vertical="floors"``, :class:`footnav.nav.floors.FloorHolder`):
a foot's final samples with its level strides held level, and each closed step's footprint at the
height its stance was held at, as the offline pipeline gives them.
"""

from __future__ import annotations

from dataclasses import replace
from typing import Any

import numpy as np

from footnav.nav.floors import FloorHolder
from footnav.pipeline.online_io import ClosedStep, FootUpdate

__all__ = ["hold_update", "held_step"]


def hold_update(holder: FloorHolder, update: FootUpdate, source: Any, final: bool) -> FootUpdate:
    """A foot's final samples with level strides held level (:class:`FloorHolder`): those whose
    stride's next stance has ended; the rest wait for it (or for the end)."""
    closed = bool(len(update.t)) and any(s.t == update.t[-1] for s in source.steps.pending)
    rows = holder.push(
        update.t,
        update.position,
        update.velocity,
        update.quaternion,
        update.stance,
        closed=closed,
        swing_rise=update.swing_rise,
    )
    if final:
        rows = tuple(np.concatenate([a, b]) for a, b in zip(rows, holder.flush()))
    t, p, v, q, stance = rows
    return FootUpdate(t, p, v, q, update.forward, stance)


def held_step(holder: FloorHolder, step: ClosedStep) -> ClosedStep:
    """The step's footprint at the height its stance was held at."""
    shift = holder.held_at(float(step.t))
    if shift is None:
        return step
    pos = np.array(step.position, dtype=float)
    pos[2] += shift
    return replace(step, position=pos)
