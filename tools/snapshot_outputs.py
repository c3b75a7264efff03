"""Snapshot every component's outputs, to prove a refactor leaves them bit for bit unchanged.

Usage::

    python tools/snapshot_outputs.py --out /tmp/before.npz        # on the commit before
    python tools/snapshot_outputs.py --out /tmp/after.npz         # on the commit after
    python tools/snapshot_outputs.py --compare /tmp/before.npz /tmp/after.npz

Each case runs a pipeline (every detector, every estimator variant, every fusion) on shared
recordings (``--data-dir``, default ../shared/data; cases whose data is absent are skipped and
listed) and on simulated walks, and stores every array of the result: positions, velocities,
quaternions, position stds, footprints and stance masks. ``--compare`` exits 1 when any array
differs in shape or in a single bit (NaNs compare equal to NaNs), printing the largest absolute
difference of each that does.
"""

from __future__ import annotations

import argparse
import sys
import time
import warnings

import numpy as np

#: (name, recording, detector, estimator, estimator params, fusion).
SIM = "sim"
CASES = [
    ("sim-adaptive-ekf-independent", SIM, "adaptive", "ekf", {}, "independent"),
    ("sim-threshold-ekf", SIM, "threshold", "ekf", {}, "independent"),
    ("sim-glrt-ekf", SIM, "glrt", "ekf", {}, "independent"),
    ("sim-hmm-ekf", SIM, "hmm", "ekf", {}, "independent"),
    ("sim-dualgait-ekf", SIM, "dual-gait", "ekf", {}, "independent"),
    ("sim-ekf-forward", SIM, "adaptive", "ekf", {"smoother": "none"}, "independent"),
    ("sim-ekf-step", SIM, "adaptive", "ekf", {"smoother": "step"}, "independent"),
    ("sim-ekf-15", SIM, "adaptive", "ekf", {"bias_states": True, "zaru_std_radps": 0.005}, "independent"),
    ("sim-ekf-closed", SIM, "adaptive", "ekf", {"closed_loop": True}, "independent"),
    ("sim-madgwick", SIM, "adaptive", "madgwick", {}, "independent"),
    ("sim-range", SIM, "adaptive", "ekf", {}, "range"),
    ("sim-step-vector", SIM, "adaptive", "ekf", {}, "step-vector"),
    ("sim-particle", SIM, "adaptive", "ekf", {}, "particle"),
    ("sim-dtw", SIM, "adaptive", "ekf", {}, "dtw"),
    ("azure-default", "azure_fgo", "adaptive", "ekf", {}, "independent"),
    ("azure-range", "azure_fgo", "adaptive", "ekf", {}, "range"),
    ("azure-madgwick", "azure_fgo", "adaptive", "madgwick", {}, "independent"),
    ("xio-short", "xio_short", "adaptive", "ekf", {}, "independent"),
    ("xio-short-closed", "xio_short", "adaptive", "ekf", {"closed_loop": True}, "independent"),
    ("pyshoe", "pyshoe_2017-11-22-11-22-03", "adaptive", "ekf", {}, "independent"),
    ("ipol-hmm", "ipol_1-1", "hmm", "ekf", {}, "independent"),
    ("ipol-step-vector", "ipol_1-1", "adaptive", "ekf", {}, "step-vector"),
    ("gaitdriven-ekf-step", "gaitdriven_31", "adaptive", "ekf", {"smoother": "step"}, "independent"),
]


def _simulated():
    from footnav import simulate

    # A rectangle: straight walking and four turns, both feet, the default consumer-grade sensor.
    return simulate("rectangle", width_m=12.0, height_m=6.0, seed=7)


def _arrays(result) -> dict[str, np.ndarray]:
    out = {}
    for side in ("left", "right"):
        traj = getattr(result, side)
        stance = getattr(result, f"stance_{side}")
        if traj is None:
            continue
        for name in ("t", "position", "velocity", "quaternion", "position_std", "steps"):
            out[f"{side}.{name}"] = np.asarray(getattr(traj, name))
        out[f"{side}.stance"] = np.asarray(stance.mask)
    return out


def snapshot(data_dir: str | None) -> tuple[dict[str, np.ndarray], list[str]]:
    import footnav
    from footnav.data.datasets import load_dataset

    arrays, skipped, recordings = {}, [], {}
    for name, source, detector, estimator, params, fusion in CASES:
        if source not in recordings:
            try:
                recordings[source] = _simulated() if source == SIM else load_dataset(source, data_dir)
            except footnav.FootnavError as exc:
                recordings[source] = exc
        recording = recordings[source]
        if isinstance(recording, Exception):
            skipped.append(f"{name}: {recording}")
            continue
        start = time.perf_counter()
        pipe = footnav.make_pipeline(detector, estimator, fusion, estimator_params=params)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            result = pipe.run(recording)
        for key, value in _arrays(result).items():
            arrays[f"{name}/{key}"] = value
        print(f"{name:32s} {time.perf_counter() - start:6.1f} s", flush=True)
    return arrays, skipped


def compare(before: str, after: str) -> int:
    a, b = np.load(before), np.load(after)
    differ = 0
    for key in sorted(set(a.files) | set(b.files)):
        if key not in a.files or key not in b.files:
            print(f"{key}: only in {'after' if key not in a.files else 'before'}")
            differ += 1
        elif a[key].shape != b[key].shape or a[key].dtype != b[key].dtype:
            print(f"{key}: shape/dtype {a[key].shape} {a[key].dtype} -> {b[key].shape} {b[key].dtype}")
            differ += 1
        elif not np.array_equal(a[key], b[key], equal_nan=a[key].dtype.kind == "f"):
            diff = np.nanmax(np.abs(a[key].astype(float) - b[key].astype(float)))
            print(f"{key}: differs, max |diff| {diff:.3g}")
            differ += 1
    print(f"{len(set(a.files) | set(b.files))} arrays compared, {differ} differ")
    return 1 if differ else 0


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", help="write the snapshot to this .npz")
    parser.add_argument("--data-dir", default=None, help="shared recordings (default: footnav's data_dir())")
    parser.add_argument("--compare", nargs=2, metavar=("BEFORE", "AFTER"))
    args = parser.parse_args(argv)
    if args.compare:
        return compare(*args.compare)
    if not args.out:
        parser.error("give --out or --compare")
    arrays, skipped = snapshot(args.data_dir)
    np.savez_compressed(args.out, **arrays)
    for line in skipped:
        print("skipped", line)
    print(f"{len(arrays)} arrays written to {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
