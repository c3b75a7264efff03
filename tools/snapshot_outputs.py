"""Snapshot every component's outputs, to prove a refactor leaves them bit for bit unchanged.

Usage::

    python tools/snapshot_outputs.py --out /tmp/before.npz        # on the commit before
    python tools/snapshot_outputs.py --out /tmp/after.npz         # on the commit after
    python tools/snapshot_outputs.py --compare /tmp/before.npz /tmp/after.npz

Each case runs a pipeline (every detector, every estimator variant, every fusion) on shared
recordings (``--data-dir``, default ../shared/data; cases whose data is absent are skipped and
listed) and on simulated walks, and stores every array of the result: positions, velocities,
quaternions, position stds, footprints and stance masks. The online cases (``ONLINE_CASES``) push
the same recordings through ``pipeline.online`` in chunks, with small filter segments (many
restarts), and store what the pushes returned (samples, forward estimates, closed steps) and
``close``'s result. ``--compare`` exits 1 when any array
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

#: (name, recording, detector, estimator params, fusion, fusion params, chunk sizes): online runs.
STEP = {"smoother": "step"}
ONLINE_CASES = [
    ("online-sim-threshold-step", SIM, "threshold", STEP, "independent", {}, (7, 13)),
    ("online-sim-glrt-15", SIM, "glrt", {**STEP, "bias_states": True}, "independent", {}, (333, 333)),
    ("online-sim-forward", SIM, "threshold", {"smoother": "none"}, "independent", {}, (50, 50)),
    ("online-sim-range", SIM, "threshold", STEP, "range", {"max_separation_m": 0.6}, (7, 5)),
    ("online-sim-range-forward", SIM, "threshold", {"smoother": "none"}, "range", {"max_separation_m": 0.6}, (7, 5)),
    ("online-sim-step-vector", SIM, "threshold", STEP, "step-vector", {"step_length": "pendulum"}, (7, 5)),
    ("online-sim-particle", SIM, "threshold", STEP, "particle", {}, (11, 9)),
    ("online-sim-default", SIM, "adaptive", {}, "independent", {}, (100, 100)),
    ("online-ipol-range", "ipol_1-1", "threshold", STEP, "range", {}, (64, 64)),
    (
        "online-azure-step-vector",
        "azure_fgo",
        "threshold",
        STEP,
        "step-vector",
        {"step_length": "pendulum"},
        (100, 100),
    ),
]
#: The filter segments' size in the online cases (samples; 16384 by default): restarts often.
ONLINE_SEGMENT = 300


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


def _chunks(imu, size):
    for a in range(0, imu.n_samples, size):
        yield imu.t[a : a + size], imu.acc[a : a + size], imu.gyr[a : a + size]


def _online(pipe, recording, sizes) -> dict[str, np.ndarray]:
    """Push both feet in chunks (the earlier foot's next chunk first); every array the pushes
    returned, concatenated per foot, the closed steps, and close()'s result."""
    from footnav.pipeline import online_foot, online_joint

    saved = online_foot.SEGMENT_SAMPLES, online_joint.SEGMENT_SAMPLES
    online_foot.SEGMENT_SAMPLES = online_joint.SEGMENT_SAMPLES = ONLINE_SEGMENT
    try:
        stream = pipe.online(feet=2)
        queues = {"left": _chunks(recording.left, sizes[0]), "right": _chunks(recording.right, sizes[1])}
        heads = {foot: next(q, None) for foot, q in queues.items()}
        updates = []
        while any(h is not None for h in heads.values()):
            foot = min((f for f, h in heads.items() if h is not None), key=lambda f: heads[f][0][0])
            updates.append(stream.push(**{foot: heads[foot]}))
            heads[foot] = next(queues[foot], None)
        result = stream.close()
        updates.append(stream.last_update)
    finally:
        online_foot.SEGMENT_SAMPLES, online_joint.SEGMENT_SAMPLES = saved
    out = {}
    for side in ("left", "right"):
        parts = [getattr(u, side) for u in updates]
        for name in ("t", "position", "velocity", "quaternion", "stance"):
            out[f"pushed.{side}.{name}"] = np.concatenate([getattr(p, name) for p in parts])
        fwd = [p.forward for p in parts if p.forward is not None]
        for name in ("t", "position", "velocity", "quaternion", "position_cov"):
            out[f"pushed.{side}.forward.{name}"] = np.array([getattr(e, name) for e in fwd])
    steps = [s for u in updates for s in u.steps]
    out["pushed.steps.t"] = np.array([s.t for s in steps])
    out["pushed.steps.foot"] = np.array([s.foot == "left" for s in steps])
    out["pushed.steps.position"] = np.array([s.position for s in steps]).reshape(-1, 3)
    out["pushed.steps.stride_heading"] = np.array([(s.stride_length_m, s.heading_rad) for s in steps]).reshape(-1, 2)
    if result is not None:
        out.update({f"closed.{k}": v for k, v in _arrays(result).items()})
    return out


def _recording(recordings: dict, source: str, data_dir: str | None):
    import footnav
    from footnav.data.datasets import load_dataset

    if source not in recordings:
        try:
            recordings[source] = _simulated() if source == SIM else load_dataset(source, data_dir)
        except footnav.FootnavError as exc:
            recordings[source] = exc
    return recordings[source]


def snapshot(data_dir: str | None) -> tuple[dict[str, np.ndarray], list[str]]:
    import footnav

    arrays, skipped, recordings = {}, [], {}
    for name, source, detector, estimator, params, fusion in CASES:
        recording = _recording(recordings, source, data_dir)
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
    for name, source, detector, params, fusion, fusion_params, sizes in ONLINE_CASES:
        recording = _recording(recordings, source, data_dir)
        if isinstance(recording, Exception):
            skipped.append(f"{name}: {recording}")
            continue
        start = time.perf_counter()
        pipe = footnav.make_pipeline(detector, "ekf", fusion, estimator_params=params, fusion_params=fusion_params)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            for key, value in _online(pipe, recording, sizes).items():
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
