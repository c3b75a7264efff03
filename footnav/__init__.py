"""footnav: foot-mounted inertial navigation, one or two feet, as composable components.

The public API::

    import footnav
    rec = footnav.simulate("rectangle", seed=1)
    result = footnav.make_pipeline("threshold", "ekf", "independent").run(rec.left, rec.right)
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from footnav._lazy import lazy_exports
from footnav.core.component import FootEstimator, Fusion, HeadingAid, StanceDetector
from footnav.core.types import (
    GRAVITY_MPS2,
    FootTrajectory,
    FootTruth,
    FusionResult,
    ImuData,
    Path,
    Recording,
    StanceResult,
)
from footnav.core.warning_log import warn
from footnav.errors import (
    CompositionError,
    DataNotFoundError,
    DataQualityWarning,
    FootnavError,
    FootnavWarning,
    InvalidInputError,
    InvalidParameterError,
    MetricNotFoundError,
    PluginError,
    PluginWarning,
    UnknownComponentError,
)
from footnav.pipeline.factory import (
    Pipeline,
    list_components,
    load_pipeline,
    make_detector,
    make_estimator,
    make_fusion,
    make_heading_aid,
    make_pipeline,
)
from footnav.pipeline.result import PipelineResult
from footnav.plugins.hookspecs import hookimpl

if TYPE_CHECKING:
    from footnav._version import __version__
    from footnav.analysis.batch import evaluate_many
    from footnav.analysis.comparison import DetectorComparison, compare_detectors
    from footnav.analysis.evaluation import EvaluationReport, evaluate

#: Public names loaded on first use (PEP 562): the analysis layer pulls in scipy.optimize and the
#: metrics, which ``import footnav`` (and ``footnav run``) do not need; the version reads the
#: installed metadata (importlib.metadata, ~10 ms).
_LAZY = {
    "__version__": "footnav._version",
    "evaluate": "footnav.analysis.evaluation",
    "EvaluationReport": "footnav.analysis.evaluation",
    "evaluate_many": "footnav.analysis.batch",
    "compare_detectors": "footnav.analysis.comparison",
    "DetectorComparison": "footnav.analysis.comparison",
}


__getattr__, __dir__ = lazy_exports(__name__, _LAZY)


def simulate(scenario: str = "straight", *, seed: int = 0, rate_hz: float = 100.0, **options) -> Recording:
    """Simulated two-foot walk with truth; see :func:`footnav.data.simulate.simulate`."""
    from footnav.data.simulate import simulate as _simulate

    return _simulate(scenario, seed=seed, rate_hz=rate_hz, **options)


def load(path, format: str | None = None, **options) -> Recording:
    """Read a recording, guessing its format; see :func:`footnav.data.io.load`."""
    from footnav.data.io import load as _load

    return _load(path, format=format, **options)


__all__ = [
    "__version__",
    "hookimpl",
    "simulate",
    "load",
    "make_pipeline",
    "load_pipeline",
    "evaluate",
    "evaluate_many",
    "EvaluationReport",
    "compare_detectors",
    "DetectorComparison",
    "make_detector",
    "make_estimator",
    "make_fusion",
    "make_heading_aid",
    "list_components",
    "Pipeline",
    "StanceDetector",
    "FootEstimator",
    "Fusion",
    "HeadingAid",
    "ImuData",
    "StanceResult",
    "FootTrajectory",
    "FootTruth",
    "Path",
    "FusionResult",
    "PipelineResult",
    "Recording",
    "GRAVITY_MPS2",
    "FootnavError",
    "InvalidInputError",
    "InvalidParameterError",
    "MetricNotFoundError",
    "UnknownComponentError",
    "CompositionError",
    "PluginError",
    "DataNotFoundError",
    "FootnavWarning",
    "DataQualityWarning",
    "warn",
    "PluginWarning",
]
