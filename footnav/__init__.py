"""footnav: foot-mounted inertial navigation, one or two feet, as composable components.

The public API::

    import footnav
    rec = footnav.simulate("rectangle", seed=1)
    result = footnav.make_pipeline("threshold", "ekf", "independent").run(rec.left, rec.right)
"""

from __future__ import annotations

from importlib.metadata import PackageNotFoundError, version

from footnav.core.component import FootEstimator, Fusion, StanceDetector
from footnav.core.errors import (
    CompositionError,
    DataNotFoundError,
    DataQualityWarning,
    FootnavError,
    FootnavWarning,
    InvalidInputError,
    InvalidParameterError,
    PluginError,
    PluginWarning,
    UnknownComponentError,
)
from footnav.core.comparison import DetectorComparison, compare_detectors
from footnav.core.batch import evaluate_many
from footnav.core.evaluation import EvaluationReport, evaluate
from footnav.core.warning_log import warn
from footnav.core.pipeline import (
    Pipeline,
    list_components,
    load_pipeline,
    make_detector,
    make_estimator,
    make_fusion,
    make_pipeline,
)
from footnav.core.types import (
    GRAVITY_MPS2,
    FootTrajectory,
    FootTruth,
    FusionResult,
    ImuData,
    Path,
    PipelineResult,
    Recording,
    StanceResult,
)
from footnav.plugins.hookspecs import hookimpl

try:
    __version__ = version("footnav")
except PackageNotFoundError:  # running from a source tree that is not installed
    __version__ = "0+unknown"


def simulate(scenario: str = "straight", *, seed: int = 0, rate_hz: float = 100.0, **options) -> Recording:
    """Simulated two-foot walk with truth; see :func:`footnav.core.simulate.simulate`."""
    from footnav.core.simulate import simulate as _simulate

    return _simulate(scenario, seed=seed, rate_hz=rate_hz, **options)


def load(path, format: str | None = None, **options) -> Recording:
    """Read a recording, guessing its format; see :func:`footnav.core.io.load`."""
    from footnav.core.io import load as _load

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
    "list_components",
    "Pipeline",
    "StanceDetector",
    "FootEstimator",
    "Fusion",
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
    "UnknownComponentError",
    "CompositionError",
    "PluginError",
    "DataNotFoundError",
    "FootnavWarning",
    "DataQualityWarning",
    "warn",
    "PluginWarning",
]
