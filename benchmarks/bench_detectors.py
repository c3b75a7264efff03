"""Stance detector cost per sample, and the default pipeline end to end, on one long simulated walk.

Run:  python benchmarks/bench_detectors.py [--minutes 60] [--rate-hz 100] [--repeat 3]

Prints the machine, the recording and, for each window-based detector (``adaptive``, the default;
``threshold``; ``glrt``), the best-of-``repeat`` wall time of ``detect`` per sample; then the
stance self-check that every pipeline run adds, and the default pipeline (``make_pipeline()``) per
sample per foot. Targets (issue 13): the default detector <= 0.2 us/sample, so that the default
pipeline stays under 1 us/sample per foot. Ratios to ``threshold`` are measured in the same
process, so they hold across machines better than the absolute times.
"""

from __future__ import annotations

import argparse
import platform

from _common import best_of, cpu_name, straight_walk  # benchmarks/_common.py (scripts run from benchmarks/)

#: Issue 13's budget for the default detector, us/sample.
DETECTOR_BUDGET_US = 0.2


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--minutes", type=float, default=60.0)
    ap.add_argument("--rate-hz", type=float, default=100.0)
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()

    import numpy as np

    import footnav
    from footnav.nav.stance_check import check_stances

    rec = straight_walk(args.minutes, args.rate_hz)
    imu = rec.left
    n = imu.n_samples

    def best(fn) -> float:
        return best_of(fn, args.repeat)[0]

    print(f"machine: {platform.machine()} {cpu_name()}, python {platform.python_version()}, numpy {np.__version__}")
    print(
        f"recording: simulated straight walk, {n} samples per foot "
        f"({n / args.rate_hz / 60:.1f} min at {args.rate_hz:g} Hz)"
    )
    per_sample = {}
    for name in ("threshold", "adaptive", "glrt"):
        det = footnav.make_detector(name)
        det.detect(imu)  # warm
        per_sample[name] = best(lambda det=det: det.detect(imu)) / n * 1e6
    stance = footnav.make_detector("adaptive").detect(imu)
    check_us = best(lambda: check_stances(imu, stance)) / n * 1e6
    pipe = footnav.make_pipeline()
    pipe.run(rec.left, rec.right)  # warm (compiles on a cold cache)
    pipeline_us = best(lambda: pipe.run(rec.left, rec.right)) / (2 * n) * 1e6

    print("detector    us/sample   x threshold")
    for name, us in per_sample.items():
        print(f"{name:<11} {us:9.3f}   {us / per_sample['threshold']:6.2f}")
    print(f"stance self-check: {check_us:.3f} us/sample")
    verdict = "met" if per_sample["adaptive"] <= DETECTOR_BUDGET_US else "NOT met"
    print(f"default detector budget {DETECTOR_BUDGET_US} us/sample: {verdict}")
    print(f"default pipeline (adaptive + ekf + independent, self-check included): {pipeline_us:.3f} us/sample/foot")


if __name__ == "__main__":
    main()
