"""The error-state ZUPT-aided EKF (``ekf``): one concept per module, imports going one way.

=================  ===========================================================================
``_buffers``       the per-sample arrays laid out against 4K aliasing
``_records``       named types: noise, filter state, checkpoint, the event log, scratch
``_kernels``       compiled covariance prediction and feedback (the update: nav/kalman.py)
``_backward``      the compiled backward pass of the RTS smoother over the event log
``_loop``          the compiled forward loop, which records and smooths as it runs
``_measurements``  the filter's updates from outside its ZUPT: a caller's, the range constraint's
``filter``         :class:`InsFilter`, the step-able filter a fusion advances, with checkpoints
``smoother``       RTS smoothing of a run, step-wise or over the whole walk
``online``         :class:`OnlineInsFilter`, the filter a stream runs in segments
``estimator``      :class:`EkfEstimator`, the registered ``ekf`` component
=================  ===========================================================================

Each module imports only those above it in this list (``_loop`` the compiled ``_backward``
pass it runs; ``smoother`` the filter it smooths), never one below. The modules with a leading
underscore are internals (their names and layouts change without notice); the public classes
are the ones a caller builds or is handed (the filter, its online form, the smoothers, the
estimator) and the named types they take and give (:class:`FilterNoise`, :class:`FilterState`,
:class:`Checkpoint`), all importable from this package.
"""

from footnav.estimators.ekf._records import Checkpoint, FilterNoise, FilterState
from footnav.estimators.ekf.estimator import EkfEstimator
from footnav.estimators.ekf.filter import MAX_SEGMENT_EVENTS, InsFilter
from footnav.estimators.ekf.online import OnlineInsFilter
from footnav.estimators.ekf.smoother import SMOOTHERS, SegmentRecords, StepSmoother, smooth

__all__ = [
    "MAX_SEGMENT_EVENTS",
    "SMOOTHERS",
    "Checkpoint",
    "EkfEstimator",
    "FilterNoise",
    "FilterState",
    "InsFilter",
    "OnlineInsFilter",
    "SegmentRecords",
    "StepSmoother",
    "smooth",
]
