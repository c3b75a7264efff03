"""EKF speed: microseconds per sample on a simulated recording, warm, one core; first-call cost.

Run:  python benchmarks/bench_ekf.py [--minutes 10] [--rate-hz 100] [--repeat 5]

Prints the machine, the per-sample time of the ``ekf`` estimator (truth stance, so only the
filter is timed), of the ``threshold`` detector, and of the whole default pipeline on both feet.
The first call in a fresh process includes loading numba's cache (or compiling when there is none).
"""

from __future__ import annotations

import argparse
import os
import platform
import time

import numpy as np


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--minutes", type=float, default=10.0)
    ap.add_argument("--rate-hz", type=float, default=100.0)
    ap.add_argument("--repeat", type=int, default=5)
    args = ap.parse_args()

    t0 = time.perf_counter()
    import footnav
    from footnav.core.types import StanceResult
    from footnav.estimators.ekf import EkfEstimator

    import_s = time.perf_counter() - t0
    speed_mps = 1.4 / 1.1  # default stride length / stride period of the simulator
    rec = footnav.simulate("straight", seed=0, rate_hz=args.rate_hz, distance_m=args.minutes * 60 * speed_mps)
    n = rec.left.n_samples
    stance = StanceResult(rec.truth_left.stance)
    est = EkfEstimator()

    t0 = time.perf_counter()
    est.estimate(rec.left.slice(0, 2000), StanceResult(rec.truth_left.stance[:2000]))
    first_s = time.perf_counter() - t0

    def best(fn) -> float:
        times = []
        for _ in range(args.repeat):
            t0 = time.perf_counter()
            fn()
            times.append(time.perf_counter() - t0)
        return min(times)

    ekf_s = best(lambda: est.estimate(rec.left, stance))
    det = footnav.make_detector("threshold")
    det_s = best(lambda: det.detect(rec.left))
    pipe = footnav.make_pipeline()
    pipe_s = best(lambda: pipe.run(rec.left, rec.right))

    print(f"machine: {platform.machine()}, {platform.processor() or 'cpu'}, {os.cpu_count()} cores, "
          f"Python {platform.python_version()}, numpy {np.__version__}")
    print(f"recording: {rec.left.duration_s / 60:.1f} min simulated at {args.rate_hz:g} Hz, {n} samples per foot")
    print(f"import footnav: {import_s:.2f} s; first ekf call (cache load or compile): {first_s:.2f} s")
    print(f"ekf estimate (one foot, warm):      {ekf_s / n * 1e6:.3f} us/sample  ({ekf_s:.3f} s)")
    print(f"threshold detect (one foot, warm):  {det_s / n * 1e6:.3f} us/sample  ({det_s:.3f} s)")
    print(f"default pipeline (two feet, warm):  {pipe_s / (2 * n) * 1e6:.3f} us/sample/foot  ({pipe_s:.3f} s)")


if __name__ == "__main__":
    main()
