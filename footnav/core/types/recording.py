"""A recording of one or both feet (:class:`Recording`) and the reference motion it may carry (:class:`FootTruth`)."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from footnav.core.errors import InvalidInputError
from footnav.core.types._arrays import _readonly
from footnav.core.types.imu import ImuData

__all__ = ["FootTruth", "Recording"]


@dataclass(frozen=True, eq=False)
class FootTruth:
    """Reference motion of one foot, as far as a recording or the simulator knows it.

    Parameters
    ----------
    t
        Times in s of the reference samples, on the IMU's clock, shape (M,). May differ from the
        IMU's times (e.g. motion capture at 100 Hz); may be empty when only ``closed_loop`` is known.
    position
        Reference position in m, (M, 3), in ``frame``. Readers convert to z up; origin and heading
        are the reference system's own, so align before comparing (see ``footnav.analysis.metrics``).
    quaternion
        Reference orientation [w, x, y, z], body -> ``frame``, (M, 4), or None.
    velocity
        Reference velocity in m/s, (M, 3), or None.
    stance
        Reference stance mask over the IMU samples (N,), or None. ``meta["stance_source"]`` says
        what it is (simulator truth, mocap-derived, proxy labels of another detector).
    events
        Reference gait events as IMU sample indices (``heel_strike``, ``foot_flat``, ``heel_off``,
        ``toe_off``, ``mid_stance``), possibly empty.
    closed_loop
        True when the walk is known to end where it started.
    frame
        ``"nav"`` for the simulator (footnav's nav frame), else the reference system's name
        (``"vicon"``, ``"mocap"``, ...), always z up after the reader's conversion.
    """

    t: NDArray[np.float64]
    position: NDArray[np.float64]
    quaternion: NDArray[np.float64] | None = None
    velocity: NDArray[np.float64] | None = None
    stance: NDArray[np.bool_] | None = None
    events: Mapping[str, NDArray[np.int64]] = field(default_factory=dict)
    closed_loop: bool = False
    frame: str = "nav"
    meta: Mapping[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        t = np.asarray(self.t, dtype=np.float64).reshape(-1)
        m = len(t)
        object.__setattr__(self, "t", _readonly(t))
        pos = np.asarray(self.position, dtype=np.float64).reshape(-1, 3) if m else np.empty((0, 3))
        if len(pos) != m:
            raise InvalidInputError(f"expected shape ({m}, 3), got {pos.shape}", field="position")
        object.__setattr__(self, "position", _readonly(pos))
        for name, cols in (("quaternion", 4), ("velocity", 3)):
            val = getattr(self, name)
            if val is not None:
                arr = np.asarray(val, dtype=np.float64)
                if arr.shape != (m, cols):
                    raise InvalidInputError(f"expected shape ({m}, {cols}), got {arr.shape}", field=name)
                object.__setattr__(self, name, _readonly(arr))
        if self.stance is not None:
            object.__setattr__(self, "stance", _readonly(np.asarray(self.stance, dtype=bool)))
        object.__setattr__(
            self, "events", {k: _readonly(np.asarray(v, dtype=np.int64)) for k, v in dict(self.events or {}).items()}
        )
        object.__setattr__(self, "meta", dict(self.meta))


@dataclass(frozen=True, eq=False)
class Recording:
    """A recording of one or both feet with whatever reference it carries.

    ``left`` is the only foot of a one-foot recording (``right`` is None then). ``truth_left`` and
    ``truth_right`` are None when the recording has no reference for that foot. ``meta`` holds the
    reader's name (``"format"``), the source files and every change the reader made.
    """

    left: ImuData
    right: ImuData | None = None
    truth_left: FootTruth | None = None
    truth_right: FootTruth | None = None
    name: str = ""
    meta: Mapping[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        object.__setattr__(self, "meta", dict(self.meta))

    @property
    def n_feet(self) -> int:
        """1 or 2: the feet recorded."""
        return 1 if self.right is None else 2
