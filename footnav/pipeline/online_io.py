"""What an online stream's push takes and returns (:mod:`footnav.pipeline.online`): a chunk's
``(t, acc, gyr)`` arrays from the forms a caller may give, one foot's final samples and forward
estimate (:class:`FootUpdate`, :class:`ForwardEstimate`) and the steps that closed
(:class:`ClosedStep`)."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from footnav.core.errors import InvalidInputError
from footnav.core.types import ImuData

__all__ = ["ClosedStep", "FootUpdate", "ForwardEstimate", "as_chunk", "empty_update"]


# -- what a push returns ----------------------------------------------------------------------


@dataclass(frozen=True)
class ForwardEstimate:
    """The forward filter's state at its newest sample (not final: later samples refine it).

    ``position_cov`` is the 3 x 3 position covariance (m^2) of the filter, in the nav frame
    (until the first step's heading is known: the sensor's initial heading, not yet turned).
    """

    t: float
    position: NDArray[np.float64]
    velocity: NDArray[np.float64]
    quaternion: NDArray[np.float64]
    position_cov: NDArray[np.float64]


@dataclass(frozen=True)
class ClosedStep:
    """One step that became final: the foot's stance ended at ``t`` (s).

    ``position`` is the footprint (mean position over the stance, m, nav frame),
    ``stride_length_m`` the horizontal distance from the foot's previous footprint and
    ``heading_rad`` its direction (about z from +x; nan for the first footprint).
    ``late`` is True when the step was released without waiting for the other foot
    (``max_wait_s`` ran out).
    """

    t: float
    foot: str
    position: NDArray[np.float64]
    stride_length_m: float
    heading_rad: float
    index: int
    late: bool = False


@dataclass(frozen=True)
class FootUpdate:
    """One foot's samples that became final in a push (smoothed per step, nav frame), and the
    forward estimate at its newest sample (None before the filter is aligned); ``stance`` is
    each sample's stance decision, ``swing_rise`` the swing's own rise at each stance's first
    update sample, NaN elsewhere (:func:`footnav.nav.floors.swing_rises`; None: not known)."""

    t: NDArray[np.float64]
    position: NDArray[np.float64]
    velocity: NDArray[np.float64]
    quaternion: NDArray[np.float64]
    forward: ForwardEstimate | None
    stance: NDArray[np.bool_] | None = None
    swing_rise: NDArray[np.float64] | None = None

    @property
    def n_samples(self) -> int:
        """Number of samples in the update."""
        return len(self.t)


def empty_update(forward: ForwardEstimate | None) -> FootUpdate:
    """An update with no final sample, carrying only the forward estimate."""
    z3 = np.empty((0, 3))
    return FootUpdate(np.empty(0), z3, z3.copy(), np.empty((0, 4)), forward, np.empty(0, dtype=bool))


# -- chunks -------------------------------------------------------------------------------------


def as_chunk(chunk: Any, foot: str) -> tuple[NDArray, NDArray, NDArray]:
    """``(t, acc, gyr)`` arrays (SI) of a chunk: an ImuData, a pandas DataFrame with columns ``t,
    acc_x..gyr_z``, a mapping with ``t``, ``acc``, ``gyr``, or a tuple ``(t, acc, gyr)``; one
    sample may be given as scalars and 3-vectors. Not yet checked: :class:`~footnav.pipeline.
    online_checks.ChunkChecks` checks shapes, values and time order."""
    if isinstance(chunk, ImuData):
        t, acc, gyr = chunk.t, chunk.acc, chunk.gyr
    elif hasattr(chunk, "columns") and hasattr(chunk, "iloc"):
        cols = [c for c in ("acc_x", "acc_y", "acc_z", "gyr_x", "gyr_y", "gyr_z", "t") if c not in chunk.columns]
        if cols:
            raise InvalidInputError(f"the {foot} foot's DataFrame chunk has no column(s) {cols}", field=foot)
        t = chunk["t"].to_numpy()
        acc = chunk[["acc_x", "acc_y", "acc_z"]].to_numpy()
        gyr = chunk[["gyr_x", "gyr_y", "gyr_z"]].to_numpy()
    elif isinstance(chunk, Mapping):
        try:
            t, acc, gyr = chunk["t"], chunk["acc"], chunk["gyr"]
        except KeyError as exc:
            raise InvalidInputError(
                f"the {foot} foot's chunk has no {exc.args[0]!r}; give t, acc, gyr", field=foot
            ) from None
    elif isinstance(chunk, (tuple, list)) and len(chunk) == 3:
        t, acc, gyr = chunk
    else:
        raise InvalidInputError(
            f"the {foot} foot's chunk is a {type(chunk).__name__}; give an ImuData, a DataFrame, "
            "a mapping {'t', 'acc', 'gyr'} or a tuple (t, acc, gyr)",
            field=foot,
        )
    # one sample as scalars and 3-vectors; shapes, values and time order are checked by the
    # stream's input checks (footnav.pipeline.online_checks), which name the sample's index
    t = np.atleast_1d(np.asarray(t))
    acc, gyr = np.asarray(acc), np.asarray(gyr)
    if t.shape == (1,):
        acc = acc.reshape(1, 3) if acc.shape == (3,) else acc
        gyr = gyr.reshape(1, 3) if gyr.shape == (3,) else gyr
    return t, acc, gyr
