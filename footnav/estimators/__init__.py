"""Per-foot estimators: the ``estimator`` components.

Importing this package loads none of them: each class loads when first looked up.
"""

from footnav._lazy import lazy_exports

_EXPORTS = {"EkfEstimator": "footnav.estimators.ekf", "MadgwickEstimator": "footnav.estimators.madgwick"}
__all__ = ["EkfEstimator", "MadgwickEstimator"]  # the keys of _EXPORTS
__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS)
