"""The data objects that flow between footnav's stages.

recording (:class:`ImuData`) -> detector (:class:`StanceResult`) -> estimator
(:class:`FootTrajectory`) -> fusion (:class:`FusionResult`) -> the pipeline's
:class:`footnav.pipeline.result.PipelineResult`.

All are frozen dataclasses of read-only numpy arrays, SI units, samples on axis 0. Each type names
its frame in a ``frame`` attribute:

* ``"body"`` -- the sensor's own axes (accelerometer and gyroscope axes).
* ``"nav"`` -- footnav's navigation frame: z up, gravity ``[0, 0, -GRAVITY_MPS2]``, x the initial
  walking direction (or the sensor's initial heading when no step is known), origin at the start.

One concept per module, each importing only those above it in this list (and the private array
helpers of ``_arrays``); every public name is re-exported here:

* :mod:`~footnav.core.types.units` -- ``GRAVITY_MPS2`` and the unit scale factors;
* :mod:`~footnav.core.types.imu_checks` -- the plausibility checks of sensor data and their
  thresholds (``RATE_BOUNDS_HZ``, ``CLIP_*``, ...), :func:`detect_clipping`;
* :mod:`~footnav.core.types.imu` -- :class:`ImuData`, ``GAP_FACTOR``;
* :mod:`~footnav.core.types.stance` -- :class:`StanceResult`, :func:`stance_intervals`;
* :mod:`~footnav.core.types.trajectory` -- :class:`FootTrajectory`, :class:`Path`;
* :mod:`~footnav.core.types.results` -- :class:`FusionResult`;
* :mod:`~footnav.core.types.recording` -- :class:`FootTruth`, :class:`Recording`.
"""

from __future__ import annotations

# every public name footnav.core.types held when it was one module stays importable from here
from footnav.core.types.imu import GAP_FACTOR, ImuData, ReadOnlyMeta  # noqa: F401  (ReadOnlyMeta: importable as before)
from footnav.core.types.imu_checks import (  # noqa: F401  (the check thresholds: importable as before)
    ACC_FULL_SCALES_G,
    ACC_MEDIAN_BOUNDS_MPS2,
    ACC_MOVING_FRACTION,
    ACC_MOVING_MPS2,
    ACC_REST_ERROR_FRACTION,
    ACC_REST_WARN_FRACTION,
    CLIP_FRACTION_OF_FULL_SCALE,
    CLIP_MIN_ACC_MPS2,
    CLIP_MIN_GYR_RADPS,
    CLIP_MIN_REPEATS,
    FULL_SCALE_RATIO,
    GYR_FULL_SCALES_DPS,
    GYR_PEAK_MAX_RADPS,
    GYR_PEAK_MIN_RADPS,
    PEAK_HOLD_S,
    RATE_BOUNDS_HZ,
    RATE_ERROR_HZ,
    REST_ACC_REL_STD,
    REST_GYR_RADPS,
    REST_MIN_S,
    REST_WINDOW_S,
    clipped_acc,
    detect_clipping,
)
from footnav.core.types.recording import FootTruth, Recording
from footnav.core.types.results import FusionResult
from footnav.core.types.stance import StanceResult, stance_intervals
from footnav.core.types.trajectory import FootTrajectory, Path
from footnav.core.types.units import GRAVITY_MPS2

__all__ = [
    "GAP_FACTOR",
    "GRAVITY_MPS2",
    "RATE_BOUNDS_HZ",
    "RATE_ERROR_HZ",
    "FootTrajectory",
    "FootTruth",
    "FusionResult",
    "ImuData",
    "Path",
    "Recording",
    "StanceResult",
    "clipped_acc",
    "detect_clipping",
    "stance_intervals",
]
