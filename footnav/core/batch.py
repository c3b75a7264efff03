"""Batch evaluation: many pipelines on many recordings, serially, on local processes or on Dask.

:func:`evaluate_many` runs :func:`~footnav.core.evaluation.evaluate` for every (recording,
pipeline) pair and joins the reports in that order, whatever order the runs finish in, so a
parallel run gives the same table as a serial one (but for the ``runtime`` rows). Locally it uses
joblib's ``loky`` processes (``n_jobs``); with ``backend="dask"`` it submits to a Dask
distributed scheduler (``scheduler`` address, or the current client, or a new in-process one)
when one machine is outgrown. A progress bar (tqdm, optional) shows on a terminal.
"""

from __future__ import annotations

import os
import sys
from typing import Any, Callable, Iterable, Literal, Mapping, Sequence

from footnav.core.errors import InvalidParameterError
from footnav.core.evaluation import EvaluationReport, evaluate
from footnav.core.pipeline import Pipeline
from footnav.core.types import Recording

__all__ = ["evaluate_many", "BACKENDS"]

BACKENDS = ("loky", "dask")


def _named(pipelines: Any) -> list[tuple[str, Pipeline]]:
    """(name, pipeline) pairs from a mapping, pairs, or bare pipelines (named by their components)."""
    if isinstance(pipelines, Pipeline):
        pipelines = [pipelines]
    items = pipelines.items() if isinstance(pipelines, Mapping) else pipelines
    out = []
    for item in items:
        if isinstance(item, Pipeline):
            out.append(("+".join(c.name for c in item.components), item))
        else:
            name, pipe = item
            out.append((str(name), pipe))
    names = [n for n, _ in out]
    dup = {n for n in names if names.count(n) > 1}
    if dup:
        raise InvalidParameterError(f"evaluate_many: pipeline names must be unique; repeated: {sorted(dup)} (pass a dict name -> pipeline)")
    return out


def _materialise(recording: Any) -> Recording:
    """A Recording from a Recording, a path (read with footnav.load) or a zero-argument callable."""
    if isinstance(recording, Recording):
        return recording
    if isinstance(recording, (str, os.PathLike)):
        from footnav.core.io import load

        return load(recording)
    if callable(recording):
        rec = recording()
        if not isinstance(rec, Recording):
            raise InvalidParameterError(f"evaluate_many: the recording factory {recording!r} returned {type(rec).__name__}, not a Recording")
        return rec
    raise InvalidParameterError(
        f"evaluate_many: a recording must be a Recording, a path or a zero-argument callable; got {type(recording).__name__}"
    )


def _run_one(pipeline_name: str, pipeline: Pipeline, recording: Any, keep_results: bool) -> EvaluationReport:
    report = evaluate(pipeline, _materialise(recording), pipeline_name=pipeline_name)
    return report if keep_results else EvaluationReport(report.metrics)


def _progress(total: int, progress: bool | None):
    """A tqdm bar when asked, or by default when stderr is a terminal and tqdm is installed."""
    show = sys.stderr.isatty() if progress is None else progress
    if not show:
        return None
    try:
        from tqdm.auto import tqdm
    except ImportError:
        return None
    return tqdm(total=total, desc="footnav evaluate", unit="run")


def evaluate_many(
    pipelines: Mapping[str, Pipeline] | Sequence[tuple[str, Pipeline]] | Sequence[Pipeline] | Pipeline,
    recordings: Iterable[Recording | str | os.PathLike | Callable[[], Recording]],
    *,
    n_jobs: int = 1,
    backend: Literal["loky", "dask"] = "loky",
    scheduler: str | None = None,
    progress: bool | None = None,
    keep_results: bool = True,
) -> EvaluationReport:
    """Evaluate every pipeline on every recording; one report, in (recording, pipeline) order.

    Parameters
    ----------
    pipelines
        ``{name: pipeline}``, ``[(name, pipeline), ...]`` or pipelines (named by their components).
    recordings
        Recordings with truth, or what makes them where the run happens: a file path (read with
        :func:`footnav.load`) or a zero-argument callable such as
        ``functools.partial(footnav.simulate, "rectangle", seed=3)`` -- so that workers read or
        simulate their own data instead of receiving it.
    n_jobs
        Local worker processes for ``backend="loky"``: 1 runs serially here, -1 uses every core.
    backend
        ``"loky"`` (joblib processes on this machine) or ``"dask"`` (a Dask distributed cluster;
        needs the ``dask`` extra).
    scheduler
        Dask scheduler address (``tcp://host:8786``); default: the current Dask client, else a new
        local cluster.
    progress
        Show a progress bar (needs tqdm); default: only when stderr is a terminal.
    keep_results
        Keep every run's trajectories in ``report.results``; False returns the metrics only
        (less to send back from workers).

    Returns
    -------
    EvaluationReport
        The metrics of all runs (``runtime`` is each run's own wall time) and their results.
    """
    if backend not in BACKENDS:
        raise InvalidParameterError(f"evaluate_many: unknown backend {backend!r}; valid: {', '.join(BACKENDS)}")
    if not isinstance(n_jobs, int) or isinstance(n_jobs, bool) or n_jobs == 0 or n_jobs < -1:
        raise InvalidParameterError(f"evaluate_many: n_jobs={n_jobs!r} is invalid; expected a positive int or -1 (all cores)")
    tasks = [(name, pipe, rec, keep_results) for rec in recordings for name, pipe in _named(pipelines)]
    bar = _progress(len(tasks), progress)
    reports: list[EvaluationReport | None] = [None] * len(tasks)
    try:
        if backend == "dask":
            _run_dask(tasks, reports, scheduler, bar)
        elif n_jobs == 1 or len(tasks) <= 1:
            for i, task in enumerate(tasks):
                reports[i] = _run_one(*task)
                if bar is not None:
                    bar.update(1)
        else:
            from joblib import Parallel, delayed

            jobs = os.cpu_count() or 1 if n_jobs == -1 else n_jobs
            runner = Parallel(n_jobs=jobs, backend="loky", return_as="generator")
            for i, report in enumerate(runner(delayed(_run_one)(*task) for task in tasks)):
                reports[i] = report
                if bar is not None:
                    bar.update(1)
    finally:
        if bar is not None:
            bar.close()
    total = EvaluationReport(())
    for report in reports:
        total = total + report
    return total


def _run_dask(tasks, reports, scheduler, bar) -> None:
    try:
        from dask.distributed import Client, as_completed, get_client
    except ImportError as exc:  # pragma: no cover - depends on the environment
        raise InvalidParameterError(
            "evaluate_many(backend='dask') needs dask.distributed: pip install 'footnav[dask]'"
        ) from exc
    own = None
    if scheduler is not None:
        client = own = Client(scheduler)
    else:
        try:
            client = get_client()
        except ValueError:
            client = own = Client(processes=False)
    try:
        futures = [client.submit(_run_one, *task, pure=False) for task in tasks]
        index = {f.key: i for i, f in enumerate(futures)}
        for future in as_completed(futures):
            reports[index[future.key]] = future.result()
            if bar is not None:
                bar.update(1)
    finally:
        if own is not None:
            own.close()
