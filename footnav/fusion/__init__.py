"""Dual-foot fusions: the ``fusion`` components.

Importing this package loads none of them: each class loads when first looked up.
"""

from footnav._lazy import lazy_exports

_EXPORTS = {
    "IndependentFusion": "footnav.fusion.independent",
    "RangeConstraintFusion": "footnav.fusion.range_constraint",
    "StepVectorFusion": "footnav.fusion.step_vector",
    "DtwFusion": "footnav.fusion.dtw",
    "ParticleFusion": "footnav.fusion.particle",
}
__all__ = [
    "DtwFusion",
    "IndependentFusion",
    "ParticleFusion",
    "RangeConstraintFusion",
    "StepVectorFusion",
]  # the keys of _EXPORTS
__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS)
