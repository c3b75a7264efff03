"""Batch evaluation: many pipelines on many recordings, serially, on local processes or on Dask.

:func:`evaluate_many` runs :func:`~footnav.analysis.evaluation.evaluate` for every (recording,
pipeline) pair and joins the reports in that order, whatever order the runs finish in, so a
parallel run gives the same table as a serial one (but for the ``runtime`` rows). Locally it uses
joblib's ``loky`` processes (``n_jobs``); with ``backend="dask"`` it submits to a Dask
distributed scheduler (``scheduler`` address, or the current client, or a new in-process one)
when one machine is outgrown. A progress bar (tqdm, optional) shows on a terminal.

A pair that raises (a two-foot fusion on a one-foot recording, a detector failing on one trial, a
file that cannot be read) does not end the batch: by default (``on_error="record"``) it becomes an
:class:`~footnav.analysis.evaluation.EvaluationFailure` in ``report.failures`` -- an ``error`` row in
the table and the CSV -- the other pairs run, and one warning says how many failed. The error is
caught where the pair runs, so this holds on every backend. KeyboardInterrupt, SystemExit and
MemoryError still end the batch.
"""

from __future__ import annotations

import functools
import os
import sys
from collections.abc import Callable, Iterable, Mapping, Sequence
from typing import Any, Literal

from footnav.analysis.evaluation import (
    ON_ERROR,
    EvaluationFailure,
    EvaluationReport,
    evaluate,
    evaluate_or_record,
    fatal,
)
from footnav.core.errors import FootnavWarning, InvalidParameterError
from footnav.core.parameters import worker_count
from footnav.core.types import Recording
from footnav.core.warning_log import warn
from footnav.pipeline.factory import Pipeline

__all__ = ["evaluate_many", "BACKENDS", "SERIAL_BELOW_SAMPLES", "serial_is_faster"]

BACKENDS = ("loky", "dask")

#: Below this many samples to process (every foot of every recording, once per pipeline) local
#: worker processes do not pay off: each starts Python, imports footnav and loads numba's cache
#: (2-3 s), and the recordings are pickled to it. Measured on 2 cores (docs/batch.md): 4 x 100 m
#: walks (63 k samples) 1.2 s serial, 3.6 s with 2 jobs; 4 x 3 km (1.9 M) 31.1 s against 31.8 s.
SERIAL_BELOW_SAMPLES = 2_000_000


def serial_is_faster(recordings: Sequence[Any], n_pipelines: int, n_jobs: int) -> str | None:
    """Why ``n_jobs`` local processes would be slower than one for this batch, or None.

    Only recordings already in memory are counted (paths and callables are read or made by the
    workers, which is work processes share): None when any is not a :class:`Recording`.
    """
    if n_jobs == 1 or not recordings or not all(isinstance(r, Recording) for r in recordings):
        return None
    samples = n_pipelines * sum(imu.n_samples for r in recordings for imu in (r.left, r.right) if imu is not None)
    if samples >= SERIAL_BELOW_SAMPLES:
        return None
    return (
        f"{samples:,} samples to process ({len(recordings)} recording(s) x {n_pipelines} pipeline(s)), under "
        f"{SERIAL_BELOW_SAMPLES:,}: starting worker processes (2-3 s each) would cost more than they save"
    )


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
        raise InvalidParameterError(
            f"evaluate_many: pipeline names must be unique; repeated: {sorted(dup)} (pass a dict name -> pipeline)"
        )
    return out


def _check_recording(recording: Any) -> Any:
    """A recording as given, or InvalidParameterError now (a wrong type is the caller's mistake,
    not a failed pair)."""
    if isinstance(recording, (Recording, str, os.PathLike)) or callable(recording):
        return recording
    raise InvalidParameterError(
        "evaluate_many: a recording must be a Recording, a path or a zero-argument callable; "
        f"got {type(recording).__name__}"
    )


def _label(recording: Any) -> str:
    """A name for a recording that could not be read or made: its path, or its factory's call."""
    if isinstance(recording, (str, os.PathLike)):
        return os.fspath(recording)
    if isinstance(recording, functools.partial):
        args = [repr(a) for a in recording.args] + [f"{k}={v!r}" for k, v in recording.keywords.items()]
        return f"{getattr(recording.func, '__name__', 'recording')}({', '.join(args)})"
    return getattr(recording, "__name__", None) or repr(recording)


def _materialise(recording: Any) -> Recording:
    """A Recording from a Recording, a path (read with footnav.load) or a zero-argument callable."""
    if isinstance(recording, Recording):
        return recording
    if isinstance(recording, (str, os.PathLike)):
        from footnav.data.io import load

        return load(recording)
    if callable(recording):
        rec = recording()
        if not isinstance(rec, Recording):
            raise InvalidParameterError(
                f"evaluate_many: the recording factory {recording!r} returned {type(rec).__name__}, not a Recording"
            )
        return rec
    raise InvalidParameterError(
        "evaluate_many: a recording must be a Recording, a path or a zero-argument callable; "
        f"got {type(recording).__name__}"
    )


def _run_one(
    pipeline_name: str, pipeline: Pipeline, recording: Any, keep_results: bool, record: bool
) -> EvaluationReport:
    """One pair, where it runs (here or in a worker): its report, or -- ``record`` -- its failure."""
    if not record:
        report = evaluate(pipeline, _materialise(recording), pipeline_name=pipeline_name)
    else:
        try:
            rec = _materialise(recording)
        except Exception as exc:  # KeyboardInterrupt and SystemExit pass by themselves
            if (end := fatal(exc)) is not None:
                raise end  # noqa: B904 - the exception itself, or the MemoryError it wraps
            return EvaluationReport(
                (), failures=(EvaluationFailure.from_exception(_label(recording), pipeline_name, exc),)
            )
        report = evaluate_or_record(pipeline, rec, pipeline_name)
    return report if keep_results else EvaluationReport(report.metrics, failures=report.failures, checks=report.checks)


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
    on_error: Literal["record", "raise"] = "record",
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
    on_error
        ``"record"`` (default): a pair that raises becomes an entry of ``report.failures`` (an
        ``error`` row in the table and the CSV), the other pairs run, and a FootnavWarning says
        how many failed. ``"raise"``: the first error ends the batch, as from :func:`evaluate`.
        KeyboardInterrupt, SystemExit and MemoryError always end it.

    Returns
    -------
    EvaluationReport
        The metrics of all runs (``runtime`` is each run's own wall time), their results, and the
        failed pairs in ``failures``.

    Examples
    --------
    >>> report = footnav.evaluate_many({"fused": two_foot_pipe, "plain": footnav.make_pipeline()},
    ...                                [walk, left_only])
    >>> [(f.recording, f.pipeline, f.error_type) for f in report.failures]
    [('left only', 'fused', 'CompositionError')]
    """
    if backend not in BACKENDS:
        raise InvalidParameterError(f"evaluate_many: unknown backend {backend!r}; valid: {', '.join(BACKENDS)}")
    jobs = worker_count(n_jobs, "evaluate_many")
    if on_error not in ON_ERROR:
        raise InvalidParameterError(
            f"evaluate_many: on_error={on_error!r} is invalid; expected one of {', '.join(ON_ERROR)}"
        )
    record = on_error == "record"
    named = _named(pipelines)
    tasks = [(name, pipe, _check_recording(rec), keep_results, record) for rec in recordings for name, pipe in named]
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
    if total.failures:
        n = len(total.failures)
        warn(
            f"evaluate_many: {n} of {len(tasks)} (recording, pipeline) pair{'s' if len(tasks) != 1 else ''} failed "
            f"and {'have' if n != 1 else 'has'} no metrics (see report.failures); first: {total.failures[0]}",
            FootnavWarning,
            stacklevel=2,
        )
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
