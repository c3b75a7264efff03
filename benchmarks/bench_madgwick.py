"""Madgwick + 9-state KF speed: microseconds per sample, warm, one core; first-call cost.

Run:  python benchmarks/bench_madgwick.py [--minutes 10] [--repeat 3]
      NUMBA_CACHE_DIR=$(mktemp -d) python benchmarks/bench_madgwick.py --minutes 1 --repeat 1   # cold compile
"""

from __future__ import annotations

import argparse
import os
import platform
import time
import tracemalloc

import numpy as np


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--minutes", type=float, default=10.0)
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    import footnav
    from footnav.core.types import ImuData, StanceResult
    from footnav.estimators.madgwick import MadgwickEstimator

    rec = footnav.simulate("straight", seed=0, distance_m=args.minutes * 60 * 1.4 / 1.1)
    n = rec.left.n_samples
    stance = StanceResult(rec.truth_left.stance)
    est = MadgwickEstimator()
    t0 = time.perf_counter()
    est.estimate(rec.left.slice(0, 2000), StanceResult(rec.truth_left.stance[:2000]))
    mag = np.tile([20.0, 0.0, -40.0], (2000, 1))
    marg = ImuData(rec.left.t[:2000], rec.left.acc[:2000], rec.left.gyr[:2000], mag)
    est.estimate(marg, StanceResult(rec.truth_left.stance[:2000]))
    first = time.perf_counter() - t0
    times = []
    for _ in range(args.repeat):
        t0 = time.perf_counter()
        est.estimate(rec.left, stance)
        times.append(time.perf_counter() - t0)
    tracemalloc.start()
    est.estimate(rec.left, stance)
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    print(f"machine: {platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}")
    print(f"recording: {rec.left.duration_s / 60:.1f} min at 100 Hz, {n} samples")
    print(f"first calls (IMU and MARG; cache load or compile): {first:.2f} s")
    print(f"madgwick estimate (warm): {min(times) / n * 1e6:.3f} us/sample; peak {peak / 1e6:.0f} MB")


if __name__ == "__main__":
    main()
