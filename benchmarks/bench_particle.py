"""Particle-filter fusion cost: 1000 particles against the same pipeline with fewer, and against independent.

Run:  python benchmarks/bench_particle.py [--minutes 10] [--repeat 3]

Issue 6's target: the particle filter with 1000 particles adds < 20 % to the pipeline runtime.
"""

from __future__ import annotations

import argparse
import os
import platform
import time

import footnav


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--minutes", type=float, default=10.0)
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    laps = max(1, int(round(args.minutes / 5.6)))
    rec = footnav.simulate("path", seed=11, segments=[(150.0, 90.0), (60.0, 90.0), (150.0, 90.0), (60.0, 90.0)] * laps)
    runs = {
        "independent": footnav.make_pipeline("threshold", "ekf", "independent"),
        "particle, 2 particles": footnav.make_pipeline("threshold", "ekf", "particle", fusion_params={"n_particles": 2}),
        "particle, 100 particles": footnav.make_pipeline("threshold", "ekf", "particle", fusion_params={"n_particles": 100}),
        "particle, 1000 particles": footnav.make_pipeline("threshold", "ekf", "particle", fusion_params={"n_particles": 1000}),
    }
    print(f"machine: {platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}")
    print(f"walk: {rec.left.duration_s / 60:.1f} min, two feet at 100 Hz")
    times = {}
    for label, pipe in runs.items():
        pipe.run(rec)
        best = []
        for _ in range(args.repeat):
            t0 = time.perf_counter()
            pipe.run(rec)
            best.append(time.perf_counter() - t0)
        times[label] = min(best)
        print(f"{label:26s} {times[label]:.3f} s")
    base = times["particle, 2 particles"]
    print(f"1000 particles add {100 * (times['particle, 1000 particles'] / base - 1):.0f} % to the particle pipeline with 2; "
          f"{100 * (times['particle, 1000 particles'] / times['independent'] - 1):.0f} % to the independent pipeline")


if __name__ == "__main__":
    main()
