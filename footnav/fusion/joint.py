"""Two feet in one joint filter: what every coupled fusion starts and ends with.

A coupled fusion needs both feet in one nav frame. Each foot's IMU starts with its own, unknown
heading, so :func:`start_joint` first runs each foot alone (forward filter) to find the heading
of its first step, then starts the joint :class:`~footnav.core.ins_filter.InsFilter` with each
foot turned so that its first step points along +x and the feet ``step_width_m`` apart across it
(left foot at +y). :func:`finish_joint` smooths the run as the estimator says and returns both
feet and their midpoint path.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from footnav.core.errors import CompositionError
from footnav.core.ins_filter import InsFilter
from footnav.core.smoothing import smooth
from footnav.core.types import FusionResult, ImuData, StanceResult
from footnav.fusion.independent import midpoint_path

__all__ = ["start_joint", "finish_joint", "require_stepable", "check_two_feet"]

#: Feet indices in the joint filter.
LEFT, RIGHT = 0, 1


def check_two_feet(fusion: Any, estimator: Any, right: Any, stance_right: Any) -> None:
    """What every coupled fusion checks first: its parameters, both feet, a step-able estimator."""
    fusion.validate_params()
    if right is None or stance_right is None:
        raise CompositionError(f"fusion {fusion.name!r} needs both feet")
    require_stepable(fusion, estimator)


def require_stepable(fusion: Any, estimator: Any) -> None:
    """Raise CompositionError unless ``estimator`` exposes a step-able filter (``start``)."""
    if not callable(getattr(estimator, "start", None)):
        raise CompositionError(
            f"fusion {fusion.name!r} drives the per-foot filters step by step and needs an estimator "
            f"with a step-able filter (start(imus, stances)), such as 'ekf'; {estimator.name!r} has none"
        )
    if getattr(estimator, "closed_loop", False):
        raise CompositionError(
            f"fusion {fusion.name!r}: the estimator's closed_loop constraint is for one foot alone; "
            "turn it off for a two-foot fusion"
        )


def start_joint(
    estimator: Any,
    left: ImuData,
    stance_left: StanceResult,
    right: ImuData,
    stance_right: StanceResult,
    step_width_m: float,
    *,
    return_singles: bool = False,
):
    """The joint filter of both feet in one nav frame (x: the first step, z up, origin between
    the feet), ready to run; with ``return_singles`` also each foot's own forward solution
    (FootTrajectory, first step along +x)."""
    yaws, singles = [], []
    forward = estimator.clone(smoother="none", heading="first-step")
    for imu, stance in ((left, stance_left), (right, stance_right)):
        traj = forward.estimate(imu, stance)
        singles.append(traj)
        yaws.append(float(traj.meta.get("heading_rotation_rad", 0.0)))
    half = 0.5 * float(step_width_m)
    filt = estimator.start(
        [left, right], [stance_left, stance_right], initial_yaw_rad=yaws, initial_position_m=[np.array([0.0, half, 0.0]), np.array([0.0, -half, 0.0])]
    )
    return (filt, singles) if return_singles else filt


def finish_joint(estimator: Any, filt: InsFilter, stance_left: StanceResult, stance_right: StanceResult, meta: dict) -> FusionResult:
    """Run to the end, smooth as ``estimator.smoother`` says, and package both feet and the path."""
    filt.run_until()
    mode = getattr(estimator, "smoother", "none")
    smoothed = None if mode == "none" else smooth(filt, mode)
    left = estimator.trajectory(filt, LEFT, stance_left, smoothed)
    right = estimator.trajectory(filt, RIGHT, stance_right, smoothed)
    return FusionResult(left=left, right=right, path=midpoint_path(left, right), meta=meta)
