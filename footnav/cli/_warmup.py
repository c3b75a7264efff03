"""``footnav warmup``: compile every numerical kernel into numba's cache, before the first real run.

The first call of a kernel in a process with an empty cache compiles it (the ekf's loop with
the kernels it calls takes about 6.5 s, see issue 20); later processes load the machine code
from the cache in a fraction of a second. Inlining the loop's callees made its compilation
longer, not shorter, so this command moves the compilation out of the user's way instead: run
it once after installing (or in a container's build step), as the user who will run footnav
and with the same ``NUMBA_CACHE_DIR``. The cache is per user when the installation is
read-only: numba only uses a cache folder it can write (a read-only ``__pycache__`` or
``NUMBA_CACHE_DIR`` is skipped), so machine code compiled there beforehand is not loaded.
"""

from __future__ import annotations

import argparse
import functools
import inspect
import multiprocessing
import sys
import time
from collections.abc import Callable
from concurrent.futures import ProcessPoolExecutor, as_completed
from typing import TYPE_CHECKING

from footnav.cli._common import EXIT_OK
from footnav.core.parameters import worker_count

if TYPE_CHECKING:
    from footnav.core.types import Recording

#: Short, but long enough for every code path the kernels have (stance, swing, turns, the
#: whole-walk smoother's segments): compiling does not depend on the length.
WARMUP_DISTANCE_M = 10.0


@functools.lru_cache(maxsize=1)
def _walk() -> Recording:
    from footnav.data.simulate import simulate

    return simulate("straight", distance_m=WARMUP_DISTANCE_M, seed=0)


def _tasks() -> list[tuple[str, Callable[[], object]]]:
    """What :func:`warm_up` runs: every registered estimator and fusion on a short simulated walk
    of both feet (offline, with the evaluation's metrics), and ``footnav follow``'s online stream.
    The first is the default pipeline, whose detector and filter every other one runs too."""
    from footnav.analysis.evaluation import evaluate
    from footnav.pipeline.factory import make_pipeline
    from footnav.plugins.manager import get_registry

    rec = _walk()
    reg = get_registry()
    tasks: list[tuple[str, Callable[[], object]]] = []
    for e in reg:
        if e.kind == "estimator" and not e.cls.needs_magnetometer:
            tasks.append((f"estimator {e.name}", lambda name=e.name: evaluate(make_pipeline(estimator=name), rec)))
    default = inspect.signature(make_pipeline).parameters["estimator"].default
    tasks.sort(key=lambda task: task[0] != f"estimator {default}")
    for e in reg:
        if e.kind == "fusion" and e.name != "independent" and not e.cls.needs_magnetometer:
            tasks.append((f"fusion {e.name}", lambda name=e.name: evaluate(make_pipeline(fusion=name), rec)))

    def online() -> object:  # as ``footnav follow`` composes it by default, and with its
        # windowed detector (the start-up of the default one waits 10 s of walk)
        for pipe in (make_pipeline(), make_pipeline("threshold", estimator_params={"smoother": "step"})):
            stream = pipe.online(feet=2)
            stream.push(left=rec.left, right=rec.right)
            stream.close()

    tasks.append(("online stream", online))
    return tasks


def _timed(name: str, task: Callable[[], object]) -> tuple[str, float]:
    t0 = time.perf_counter()
    task()
    return name, time.perf_counter() - t0


def _run_task(name: str) -> tuple[str, float]:
    """Run the task ``name`` of :func:`_tasks` (in a new process); return its name and seconds."""
    return _timed(name, dict(_tasks())[name])


def warm_up(progress: Callable[[str, float], None] | None = None, jobs: int = 1) -> list[tuple[str, float]]:
    """Run every built-in component once on a short simulated walk, filling numba's cache.

    With ``jobs`` > 1 the first step (the default pipeline, whose kernels every other step
    shares) runs here, then the others in up to ``jobs`` new processes at once, which load what
    the first compiled from the cache; each kernel's cache is written under a file lock
    (:mod:`footnav._cache_lock`), so processes compiling one kernel at once are safe.

    Parameters
    ----------
    progress
        Called after each step with its name and its seconds (None: silent).
    jobs
        Processes for the steps after the first; 1 runs every step in this process, -1 uses
        every core. New processes see the components the entry points register, not ones
        registered in this process only.

    Returns
    -------
    list of (str, float)
        Each step's name and wall-clock seconds (compilation or cache loading, and the run), in
        the order of the steps.
    """
    jobs = worker_count(jobs, "warm_up", "jobs")
    tasks = _tasks()
    done = {}

    def record(name: str, seconds: float) -> None:
        done[name] = seconds
        if progress is not None:
            progress(name, seconds)

    record(*_timed(*tasks[0]))
    rest = tasks[1:]
    if jobs == 1 or len(rest) < 2:
        for task in rest:
            record(*_timed(*task))
    else:
        # spawn, not fork: a child forked from a process holding numba's compiled code and
        # LLVM's state is not something numba supports
        context = multiprocessing.get_context("spawn")
        with ProcessPoolExecutor(max_workers=min(jobs, len(rest)), mp_context=context) as pool:
            for future in as_completed([pool.submit(_run_task, name) for name, _ in rest]):
                record(*future.result())
    return [(name, done[name]) for name, _ in tasks]


def warm_worker() -> float:
    """:func:`warm_up` silently, for a Dask worker: ``client.run(footnav.cli.warm_worker)`` once
    before the first distributed batch (docs/batch.md); returns the seconds taken."""
    t0 = time.perf_counter()
    warm_up()
    return time.perf_counter() - t0


def cache_folder() -> str | None:
    """The folder numba caches the ekf's loop in (the other kernels' are beside it), or None
    when footnav compiles without a cache (see :mod:`footnav._numba`)."""
    from footnav.estimators.ekf._loop import run

    cache = getattr(run, "_cache", None)
    return getattr(cache, "cache_path", None)


def cmd_warmup(args: argparse.Namespace) -> int:
    def say(name: str, seconds: float) -> None:
        print(f"{name:<20} {seconds:6.1f} s", flush=True)

    t0 = time.perf_counter()
    jobs = worker_count(args.jobs, "footnav warmup", "--jobs")
    warm_up(say, jobs=jobs)
    where = "" if jobs == 1 else f" (the steps after the first in up to {jobs} processes at once)"
    print(f"{'total':<20} {time.perf_counter() - t0:6.1f} s{where}")
    folder = cache_folder()
    if folder is None:
        print(
            "numba has no cache folder here: every process compiles again (set NUMBA_CACHE_DIR to a writable folder)",
            file=sys.stderr,
        )
    else:
        print(f"numba cache: {folder}")
    return EXIT_OK
