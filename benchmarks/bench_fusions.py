"""Each fusion against ``independent`` on one simulated two-foot walk, in one process (issue 20).

Run:  python benchmarks/bench_fusions.py [--minutes 60] [--rounds 3] [--detector glrt]

The walk is bench_long_run.py's: laps of a 150 x 60 m rectangle at 100 Hz (turns included). Each
foot's stance is detected once; only ``fusion.fuse(estimator, ...)`` is timed (default ``ekf``:
the fusions' per-foot or joint filter, their own per-step work, whole-walk smoothing). The fusions
are timed in turn, ``--rounds`` times (one warm-up call each first); each figure is the shortest
of its rounds, so a noisy machine slows every fusion alike. Ratios against ``independent`` are
the figures to compare across machines; us/sample are per foot.

``--floor`` adds the row ``joint filter only``: both feet in the coupled fusions' joint filter
(18 error states) run to the end and smoothed, with no fusion update at all: what every coupled
fusion costs before its own work.
"""

from __future__ import annotations

import argparse
import os
import platform
import time
import warnings

from _common import cpu_name

import footnav
from footnav.fusion.joint import finish_joint, start_joint

FUSIONS = ("independent", "range", "step-vector", "dtw", "particle")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--minutes", type=float, default=60.0)
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--detector", default="glrt")
    ap.add_argument("--estimator", default="ekf")
    ap.add_argument("--fusions", default=",".join(FUSIONS), help="comma-separated; independent is always first")
    ap.add_argument("--floor", action="store_true", help="also time the joint filter alone (no fusion update)")
    args = ap.parse_args()
    laps = max(1, int(round(args.minutes / 5.6)))  # one lap takes about 5.6 min
    rec = footnav.simulate("path", seed=11, segments=[(150.0, 90.0), (60.0, 90.0), (150.0, 90.0), (60.0, 90.0)] * laps)
    n = rec.left.n_samples
    print(f"machine: {cpu_name()}, {os.cpu_count()} cores, Python {platform.python_version()}")
    print(
        f"walk: {rec.left.duration_s / 60:.1f} min, {n} samples per foot; "
        f"detector {args.detector}, estimator {args.estimator}"
    )
    fusions = ["independent"] + [f for f in args.fusions.split(",") if f and f != "independent"]
    pipes = {f: footnav.make_pipeline(args.detector, args.estimator, f) for f in fusions}
    det = pipes["independent"].detector
    stances = det.detect(rec.left), det.detect(rec.right)
    runs = {
        f: (lambda pipe=pipe: pipe.fusion.fuse(pipe.estimator, rec.left, stances[0], rec.right, stances[1]))
        for f, pipe in pipes.items()
    }
    if args.floor:
        est = pipes["independent"].estimator

        def joint_only():
            filt = start_joint(est, rec.left, stances[0], rec.right, stances[1], 0.2)
            finish_joint(est, filt, stances[0], stances[1], {}, (rec.left, rec.right))

        runs = {"independent": runs.pop("independent"), "joint filter only": joint_only, **runs}
    best = dict.fromkeys(runs, float("inf"))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for run in runs.values():  # warm up: compilation and first-call caches
            run()
        for _ in range(args.rounds):
            for f, run in runs.items():
                t0 = time.perf_counter()
                run()
                best[f] = min(best[f], time.perf_counter() - t0)
    base = best["independent"]
    print("| fusion | seconds | us/sample/foot | vs independent |")
    print("|---|---|---|---|")
    for f in runs:
        print(f"| {f} | {best[f]:.2f} | {best[f] / (2 * n) * 1e6:.2f} | {best[f] / base:.2f}x |")


if __name__ == "__main__":
    main()
