"""Accuracy metrics for foot-mounted inertial navigation, as defined in footnav's seed papers.

Plain functions on numpy arrays, SI units (positions in m, times in s, event positions in
samples). Positions are ``(N, 2)`` or ``(N, 3)`` arrays in one frame, samples on axis 0; the
``dims`` keyword selects the horizontal plane (``dims=2``: x, y) or full 3-D (``dims=3``).

References (full citations in docs/references.md):

* [Zhao2019] Zhao et al., IEEE Sensors J. 2019 -- final foot separation E_s and final position error
  E_p, eq. (8), Table I.
* [Chistyakov2021] Chistyakov et al., Russian Technological J. 2021 -- DTW distance between the left and the
  right foot with a limit on the index difference (section 3, Table 1); maximum deviation from the
  RTK reference and its maximum ratio to the distance travelled (Table 2).
* [Li2018] Li, Derrode et al., TAIMA 2018 -- steps found / missing / false (Table 1); end-to-end
  error, travelled distance and its relative error, DTW distance (Table 2).
* [Lee2022] Lee, Cho, Park, JPNT 2022 -- position error at surveyed waypoints (Table 3).

Dataset papers whose truth some metrics are shaped for:

* [IPOL] Voisard, de l'Escalopier, Ricard, Oudre, "A Reference Data Set for the Study of Healthy
  Subject Gait with Inertial Measurement Units", IPOL 13 (2023), art. 497 -- hand-checked
  swings (toe-off, heel strike) inside trial boundaries: :func:`step_detection_from_swings`.
* [GD] Cetin & Koroglu, "A Stride-Wise Annotated Mini-Dataset for Gait-Driven Learning-Based
  Inertial Navigation", Turk. J. EE&CS 2026 -- hand-marked footprint positions:
  :func:`footprint_errors`.

Trajectory metrics compare arrays *as given*: none of them aligns frames implicitly. Use
:func:`rigid_align` first when the reference lives in another frame (motion capture, RTK).

One concept per module, all re-exported here (import from ``footnav.analysis.metrics``):
``_alignment`` (rigid fits), ``_trajectory`` (ATE, waypoint, end-point and distance errors),
``_deviation`` (DTW distance, maximum deviation), ``_strides`` (stride-length and footprint
errors), ``_matching`` (one-to-one event matching, event timing), ``_stance`` (steps found /
missed / false, per-sample scores) and ``_checks`` (the input checks they share).
"""

from __future__ import annotations

from footnav.analysis.metrics._alignment import RigidAlignment, align_at_start, align_on_first_steps, rigid_align
from footnav.analysis.metrics._deviation import (
    DEFAULT_RATIO_MIN_DISTANCE_M,
    DtwResult,
    MaxDeviation,
    dtw_distance,
    interpolate_positions,
    max_deviation,
)
from footnav.analysis.metrics._matching import EventMatches, TimingError, event_timing_error, match_events
from footnav.analysis.metrics._stance import (
    SampleScores,
    StepDetection,
    sample_scores,
    step_detection,
    step_detection_from_events,
    step_detection_from_swings,
)
from footnav.analysis.metrics._strides import (
    FootprintErrors,
    StrideLengthErrors,
    footprint_errors,
    stride_length_errors,
)
from footnav.analysis.metrics._trajectory import (
    DistanceError,
    EndpointError,
    WaypointErrors,
    ate_rmse,
    end_to_end_error,
    final_position_error,
    final_separation,
    height_rmse,
    loop_closure_error,
    travelled_distance,
    travelled_distance_error,
    waypoint_errors,
)

__all__ = [
    "DEFAULT_RATIO_MIN_DISTANCE_M",
    "RigidAlignment",
    "EndpointError",
    "DistanceError",
    "DtwResult",
    "MaxDeviation",
    "StrideLengthErrors",
    "FootprintErrors",
    "EventMatches",
    "StepDetection",
    "SampleScores",
    "TimingError",
    "WaypointErrors",
    "rigid_align",
    "align_at_start",
    "align_on_first_steps",
    "waypoint_errors",
    "ate_rmse",
    "height_rmse",
    "final_separation",
    "final_position_error",
    "travelled_distance",
    "travelled_distance_error",
    "end_to_end_error",
    "loop_closure_error",
    "interpolate_positions",
    "dtw_distance",
    "max_deviation",
    "stride_length_errors",
    "footprint_errors",
    "match_events",
    "step_detection",
    "step_detection_from_events",
    "step_detection_from_swings",
    "sample_scores",
    "event_timing_error",
]
