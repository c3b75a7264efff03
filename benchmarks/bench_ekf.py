"""EKF speed and memory: microseconds per sample on a simulated recording, warm, one core.

Run:  python benchmarks/bench_ekf.py [--minutes 10] [--rate-hz 100] [--repeat 3]
      NUMBA_CACHE_DIR=$(mktemp -d) python benchmarks/bench_ekf.py --minutes 1 --repeat 1   # cold compile

Prints the machine, then for the ``ekf`` estimator with 9 and 15 error states and each smoother
(none, step, whole): the warm time per sample (truth stance, so only the filter is timed) and the
peak memory the call allocates beyond its input (tracemalloc), next to the size of its output.
Also the ``threshold`` detector and the default pipeline on both feet. The first call in a fresh
process includes loading numba's cache, or compiling when there is none.
"""

from __future__ import annotations

import argparse
import functools
import os
import platform
import time
import tracemalloc

import numpy as np
from _common import best_of, straight_walk  # benchmarks/_common.py (scripts run from benchmarks/)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--minutes", type=float, default=10.0)
    ap.add_argument("--rate-hz", type=float, default=100.0)
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()

    t0 = time.perf_counter()
    import footnav
    from footnav.core.types import StanceResult
    from footnav.estimators.ekf import EkfEstimator

    import_s = time.perf_counter() - t0
    rec = straight_walk(args.minutes, args.rate_hz)
    n = rec.left.n_samples
    stance = StanceResult(rec.truth_left.stance)

    short = rec.left.slice(0, 2000), StanceResult(rec.truth_left.stance[:2000])
    t0 = time.perf_counter()
    for bias in (False, True):
        for smoother in ("none", "step", "whole"):
            EkfEstimator(bias_states=bias, smoother=smoother, zaru_std_radps=0.005 if bias else 0.0).estimate(*short)
    first_s = time.perf_counter() - t0

    def best(fn) -> float:
        return best_of(fn, args.repeat)[0]

    def peak_mb(fn) -> float:
        tracemalloc.start()
        fn()
        _, peak = tracemalloc.get_traced_memory()
        tracemalloc.stop()
        return peak / 1e6

    print(
        f"machine: {platform.machine()}, {platform.processor() or 'cpu'}, {os.cpu_count()} cores, "
        f"Python {platform.python_version()}, numpy {np.__version__}"
    )
    print(f"recording: {rec.left.duration_s / 60:.1f} min simulated at {args.rate_hz:g} Hz, {n} samples per foot")
    print(
        f"import footnav: {import_s:.2f} s; "
        f"first calls of the six ekf variants (cache load or compile): {first_s:.2f} s"
    )
    out_mb = n * (3 + 3 + 4 + 3) * 8 / 1e6
    print(f"output of one foot (position, velocity, attitude, std): {out_mb:.1f} MB")
    print("| states | smoother | us/sample | peak MB |")
    print("|---|---|---|---|")
    for bias in (False, True):
        for smoother in ("none", "step", "whole"):
            est = EkfEstimator(bias_states=bias, smoother=smoother, zaru_std_radps=0.005 if bias else 0.0)
            run = functools.partial(est.estimate, rec.left, stance)
            s = best(run)
            mb = peak_mb(run)
            print(f"| {est.n_states} | {smoother} | {s / n * 1e6:.3f} | {mb:.1f} |")
    det = footnav.make_detector("threshold")
    det_s = best(lambda: det.detect(rec.left))
    pipe = footnav.make_pipeline()
    pipe_s = best(lambda: pipe.run(rec.left, rec.right))
    print(f"threshold detect (one foot, warm):  {det_s / n * 1e6:.3f} us/sample")
    print(f"default pipeline (two feet, warm):  {pipe_s / (2 * n) * 1e6:.3f} us/sample/foot  ({pipe_s:.3f} s)")


if __name__ == "__main__":
    main()
