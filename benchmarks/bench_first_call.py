"""The first call in a fresh process: with an empty numba cache, after ``footnav warmup``, and warm (issue 20).

Run:  python benchmarks/bench_first_call.py [--runs 3]

Each run is a new Python process that imports footnav and runs the default pipeline on the demo
recording (what ``footnav demo`` computes), timed from the process's start to the result. "cold"
gives every run its own empty ``NUMBA_CACHE_DIR``: every kernel the call needs compiles. "after
warmup" runs ``footnav warmup`` into a new cache once (timed too), then the call from that cache,
as a user does after the README's set-up. The median of ``--runs`` runs of each is printed;
compare figures of one run of this script, since the machine's speed drifts from day to day.
"""

from __future__ import annotations

import argparse
import os
import platform
import statistics
import subprocess
import sys
import tempfile
import time

from _common import cpu_name

#: The call timed: import, load the demo recording, run the default pipeline on both feet.
CALL = "import footnav; from footnav.demo import demo_recording; footnav.make_pipeline().run(demo_recording())"


def _timed(code: str, cache_dir: str) -> float:
    """Seconds a fresh process takes to run ``code`` with numba's cache in ``cache_dir``."""
    env = {**os.environ, "NUMBA_CACHE_DIR": cache_dir}
    t0 = time.perf_counter()
    subprocess.run([sys.executable, "-W", "ignore", "-c", code], env=env, check=True, capture_output=True)
    return time.perf_counter() - t0


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--runs", type=int, default=3)
    args = ap.parse_args()
    print(f"machine: {cpu_name()}, {os.cpu_count()} cores, Python {platform.python_version()}")
    cold, warmup, after, warm = [], [], [], []
    for _ in range(args.runs):
        with tempfile.TemporaryDirectory() as cache:
            cold.append(_timed(CALL, cache))
            warm.append(_timed(CALL, cache))  # the same cache, now filled by the cold call
        with tempfile.TemporaryDirectory() as cache:
            warmup.append(_timed("from footnav.cli._warmup import warm_up; warm_up()", cache))
            after.append(_timed(CALL, cache))
    print("| first call | median s | runs |")
    print("|---|---|---|")
    for name, xs in (("cold (empty numba cache)", cold), ("footnav warmup, once", warmup),
                     ("after footnav warmup", after), ("warm (the call's own cache)", warm)):
        print(f"| {name} | {statistics.median(xs):.2f} | {', '.join(f'{x:.2f}' for x in xs)} |")


if __name__ == "__main__":
    main()
