"""Independent feet: each foot is estimated alone; the pedestrian is the midpoint of the feet.

The baseline every dual-foot method is compared with. With two feet the path is the midpoint of the
feet on the left foot's time grid (the right foot interpolated linearly, within the common time
span); with one foot the path is that foot.

Each foot is estimated over its own whole time span. When the feet's spans differ markedly
(starts or ends more than 2 s or 5 % of the longer recording apart,
:func:`footnav.nav.spans.span_difference`) the fusion warns (DataQualityWarning); the spans and
their differences are in ``meta["span"]`` whenever both feet are given.
"""

from __future__ import annotations

from typing import cast

import numpy as np

from footnav.core.component import FootEstimator, Fusion
from footnav.core.errors import DataQualityWarning
from footnav.core.types import FootTrajectory, FusionResult, ImuData, Path, StanceResult
from footnav.core.warning_log import warn
from footnav.nav.interpolation import interp_columns
from footnav.nav.spans import span_difference

__all__ = ["IndependentFusion", "midpoint_path"]


def midpoint_path(left: FootTrajectory, right: FootTrajectory | None) -> Path:
    """Midpoint of both feet on the left foot's times within the common span (or the one foot)."""
    if right is None:
        return Path(t=left.t, position=left.position, meta={"path": "single foot"})
    lo, hi = max(left.t[0], right.t[0]), min(left.t[-1], right.t[-1])
    keep = (left.t >= lo) & (left.t <= hi)
    # where t increases (any estimator's) the kept samples are one run: a slice, not a copy
    # through a boolean mask of the (N, 3) positions
    i0, i1 = int(np.argmax(keep)), len(keep) - int(np.argmax(keep[::-1]))
    if keep[i0:i1].all():
        keep = slice(i0, i1)
    t = left.t[keep]
    right_pos = interp_columns(t, right.t, right.position[:, :3])
    return Path(t=t, position=0.5 * (left.position[keep] + right_pos), meta={"path": "midpoint of the feet"})


class IndependentFusion(Fusion):
    """Each foot alone through the per-foot estimator; path = midpoint of the feet.

    Takes no parameters.
    """

    name = "independent"

    def __init__(self) -> None:
        pass

    def fuse(
        self,
        estimator: FootEstimator,
        left: ImuData,
        stance_left: StanceResult,
        right: ImuData | None = None,
        stance_right: StanceResult | None = None,
    ) -> FusionResult:
        """Estimate each foot with ``estimator`` and average them into the pedestrian path."""
        meta: dict = {"fusion": self.describe()}
        if right is not None and len(left.t) and len(right.t):
            diff = span_difference(left, right)
            if diff["marked"]:
                warn(f"fusion {self.name!r}: {diff['message']}", DataQualityWarning, stacklevel=3)
            meta["span"] = {k: v for k, v in diff.items() if k != "message"}
        traj_left = estimator.estimate(left, stance_left)
        # stance_right comes with right (the pipeline detects both feet)
        traj_right = None if right is None else estimator.estimate(right, cast(StanceResult, stance_right))
        return FusionResult(left=traj_left, right=traj_right, path=midpoint_path(traj_left, traj_right), meta=meta)
