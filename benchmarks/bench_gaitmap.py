"""footnav against gaitmap's RtsKalman on the same walk: detection + EKF + RTS smoothing.

Run:  python benchmarks/bench_gaitmap.py --gaitmap-python PY [--minutes 10] [--repeat 3]

PY is a Python with ``pip install gaitmap==2.6.0`` (gaitmap is not a footnav dependency; its
own venv keeps its pins away from ours). One simulated foot at 204.8 Hz (gaitmap's example
rate) is written to a temporary .npz; footnav's pipelines time it in this process, gaitmap's
``RtsKalman().estimate`` (its default ZUPT detector, error-state Kalman filter and RTS smoother,
level-walking pseudo-measurement) in a subprocess of PY. The two are timed alternately, best of
``--repeat`` in each of two rounds, so that a load on the machine falls on both. The ratio is
gaitmap's time over footnav's: higher is faster for footnav.

gaitmap expects acc in m/s^2 and gyr in deg/s in its own sensor frame; the simulated foot is given
in those units (the frame convention does not change the work done per sample, and is not the
point here: accuracy is compared on real recordings in docs/accuracy.md).
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import subprocess
import sys
import tempfile
import warnings
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _common import best_of, cpu_name, straight_walk

import footnav

RATE_HZ = 204.8

GAITMAP_SCRIPT = """
import json, sys, time, warnings
import numpy as np, pandas as pd
from gaitmap.trajectory_reconstruction import RtsKalman
warnings.simplefilter("ignore")
d = np.load(sys.argv[1])
cols = {f"acc_{a}": d["acc"][:, i] for i, a in enumerate("xyz")}
cols.update({f"gyr_{a}": np.rad2deg(d["gyr"][:, i]) for i, a in enumerate("xyz")})
data = pd.DataFrame(cols)
best = float("inf")
for _ in range(int(sys.argv[2])):
    t0 = time.perf_counter()
    RtsKalman().estimate(data, sampling_rate_hz=float(sys.argv[3]))
    best = min(best, time.perf_counter() - t0)
import gaitmap
print(json.dumps({"seconds": best, "version": gaitmap.__version__}))
"""

#: footnav pipelines timed: the default, and the detector closest to gaitmap's (a gyro threshold).
PIPELINES = {"default (adaptive + ekf, whole-walk RTS)": "adaptive", "threshold + ekf, whole-walk RTS": "threshold"}


def time_gaitmap(python: str, path: str, repeat: int) -> dict:
    out = subprocess.run(
        [python, "-c", GAITMAP_SCRIPT, path, str(repeat), str(RATE_HZ)], capture_output=True, text=True, check=False
    )
    if out.returncode != 0:
        raise SystemExit(f"gaitmap run failed:\n{out.stderr[-2000:]}")
    return json.loads(out.stdout.strip().splitlines()[-1])


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--gaitmap-python",
        default=os.environ.get("FOOTNAV_GAITMAP_PYTHON"),
        help="a Python with gaitmap 2.6 installed (or $FOOTNAV_GAITMAP_PYTHON)",
    )
    parser.add_argument("--minutes", type=float, default=10.0)
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args(argv)
    if not args.gaitmap_python:
        print("gaitmap not given (--gaitmap-python PY): nothing to compare; see the module docstring", file=sys.stderr)
        return 2
    walk = straight_walk(args.minutes, RATE_HZ)
    imu = walk.left
    n = imu.n_samples
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "walk.npz")
        np.savez(path, acc=imu.acc, gyr=imu.gyr)
        pipes = {label: footnav.make_pipeline(det, "ekf") for label, det in PIPELINES.items()}
        for pipe in pipes.values():  # compile outside the timing
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                pipe.run(imu)
        ours = {label: float("inf") for label in pipes}
        theirs, version = float("inf"), ""
        for _ in range(2):  # alternate, so that a load on the machine falls on both
            for label, pipe in pipes.items():
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    t, _ = best_of(lambda pipe=pipe: pipe.run(imu), args.repeat)
                ours[label] = min(ours[label], t)
            g = time_gaitmap(args.gaitmap_python, path, args.repeat)
            theirs, version = min(theirs, g["seconds"]), g["version"]
    print(
        f"machine: {cpu_name()}, {os.cpu_count()} cores, Python {platform.python_version()}, "
        f"numpy {np.__version__}, footnav {footnav.__version__}, gaitmap {version}"
    )
    print(f"walk: one foot, {n} samples at {RATE_HZ} Hz ({n / RATE_HZ / 60:.1f} min), best of {args.repeat} x 2 rounds")
    print(f"  gaitmap RtsKalman (its ZUPT detector + EKF + RTS): {theirs:.3f} s, {theirs / n * 1e6:.2f} us/sample")
    for label, t in ours.items():
        print(f"  footnav {label}: {t:.3f} s, {t / n * 1e6:.3f} us/sample, gaitmap / footnav = {theirs / t:.1f}x")
    return 0


if __name__ == "__main__":
    sys.exit(main())
