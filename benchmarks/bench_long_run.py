"""Long-run stability: a simulated 60-minute two-foot walk through every pipeline combination.

Run:  python benchmarks/bench_long_run.py [--minutes 60]

For every (detector, estimator, fusion) registered: runtime, peak memory of a second run (tracemalloc),
and whether any output is not finite. Then the joint two-foot EKF (9 and 15 states) run step by
step over the whole walk: the largest covariance asymmetry and the smallest eigenvalue over every
step's checkpoint.
"""

from __future__ import annotations

import argparse
import itertools
import os
import platform
import time
import tracemalloc
import warnings

import numpy as np

import footnav
from footnav import StanceResult
from footnav.estimators.ekf import EkfEstimator


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--minutes", type=float, default=60.0)
    args = ap.parse_args()
    laps = max(1, int(round(args.minutes / 5.6)))  # one 150 x 63 m lap takes about 5.6 min
    segments = [(150.0, 90.0), (60.0, 90.0), (150.0, 90.0), (60.0, 90.0)] * laps
    rec = footnav.simulate("path", seed=11, segments=segments)
    print(f"machine: {platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}")
    print(f"walk: {rec.left.duration_s / 60:.1f} min, {rec.left.n_samples} samples per foot, {laps} laps")
    comps = footnav.list_components()
    print("| detector | estimator | fusion | runtime s | peak MB | finite |")
    print("|---|---|---|---|---|---|")
    for det, est, fus in itertools.product(comps["detector"], comps["estimator"], comps["fusion"]):
        pipe = footnav.make_pipeline(det, est, fus)
        t0 = time.perf_counter()
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                res = pipe.run(rec)
        except footnav.FootnavError as err:
            print(f"| {det} | {est} | {fus} | - | - | refused: {type(err).__name__}: {str(err)[:80]} |")
            continue
        runtime = time.perf_counter() - t0
        # memory in a second run: tracing every allocation slows Python-level loops several-fold
        tracemalloc.start()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            pipe.run(rec)
        _, peak = tracemalloc.get_traced_memory()
        tracemalloc.stop()
        finite = all(
            np.isfinite(a).all()
            for a in (res.left.position, res.right.position, res.path.position, res.left.position_std)
        )
        print(f"| {det} | {est} | {fus} | {runtime:.2f} | {peak / 1e6:.0f} | {finite} |", flush=True)
    stances = [StanceResult(rec.truth_left.stance), StanceResult(rec.truth_right.stance)]
    for params in ({}, {"bias_states": True, "zaru_std_radps": 0.005}):
        est = EkfEstimator(smoother="step", **params)
        filt = est.start([rec.left, rec.right], stances)
        filt.step_stops = True  # a checkpoint at every step end, to look at the covariance there
        t0 = time.perf_counter()
        filt.run_until()
        runtime = time.perf_counter() - t0
        asym = max(float(np.abs(cp.cov - cp.cov.T).max()) for cp in filt.checkpoints[1:])
        eig = min(float(np.linalg.eigvalsh(cp.cov).min()) for cp in filt.checkpoints[1:])
        print(
            f"joint two-foot EKF, {est.n_states} states per foot: {len(filt.checkpoints)} step checkpoints, "
            f"{runtime:.2f} s, max covariance asymmetry {asym:.3g}, min eigenvalue {eig:.3g}"
        )


if __name__ == "__main__":
    main()
