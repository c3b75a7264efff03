"""Batch evaluation speed-up: 40 simulated recordings, serial vs joblib processes (and Dask).

Run:  python benchmarks/bench_batch.py [--recordings 40] [--jobs 2] [--dask]

Each recording is a simulated two-foot walk round a 105 x 68 m rectangle (about 5 minutes at
100 Hz), simulated by the worker that evaluates it; the pipeline is the default one. Prints the
serial and parallel wall times and their ratio; the target is >= 1.6x with 2 processes on a
2-core machine. Worker start-up (process spawn, numba cache load) counts against the parallel run.
"""

from __future__ import annotations

import argparse
import os
import platform
import time
from functools import partial

import footnav
from footnav.analysis.batch import evaluate_many
from footnav.core.types import Recording


def simulate_named(seed: int, scale: float = 1.0) -> Recording:
    """A two-foot walk round a (105 x 68 m) x scale rectangle (4.6 min x scale), named after its seed."""
    rec = footnav.simulate("rectangle", seed=seed, width_m=105.0 * scale, height_m=68.0 * scale)
    return Recording(**{**rec.__dict__, "name": f"rect-{seed}"})


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--recordings", type=int, default=40)
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--scale", type=float, default=4.0, help="rectangle size as a multiple of 105 x 68 m (4: 18 min)")
    ap.add_argument("--dask", action="store_true", help="also time a local Dask cluster with --jobs workers")
    args = ap.parse_args()
    # each worker simulates its own recordings: only the pipeline and a seed travel
    recs = [partial(simulate_named, seed, args.scale) for seed in range(args.recordings)]
    pipes = {"default": footnav.make_pipeline()}
    evaluate_many(pipes, recs[:1])  # warm numba's cache in this process

    t0 = time.perf_counter()
    serial = evaluate_many(pipes, recs, progress=False, keep_results=False)
    t_serial = time.perf_counter() - t0
    t0 = time.perf_counter()
    parallel = evaluate_many(pipes, recs, n_jobs=args.jobs, progress=False, keep_results=False)
    t_par = time.perf_counter() - t0
    t0 = time.perf_counter()  # again: loky keeps its workers, so this run has no start-up
    evaluate_many(pipes, recs, n_jobs=args.jobs, progress=False, keep_results=False)
    t_warm = time.perf_counter() - t0
    same = [m.value for m in serial.metrics if m.name != "runtime"] == [
        m.value for m in parallel.metrics if m.name != "runtime"
    ]
    print(f"machine: {platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}")
    print(
        f"{args.recordings} simulated recordings of {simulate_named(0, args.scale).left.duration_s:.0f} s, "
        "default pipeline"
    )
    print(
        f"serial: {t_serial:.2f} s; loky n_jobs={args.jobs}: {t_par:.2f} s (speed-up {t_serial / t_par:.2f}x), "
        f"with its workers already started: {t_warm:.2f} s ({t_serial / t_warm:.2f}x); same metrics: {same}"
    )
    if args.dask:
        from dask.distributed import Client, LocalCluster

        with (
            LocalCluster(n_workers=args.jobs, threads_per_worker=1, dashboard_address=None) as cluster,
            Client(cluster),
        ):
            t0 = time.perf_counter()
            evaluate_many(pipes, recs, backend="dask", progress=False, keep_results=False)
            t_dask = time.perf_counter() - t0
        print(f"dask LocalCluster {args.jobs} workers: {t_dask:.2f} s; speed-up {t_serial / t_dask:.2f}x")


if __name__ == "__main__":
    main()
