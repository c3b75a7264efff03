"""What a user waits for around the filter (issue 33): ``import footnav`` and ``footnav run`` on a
one-minute one-foot recording, each in a fresh process, after warmup (numba's cache filled).

Run:  python benchmarks/bench_startup.py [--repeat 7] [--file RECORDING]

Import: the total ``python -X importtime -c "import footnav"`` reports for footnav, and the wall
time of ``python -c "import footnav"`` less that of ``python -c pass``. Run: the wall time of
``python -m footnav.cli run --left FILE --out TMP --force`` after one untimed run (which fills
numba's cache if needed). Without ``--file`` the recording is a simulated one-minute straight walk
at 100 Hz (``footnav simulate``, left foot); ``FOOTNAV_DATA``'s x-io long walk (70.7 s, ~400 Hz)
is timed as well when present. Each figure is the median of ``--repeat`` runs.
"""

from __future__ import annotations

import argparse
import os
import platform
import re
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from _common import WALK_SPEED_MPS, cpu_name


def _wall(args: list[str]) -> float:
    t0 = time.perf_counter()
    subprocess.run(args, check=True, capture_output=True)
    return time.perf_counter() - t0


def _importtime() -> float:
    """``import footnav``'s cumulative time (s) as ``-X importtime`` reports it."""
    err = subprocess.run(
        [sys.executable, "-X", "importtime", "-c", "import footnav"], check=True, capture_output=True, text=True
    ).stderr
    match = re.search(r"\|\s*(\d+)\s*\|\s*footnav\s*$", err, re.MULTILINE)
    return int(match.group(1)) / 1e6


def _median(fn, repeat: int) -> tuple[float, list[float]]:
    runs = [fn() for _ in range(repeat)]
    return statistics.median(runs), runs


def _show(what: str, median: float, runs: list[float]) -> None:
    print(f"{what:<48} median {median:6.3f} s  (runs: {', '.join(f'{r:.3f}' for r in runs)})")


def _simulated_minute(folder: str) -> str:
    out = Path(folder) / "sim"
    subprocess.run(
        [
            sys.executable,
            "-m",
            "footnav.cli",
            "simulate",
            "straight",
            "--seed",
            "1",
            "--set",
            f"distance_m={60 * WALK_SPEED_MPS:.1f}",
            "--out",
            str(out),
        ],
        check=True,
        capture_output=True,
    )
    return str(out / "left.csv")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--repeat", type=int, default=7)
    ap.add_argument(
        "--file", action="append", help="recording(s) to run (default: a simulated minute, the x-io long walk)"
    )
    args = ap.parse_args()
    print(f"{cpu_name()}, {os.cpu_count()} cores, Python {platform.python_version()}")

    py = sys.executable
    _show("import footnav (-X importtime total)", *_median(_importtime, args.repeat))
    bare, _ = _median(lambda: _wall([py, "-c", "pass"]), args.repeat)
    _show(
        f"import footnav (wall, less {bare:.3f} s of bare python)",
        *_median(lambda: _wall([py, "-c", "import footnav"]) - bare, args.repeat),
    )
    _show("footnav --help (wall)", *_median(lambda: _wall([py, "-m", "footnav.cli", "--help"]), args.repeat))

    with tempfile.TemporaryDirectory() as tmp:
        files = args.file or [_simulated_minute(tmp)]
        if not args.file:
            xio = Path(os.environ.get("FOOTNAV_DATA", "")) / "xio_gait_tracking" / "long_walk.csv"
            if os.environ.get("FOOTNAV_DATA") and xio.exists():
                files.append(str(xio))
        for path in files:
            cmd = [py, "-m", "footnav.cli", "run", "--left", path, "--out", str(Path(tmp) / "out"), "--force"]
            _wall(cmd)  # warmup: fills numba's cache when empty, and the OS's file cache
            name = "simulated minute, 100 Hz" if path.startswith(tmp) else Path(path).name
            _show(f"footnav run ({name}, wall)", *_median(lambda cmd=cmd: _wall(cmd), args.repeat))


if __name__ == "__main__":
    main()
