"""The error-state ZUPT-aided EKF (``ekf``): one concept per module, imports going one way.

=================  ===========================================================================
``buffers``        the per-sample arrays laid out against 4K aliasing
``records``        named types: noise, filter state, checkpoint, the smoother's record, scratch
``kernels``        compiled covariance prediction and feedback (the update: core/kalman.py)
``backward``       the compiled backward pass of the RTS smoother (Bryson-Frazier form)
``loop``           the compiled forward loop, which records and smooths as it runs
``filter``         :class:`InsFilter`, the step-able filter a fusion advances, with checkpoints
``smoother``       RTS smoothing of a run, step-wise or over the whole walk
``estimator``      :class:`EkfEstimator`, the registered ``ekf`` component
=================  ===========================================================================

Each module imports only those above it in this list (``loop`` the compiled ``backward`` pass
it runs; ``smoother`` the filter it smooths), never one below.
"""

from footnav.estimators.ekf.estimator import EkfEstimator
from footnav.estimators.ekf.filter import InsFilter
from footnav.estimators.ekf.records import Checkpoint, FilterNoise, FilterState
from footnav.estimators.ekf.smoother import SMOOTHERS, SegmentRecords, StepSmoother, smooth

__all__ = ["SMOOTHERS", "Checkpoint", "EkfEstimator", "FilterNoise", "FilterState", "InsFilter", "SegmentRecords", "StepSmoother", "smooth"]
