"""The simulator's speed: a two-foot straight walk of about an hour.

Run:  python benchmarks/bench_simulate.py [--minutes 60] [--repeat 3]

Prints the machine and the warm best-of-``repeat`` wall time of ``footnav.simulate("straight",
...)`` for a walk of ``--minutes`` at 100 Hz (the timing tests/data/test_simulate.py used to assert:
under 8 s for an hour).
"""

from __future__ import annotations

import argparse
import os
import platform

from _common import WALK_SPEED_MPS, best_of, cpu_name  # benchmarks/_common.py (scripts run from benchmarks/)

import footnav


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--minutes", type=float, default=60.0)
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    distance_m = args.minutes * 60.0 * WALK_SPEED_MPS
    footnav.simulate("straight", distance_m=10.0)  # compile
    best, rec = best_of(lambda: footnav.simulate("straight", distance_m=distance_m), args.repeat)
    print(
        f"machine: {cpu_name()}, {os.cpu_count()} cores, Python {platform.python_version()}, "
        f"footnav {footnav.__version__}"
    )
    print(
        f"simulate straight, {rec.left.duration_s / 60:.1f} min two feet at {rec.left.rate_hz:.0f} Hz: "
        f"{best:.2f} s (best of {args.repeat})"
    )


if __name__ == "__main__":
    main()
