"""Stance detectors: the ``detector`` components (one module each; the registry names them).

Importing this package loads none of them: each class loads when first looked up.
"""

from footnav._lazy import lazy_exports

_EXPORTS = {
    "AdaptiveDetector": "footnav.detectors.adaptive",
    "ThresholdDetector": "footnav.detectors.threshold",
    "AccMagnitudeDetector": "footnav.detectors.threshold",
    "AccVarianceDetector": "footnav.detectors.threshold",
    "AredDetector": "footnav.detectors.threshold",
    "GlrtDetector": "footnav.detectors.glrt",
    "DualGaitDetector": "footnav.detectors.dual_gait",
    "HmmDetector": "footnav.detectors.hmm",
}
__all__ = [
    "AccMagnitudeDetector",
    "AccVarianceDetector",
    "AdaptiveDetector",
    "AredDetector",
    "DualGaitDetector",
    "GlrtDetector",
    "HmmDetector",
    "ThresholdDetector",
]  # the keys of _EXPORTS
__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS)
