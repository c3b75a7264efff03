"""Madgwick + 9-state KF speed: microseconds per sample, warm, one core; first-call cost.

Run:  python benchmarks/bench_madgwick.py [--minutes 10 60] [--rate-hz 100] [--repeat 3]

Prints the machine; the first calls (IMU and MARG filters) in a fresh process with numba's cache
emptied (NUMBA_CACHE_DIR set to a new temporary folder: the compile time), then in another fresh
process with that cache filled (the load time); then for each recording length the warm time per
sample of ``estimate`` with the IMU and the MARG filter (truth stance, so only the estimator is
timed; best of ``--repeat``) and the peak memory the call allocates (tracemalloc).
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import subprocess
import sys
import tempfile
import time
import tracemalloc

import numpy as np
from _common import WALK_SPEED_MPS  # benchmarks/_common.py (scripts run from benchmarks/)

#: Run in a fresh interpreter: import time, then the first IMU and MARG calls on a short walk.
_FIRST_CALLS = """
import json, time
t0 = time.perf_counter()
import footnav
from dataclasses import replace
from footnav.nav import quaternion as quat
from footnav.core.types import StanceResult
from footnav.estimators.madgwick import MadgwickEstimator
t1 = time.perf_counter()
rec = footnav.simulate("straight", seed=0, distance_m=10.0)
stance = StanceResult(rec.truth_left.stance)
marg = replace(rec.left, mag=quat.rotate(quat.conjugate(rec.truth_left.quaternion), [20.0, 0.0, -40.0]))
t2 = time.perf_counter()
MadgwickEstimator().estimate(rec.left, stance)
t3 = time.perf_counter()
MadgwickEstimator().estimate(marg, stance)
t4 = time.perf_counter()
print(json.dumps({"import_s": t1 - t0, "imu_s": t3 - t2, "marg_s": t4 - t3}))
"""


def first_calls(cache_dir: str) -> dict[str, float]:
    """Times of :data:`_FIRST_CALLS` in a fresh process using numba cache ``cache_dir``."""
    env = {**os.environ, "NUMBA_CACHE_DIR": cache_dir}
    out = subprocess.run([sys.executable, "-c", _FIRST_CALLS], env=env, check=True, capture_output=True, text=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--minutes", type=float, nargs="+", default=[10.0, 60.0])
    ap.add_argument("--rate-hz", type=float, default=100.0)
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()

    print(
        f"machine: {platform.machine()}, {platform.processor() or 'cpu'}, {os.cpu_count()} cores, "
        f"Python {platform.python_version()}, numpy {np.__version__}"
    )
    with tempfile.TemporaryDirectory(prefix="numba-cache-") as cache:
        cold = first_calls(cache)
        warm = first_calls(cache)
    for label, r in (("empty numba cache (compile)", cold), ("filled numba cache (load)", warm)):
        print(
            f"fresh process, {label}: import footnav {r['import_s']:.2f} s; first IMU call {r['imu_s']:.2f} s, "
            f"first MARG call {r['marg_s']:.2f} s"
        )

    from dataclasses import replace

    import footnav
    from footnav.core.types import StanceResult
    from footnav.estimators.madgwick import MadgwickEstimator
    from footnav.nav import quaternion as quat

    est = MadgwickEstimator()
    speed_mps = WALK_SPEED_MPS
    print("| recording | samples | filter | us/sample | peak MB |")
    print("|---|---|---|---|---|")
    for minutes in args.minutes:
        rec = footnav.simulate("straight", seed=0, rate_hz=args.rate_hz, distance_m=minutes * 60 * speed_mps)
        n = rec.left.n_samples
        stance = StanceResult(rec.truth_left.stance)
        marg = replace(rec.left, mag=quat.rotate(quat.conjugate(rec.truth_left.quaternion), [20.0, 0.0, -40.0]))
        for name, imu in (("IMU", rec.left), ("MARG", marg)):
            est.estimate(imu.slice(0, 2000), StanceResult(stance.mask[:2000]))  # compiled before timing
            times = []
            for _ in range(args.repeat):
                t0 = time.perf_counter()
                est.estimate(imu, stance)
                times.append(time.perf_counter() - t0)
            tracemalloc.start()
            est.estimate(imu, stance)
            peak = tracemalloc.get_traced_memory()[1]
            tracemalloc.stop()
            print(
                f"| {rec.left.duration_s / 60:.1f} min at {args.rate_hz:g} Hz | {n} | {name} | "
                f"{min(times) / n * 1e6:.3f} | {peak / 1e6:.0f} |"
            )


if __name__ == "__main__":
    main()
