"""What a fusion returns (:class:`FusionResult`); a whole run's result is
:class:`footnav.pipeline.result.PipelineResult`, the files it writes :mod:`footnav.data.results`'."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

from footnav.core.types.trajectory import FootTrajectory, Path

__all__ = ["FusionResult"]


@dataclass(frozen=True, eq=False)
class FusionResult:
    """Output of a fusion strategy: both feet (right may be None) and the pedestrian path."""

    left: FootTrajectory
    right: FootTrajectory | None
    path: Path
    meta: Mapping[str, Any] = field(default_factory=dict)
