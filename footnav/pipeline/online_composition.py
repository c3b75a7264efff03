"""Which pipelines can run online, and why the others cannot (:mod:`footnav.pipeline.online`).

:func:`check_online` is asked when a stream is made: a pipeline with a component that cannot
decide or estimate as samples arrive is refused there, with a message naming the component and
why (docs/online.md has the table).
"""

from __future__ import annotations

from typing import Any

from footnav.core.errors import CompositionError
from footnav.core.online_contract import online_gaps

__all__ = ["COUPLED_ONLINE_FUSIONS", "OFFLINE_ONLY_FUSIONS", "ONLINE_FUSIONS", "check_online"]

#: Fusions of each foot alone: they run online on per-foot filters.
ONLINE_FUSIONS = ("independent",)
#: Built-in coupled fusions that run online, on a joint filter fed by both feet (their
#: ``session``, :class:`footnav.core.component.FusionSession`; a plugin's fusion runs online the same
#: way when it offers one).
COUPLED_ONLINE_FUSIONS = ("range", "step-vector", "particle")
#: Why the other built-in fusions are offline only.
OFFLINE_ONLY_FUSIONS = {
    "dtw": "it averages the feet's whole walks (dynamic time warping needs both sequences complete)"
}


def check_online(pipeline: Any, feet: int) -> float:
    """The detector's latency (s) when the pipeline can run online; else InvalidParameterError or
    CompositionError saying which component cannot and why."""
    det, est, fus = pipeline.detector, pipeline.estimator, pipeline.fusion
    latency = det.latency_s
    if latency is None:
        raise CompositionError(
            f"detector {det.name!r} cannot run online: its decision on a sample depends on samples without "
            f"bound (it declares latency_s = None); use a windowed detector such as 'adaptive', 'threshold' or 'glrt'"
        )
    if fus.needs_two_feet and feet < 2:
        raise CompositionError(f"fusion {fus.name!r} needs both feet (feet=2)")
    if getattr(det, "needs_two_feet", False) and feet < 2:
        raise CompositionError(f"detector {det.name!r} needs both feet (feet=2): it detects them together")
    aid = getattr(pipeline, "heading_aid", None)
    if aid is not None and not aid.online:
        raise CompositionError(
            f"heading aid {aid.name!r} is offline only: it learns from the whole walk; online, use heading_aid=None"
        )
    if fus.name not in ONLINE_FUSIONS and not callable(getattr(fus, "session", None)):
        why = OFFLINE_ONLY_FUSIONS.get(
            fus.name, "it offers no session (footnav.core.component.FusionSession) to run as samples arrive"
        )
        online = [*ONLINE_FUSIONS, *COUPLED_ONLINE_FUSIONS]
        raise CompositionError(
            f"fusion {fus.name!r} is offline only: {why}; online mode runs {', '.join(repr(n) for n in online)}"
        )
    if fus.name not in ONLINE_FUSIONS:
        if feet < 2:
            raise CompositionError(f"fusion {fus.name!r} fuses both feet in one filter online: it needs feet=2")
        fus.session(est, 0.0)  # refuses parameters that need the whole walk (CompositionError)
    gaps = online_gaps(est)
    if gaps:
        raise CompositionError(
            f"estimator {est.name!r} has no step-able filter a stream can run "
            "(footnav.core.online_contract.OnlineEstimator: start(imus, stances) and the rest); "
            f"it lacks {', '.join(gaps)}; online mode needs one, such as 'ekf'"
        )
    est.validate_params()
    if getattr(est, "smoother", None) not in ("whole", "step", "none"):
        raise CompositionError(
            f"estimator {est.name!r} with smoother={getattr(est, 'smoother', None)!r} cannot run online: expected "
            "'whole' (step-wise live, the whole walk at close), 'step' or 'none'"
        )
    if getattr(est, "closed_loop", False):
        raise CompositionError(f"estimator {est.name!r} with closed_loop=True is offline only: it needs the walk's end")
    if getattr(est, "zupt_start_delay_s", 0.0) or getattr(est, "zupt_end_advance_s", 0.0):
        raise CompositionError(
            f"estimator {est.name!r} with zupt_start_delay_s or zupt_end_advance_s is offline only for now: "
            "the stance's edges are cut on the whole mask before the run"
        )
    if getattr(est, "clip_excess_mps2", 0.0):
        raise CompositionError(
            f"estimator {est.name!r} with clip_excess_mps2 > 0 is offline only for now: the clipped samples "
            "are found on the whole recording before the run"
        )
    return float(latency)
