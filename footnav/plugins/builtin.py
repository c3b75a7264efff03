"""footnav's own components, registered through the same hooks a third-party plugin uses.

A new built-in is one module in detectors/, estimators/, fusion/ or heading_aids/ plus one line here. Each class
is registered by reference (``"module:Class"``, with its name) and imported when first used, so
that building the registry (every ``make_pipeline``) imports only the components it runs.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from footnav.plugins.hookspecs import Register, hookimpl

if TYPE_CHECKING:  # the classes named below (for readers, type checkers and tests/test_layers.py)
    from footnav.detectors.adaptive import AdaptiveDetector  # noqa: F401
    from footnav.detectors.dual_gait import DualGaitDetector  # noqa: F401
    from footnav.detectors.glrt import GlrtDetector  # noqa: F401
    from footnav.detectors.hmm import HmmDetector  # noqa: F401
    from footnav.detectors.threshold import AccMagnitudeDetector, AccVarianceDetector, AredDetector, ThresholdDetector  # noqa: F401
    from footnav.estimators.ekf import EkfEstimator  # noqa: F401
    from footnav.estimators.madgwick import MadgwickEstimator  # noqa: F401
    from footnav.fusion.dtw import DtwFusion  # noqa: F401
    from footnav.fusion.independent import IndependentFusion  # noqa: F401
    from footnav.fusion.particle import ParticleFusion  # noqa: F401
    from footnav.fusion.range_constraint import RangeConstraintFusion  # noqa: F401
    from footnav.fusion.step_vector import StepVectorFusion  # noqa: F401
    from footnav.heading_aids.dominant_directions import DominantDirectionsAid  # noqa: F401
    from footnav.heading_aids.magnetometer import MagnetometerAid  # noqa: F401
    from footnav.heading_aids.none import NoHeadingAid  # noqa: F401

#: kind -> (name, "module:Class"), in registration order. tests/plugins checks each name against
#: its class's ``name``.
BUILTINS = {
    "detector": [
        ("adaptive", "footnav.detectors.adaptive:AdaptiveDetector"),
        ("threshold", "footnav.detectors.threshold:ThresholdDetector"),
        ("acc-magnitude", "footnav.detectors.threshold:AccMagnitudeDetector"),
        ("acc-variance", "footnav.detectors.threshold:AccVarianceDetector"),
        ("ared", "footnav.detectors.threshold:AredDetector"),
        ("glrt", "footnav.detectors.glrt:GlrtDetector"),
        ("dual-gait", "footnav.detectors.dual_gait:DualGaitDetector"),
        ("hmm", "footnav.detectors.hmm:HmmDetector"),
    ],
    "estimator": [
        ("ekf", "footnav.estimators.ekf:EkfEstimator"),
        ("madgwick", "footnav.estimators.madgwick:MadgwickEstimator"),
    ],
    "fusion": [
        ("independent", "footnav.fusion.independent:IndependentFusion"),
        ("range", "footnav.fusion.range_constraint:RangeConstraintFusion"),
        ("step-vector", "footnav.fusion.step_vector:StepVectorFusion"),
        ("dtw", "footnav.fusion.dtw:DtwFusion"),
        ("particle", "footnav.fusion.particle:ParticleFusion"),
    ],
    "heading_aid": [
        ("none", "footnav.heading_aids.none:NoHeadingAid"),
        ("dominant-directions", "footnav.heading_aids.dominant_directions:DominantDirectionsAid"),
        ("magnetometer", "footnav.heading_aids.magnetometer:MagnetometerAid"),
    ],
}


@hookimpl
def footnav_register_detectors(register: Register) -> None:
    """Register the built-in stance detectors."""
    for name, ref in BUILTINS["detector"]:
        register(ref, name=name)


@hookimpl
def footnav_register_estimators(register: Register) -> None:
    """Register the built-in per-foot estimators."""
    for name, ref in BUILTINS["estimator"]:
        register(ref, name=name)


@hookimpl
def footnav_register_fusions(register: Register) -> None:
    """Register the built-in fusions."""
    for name, ref in BUILTINS["fusion"]:
        register(ref, name=name)


@hookimpl
def footnav_register_heading_aids(register: Register) -> None:
    """Register the built-in heading aids."""
    for name, ref in BUILTINS["heading_aid"]:
        register(ref, name=name)
