"""Covariance honesty: does position_std cover the error on simulated walks?

Run:  python benchmarks/bench_consistency.py [--minutes 10 60] [--seeds 12] [--gyr-scale-std 0.005]

Walks: laps of a 150 x 60 m rectangle (``simulate("path")``, the simulator's default sensor), each
length with seeds 0 .. seeds-1, both feet. Each runs through the default pipeline (adaptive
detector) with the ``ekf`` estimator (whole-walk, step-wise and no smoothing; and whole-walk with
``heading_drift_in_std=False``, the filter's covariance alone as before issue 14) and with
``madgwick`` (alone as well). ``--gyr-scale-std S`` gives each walk's gyro a scale-factor error
drawn from N(0, S^2) with the walk's seed, the same on every axis: with S the estimators' own
``gyro_scale_std`` (0.005) it checks that term; 0 (the default) is the simulator's sensor as it is.

The error is the estimate minus the truth, both relative to the start (a ZUPT INS knows its
position only relative to where it started). ``position_std`` is per axis (the diagonal of the
covariance), so the check is per axis: the fraction of samples (x and y, every sample after the
start, every walk) with ``|error| <= 1 std`` and ``<= 2 std``, 68.3 % and 95.4 % for a consistent
Gaussian, and the NEES per axis, the mean of ``(error / std)^2``, 1 when consistent (a few large
ratios dominate it: heavy tails show there first). The error of one walk is made of a few random
numbers (the heading's drift) and stays correlated over the whole walk, so one walk's coverage
is anything from 0 to 100 %; only the average over walks approaches 68 % (the spread is printed).
"""

from __future__ import annotations

import argparse
import os
import platform
import time
import warnings

import numpy as np
from numpy.typing import NDArray

import footnav

CONFIGS = [
    ("ekf", {}, "whole"),
    ("ekf", {"smoother": "step"}, "step"),
    ("ekf", {"smoother": "none"}, "none"),
    ("ekf", {"gyro_scale_std": 0.0}, "whole, no scale term"),
    ("ekf", {"heading_drift_in_std": False}, "whole, filter covariance only"),
    ("madgwick", {}, "-"),
    ("madgwick", {"heading_drift_in_std": False}, "-, filter covariance only"),
]


def walk(minutes: float, seed: int, gyr_scale_std: float = 0.0) -> footnav.Recording:
    """Laps of a 150 x 60 m rectangle, about ``minutes`` long (one lap takes 5.6 min), with a gyro
    scale-factor error drawn from N(0, gyr_scale_std^2)."""
    scale = min(1.0, minutes / 5.6)
    lap = [(150.0 * scale, 90.0), (60.0 * scale, 90.0)] * 2
    k = float(np.clip(np.random.default_rng(seed).normal(0.0, gyr_scale_std), -0.2, 0.2)) if gyr_scale_std else 0.0
    segments = lap * max(1, int(round(minutes / 5.6)))
    return footnav.simulate("path", seed=seed, segments=segments, gyr_scale_error=k)


def scores(traj: footnav.FootTrajectory, truth) -> tuple[NDArray, float, float]:
    """Per-axis error / std of x and y after the start, the final horizontal error and std (m)."""
    err = traj.position[:, :2] - (truth.position[:, :2] - truth.position[0, :2])
    std = traj.position_std[:, :2]
    moving = np.all(std > 0, axis=1)  # the start, where both are 0
    return (err[moving] / std[moving]).ravel(), float(np.hypot(*err[-1])), float(np.hypot(*std[-1]))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--minutes", type=float, nargs="+", default=[10.0, 60.0])
    ap.add_argument("--seeds", type=int, default=12)
    ap.add_argument("--gyr-scale-std", type=float, default=0.0)
    args = ap.parse_args()
    print(f"machine: {platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}")
    print("per axis, x and y; consistent: 68.3 % within 1 std, 95.4 % within 2 std, NEES 1")
    print(f"gyro scale-factor error of the walks: N(0, {args.gyr_scale_std:g}^2)")
    print(
        "| walk | estimator | smoother | walks | within 1 std | per walk | within 2 std | NEES/axis "
        "| final error RMS m | final std mean m |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|")
    t0 = time.perf_counter()
    for minutes in args.minutes:
        results: dict[int, list] = {i: [] for i in range(len(CONFIGS))}
        duration = 0.0
        for seed in range(args.seeds):
            rec = walk(minutes, seed, args.gyr_scale_std)
            duration = rec.left.duration_s / 60
            for i, (est, params, _) in enumerate(CONFIGS):
                pipe = footnav.make_pipeline(estimator=est, estimator_params=params)
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    res = pipe.run(rec.left, rec.right)
                results[i] += [scores(res.left, rec.truth_left), scores(res.right, rec.truth_right)]
        for i, (est, _, label) in enumerate(CONFIGS):
            z = np.concatenate([r[0] for r in results[i]])
            per_walk = [np.mean(np.abs(r[0]) <= 1) for r in results[i]]
            end_err = np.sqrt(np.mean([r[1] ** 2 for r in results[i]]))
            end_std = np.mean([r[2] for r in results[i]])
            # each walk weighs the same: walks of one length have the same number of samples
            print(
                f"| {duration:.0f} min | {est} | {label} | {len(per_walk)} | {100 * np.mean(np.abs(z) <= 1):.0f} % | "
                f"{100 * min(per_walk):.0f}-{100 * max(per_walk):.0f} % | {100 * np.mean(np.abs(z) <= 2):.0f} % | "
                f"{np.mean(z**2):.2f} | {end_err:.1f} | {end_std:.1f} |",
                flush=True,
            )
    print(f"({time.perf_counter() - t0:.0f} s)")


if __name__ == "__main__":
    main()
