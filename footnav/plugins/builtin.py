"""footnav's own components, registered through the same hooks a third-party plugin uses.

A new built-in is one module in detectors/, estimators/ or fusion/ plus one line here.
"""

from __future__ import annotations

from footnav.plugins.hookspecs import hookimpl


@hookimpl
def footnav_register_detectors(register):
    from footnav.detectors.adaptive import AdaptiveDetector
    from footnav.detectors.dual_gait import DualGaitDetector
    from footnav.detectors.glrt import GlrtDetector
    from footnav.detectors.hmm import HmmDetector
    from footnav.detectors.threshold import AccMagnitudeDetector, AccVarianceDetector, AredDetector, ThresholdDetector

    register(AdaptiveDetector)
    register(ThresholdDetector)
    register(AccMagnitudeDetector)
    register(AccVarianceDetector)
    register(AredDetector)
    register(GlrtDetector)
    register(DualGaitDetector)
    register(HmmDetector)


@hookimpl
def footnav_register_estimators(register):
    from footnav.estimators.ekf import EkfEstimator
    from footnav.estimators.madgwick import MadgwickEstimator

    register(EkfEstimator)
    register(MadgwickEstimator)


@hookimpl
def footnav_register_fusions(register):
    from footnav.fusion.dtw import DtwFusion
    from footnav.fusion.independent import IndependentFusion
    from footnav.fusion.particle import ParticleFusion
    from footnav.fusion.range_constraint import RangeConstraintFusion
    from footnav.fusion.step_vector import StepVectorFusion

    register(IndependentFusion)
    register(RangeConstraintFusion)
    register(StepVectorFusion)
    register(DtwFusion)
    register(ParticleFusion)
