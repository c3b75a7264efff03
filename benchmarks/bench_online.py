"""Online mode: throughput, memory and latency of a 1-hour two-foot replay.

Run:  python benchmarks/bench_online.py [--minutes 60] [--chunk-s 1.0] [--repeat 1] [--pipeline default]

A simulated 5.6-minute walk (a 60 x 25 m loop, standstills at both ends) is repeated to fill
``--minutes`` at 100 Hz and pushed through ``pipeline.online(feet=2, keep=False)`` (threshold
detector, EKF smoothing each step at its end, independent feet) in chunks of ``--chunk-s`` per
foot, both feet in each push. Reported:

* throughput: the walk's duration over the wall time of all pushes (one core, no tracing), and
  over the process's CPU time in them (less sensitive to other work on a shared machine); with
  ``--repeat N`` the median of N replays;
* memory: tracemalloc's peak over the first 10 minutes and over the whole replay (a second run:
  tracing slows Python-level code), which must stay within 10 %;
* latency: for every closed step, the samples between the step's end (its stance's last sample)
  and the newest sample pushed when it became final, against the detector's declared
  ``latency_s`` (chunks of one sample, on the first minutes: a longer chunk only adds its length);
* the offline causal run of the first loop against the online one (largest position difference).

``--pipeline default`` replays ``make_pipeline()``'s components instead (the adaptive detector, the
whole-walk smoother's step-wise output live and its rerun at close, the floors).

``--fusion range`` (or ``step-vector``, with the pendulum step length as in the figures so far, or
``particle``) runs both
feet in the coupled fusion's joint filter instead (:mod:`footnav.pipeline.online_joint`; the
per-foot streams run beside it), and the same pipeline with ``independent`` in turn, round by
round in the same process, for the ratio of their times.
"""

from __future__ import annotations

import argparse
import math
import os
import platform
import sys
import time
import tracemalloc
import warnings
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _common import cpu_name

import footnav

RATE_HZ = 100.0


def tiled_walk(minutes: float) -> tuple[footnav.ImuData, footnav.ImuData, footnav.Recording]:
    """One loop repeated to fill ``minutes``: it starts and ends standing still, so the copies
    join without a jump."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        loop = footnav.simulate("rectangle", seed=7, rate_hz=RATE_HZ, width_m=60, height_m=25)
    copies = max(1, math.ceil(minutes * 60 / (loop.left.duration_s + 1 / RATE_HZ)))
    feet = []
    for imu in (loop.left, loop.right):
        n = imu.n_samples
        t = np.arange(n * copies) / RATE_HZ
        feet.append(footnav.ImuData(t=t, acc=np.tile(imu.acc, (copies, 1)), gyr=np.tile(imu.gyr, (copies, 1))))
    return feet[0], feet[1], loop


def replay(pipe, left, right, chunk: int, trace_at_s: float | None = None, view=None):
    """Push both feet in chunks; returns (wall time in push, the stream, peak bytes at
    ``trace_at_s`` of walk, peak bytes at the end, CPU time in push). With ``view`` (a LiveView)
    each push's steps are handed to it, inside the timed part."""
    stream = pipe.online(feet=2, keep=False)
    n = left.n_samples
    spent, cpu, peak_early = 0.0, 0.0, None
    for a in range(0, n, chunk):
        b = min(a + chunk, n)
        lc = (left.t[a:b], left.acc[a:b], left.gyr[a:b])
        rc = (right.t[a:b], right.acc[a:b], right.gyr[a:b])
        c0, t0 = time.process_time(), time.perf_counter()
        update = stream.push(left=lc, right=rc)
        if view is not None:
            view.add(update.steps)
            view.flush()
        spent += time.perf_counter() - t0
        cpu += time.process_time() - c0
        if trace_at_s is not None and peak_early is None and left.t[b - 1] >= trace_at_s:
            peak_early = tracemalloc.get_traced_memory()[1]
    c0, t0 = time.process_time(), time.perf_counter()
    stream.close()
    spent += time.perf_counter() - t0
    cpu += time.process_time() - c0
    peak_end = tracemalloc.get_traced_memory()[1] if trace_at_s is not None else None
    return spent, stream, peak_early, peak_end, cpu


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--minutes", type=float, default=60.0)
    ap.add_argument("--chunk-s", type=float, default=1.0, help="chunk length per foot and push, s")
    ap.add_argument("--repeat", type=int, default=1, help="throughput replays; their median is reported")
    ap.add_argument(
        "--fusion",
        default="independent",
        choices=["independent", "range", "step-vector", "particle"],
        help="independent feet, or both in a coupled fusion's joint filter (step-vector: the pendulum step length)",
    )
    ap.add_argument("--view", action="store_true", help="with and without footnav follow's live view, in turn")
    ap.add_argument(
        "--pipeline",
        default="bench",
        choices=["bench", "default"],
        help="bench: threshold + step-wise EKF (the figures since issue 19); default: make_pipeline()'s "
        "components (adaptive detector, whole-walk smoother, floors) with --fusion",
    )
    args = ap.parse_args()
    params = {"step_length": "pendulum"} if args.fusion == "step-vector" else {}
    if args.pipeline == "default":
        pipe = footnav.make_pipeline(fusion=args.fusion, fusion_params=params)
    else:
        pipe = footnav.make_pipeline(
            "threshold", "ekf", args.fusion, estimator_params={"smoother": "step"}, fusion_params=params
        )
    left, right, loop = tiled_walk(args.minutes)
    chunk = max(1, round(args.chunk_s * RATE_HZ))
    print(f"pipeline: {pipe!r}")
    print(f"machine: {cpu_name()}, {platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}")
    print(
        f"walk: {left.duration_s / 60:.1f} min at {RATE_HZ:g} Hz, two feet, {left.n_samples} samples per foot; "
        f"chunks of {chunk} samples per foot"
    )

    replay(pipe, loop.left.slice(0, 2000), loop.right.slice(0, 2000), chunk)  # compile and warm up
    coupled = args.fusion != "independent"
    # the reference replayed in turn in this process: independent feet for a coupled fusion (of the
    # same pipeline), the bench pipeline for the default one
    compared = coupled or args.pipeline == "default"
    base = None
    if coupled and args.pipeline == "default":
        base = footnav.make_pipeline()
    elif compared:
        base = footnav.make_pipeline("threshold", "ekf", "independent", estimator_params={"smoother": "step"})
    if compared:
        replay(base, loop.left.slice(0, 2000), loop.right.slice(0, 2000), chunk)
    runs, base_runs = [], []
    for _ in range(max(1, args.repeat)):  # the fusion and independent in turn, in this process
        runs.append(replay(pipe, left, right, chunk))
        if compared:
            base_runs.append(replay(base, left, right, chunk)[0])
    spent = float(np.median([r[0] for r in runs]))
    cpu = float(np.median([r[4] for r in runs]))
    pushes = math.ceil(left.n_samples / chunk)
    each = (
        f" (median of {len(runs)}: {', '.join(f'{left.duration_s / r[0]:,.0f}x' for r in runs)})"
        if len(runs) > 1
        else ""
    )
    print(
        f"throughput: {left.duration_s / spent:,.0f}x real time{each} "
        f"({spent:.2f} s for {left.duration_s / 60:.1f} min, "
        f"{spent / (2 * left.n_samples) * 1e6:.2f} us per sample, "
        f"{spent / pushes * 1e6:.0f} us per push of both feet); "
        f"CPU time: {left.duration_s / cpu:,.0f}x "
        f"({cpu / pushes * 1e6:.0f} us per push)"
    )
    if compared:
        ratios = [r[0] / b for r, b in zip(runs, base_runs)]
        print(
            f"  against {base!r} in this process, replayed in turn: {float(np.median(ratios)):.2f}x its time "
            f"(rounds: {', '.join(f'{x:.2f}x' for x in ratios)}; "
            f"it ran {left.duration_s / float(np.median(base_runs)):,.0f}x real time)"
        )

    if args.view:
        view_ratio(pipe, left, right, chunk, max(1, args.repeat))
        return

    tracemalloc.start()
    _, _, early, end, _ = replay(pipe, left, right, chunk, trace_at_s=min(600.0, left.duration_s / 2))
    tracemalloc.stop()
    print(
        f"memory (tracemalloc peak): {early / 1e6:.2f} MB after 10 min, {end / 1e6:.2f} MB after "
        f"{left.duration_s / 60:.0f} min ({100 * (end / early - 1):+.1f} %)"
    )

    # latency, chunks of one sample, on the first loop (both feet in lockstep for a coupled fusion)
    first = loop.left
    one = pipe.online(feet=2 if coupled else 1)
    for a in range(first.n_samples):
        chunks = {"left": (first.t[a : a + 1], first.acc[a : a + 1], first.gyr[a : a + 1])}
        if coupled:
            chunks["right"] = (loop.right.t[a : a + 1], loop.right.acc[a : a + 1], loop.right.gyr[a : a + 1])
        one.push(**chunks)
    result = one.close()
    lag = np.array([newest - end for end, newest in (one.joint.feet[0] if coupled else one.feet[0]).step_final_at])
    declared = pipe.detector.latency_s
    print(
        f"latency: a step is final {lag.min()}-{lag.max()} samples ({lag.max() / RATE_HZ * 1e3:.0f} ms at most) "
        f"after its stance's last sample arrives; declared latency_s = {declared:.3f} s "
        f"({math.ceil(declared * RATE_HZ)} samples) + 3 samples of the stream's margin"
    )
    if coupled:
        later = lag[5:]
        print(
            f"  (the first steps wait for both feet's first-step headings: the first 5 steps {lag[:5].tolist()}, "
            f"the {len(later)} after them {later.min()}-{later.max()} samples)"
        )
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        off = pipe.run(first, loop.right if coupled else None)
    print(
        f"offline causal run vs online (chunks of 1): largest position difference "
        f"{np.abs(off.left.position - result.left.position).max():.1e} m"
    )


def view_ratio(pipe, left, right, chunk: int, repeat: int) -> None:
    """Throughput with the live view and without, replayed in turn."""
    from footnav.report.live import LiveView

    on, off, cpu_on, cpu_off, drawn = [], [], [], [], 0
    for _ in range(repeat):
        r = replay(pipe, left, right, chunk)
        off.append(r[0])
        cpu_off.append(r[4])
        view = LiveView("bench_online --view")
        view.wait_ready()  # its start (matplotlib's import) is once per run, not throughput
        t0 = time.perf_counter()
        r = replay(pipe, left, right, chunk, view=view)
        on.append(r[0])
        cpu_on.append(r[4])
        view.close()
        drawn = view.sent
    off_s, on_s = float(np.median(off)), float(np.median(on))
    print(
        f"live view: {left.duration_s / on_s:,.0f}x real time with it, {left.duration_s / off_s:,.0f}x without "
        f"(median of {repeat}; rounds with/without: {', '.join(f'{a / b:.2f}' for a, b in zip(on, off))}); "
        f"with it {on_s / off_s:.2f}x the time; {drawn} steps sent to the view, "
        f"{time.perf_counter() - t0:.1f} s for the last round with it"
    )
    print(
        f"  the stream's own CPU time (its process; the view draws in another): "
        f"{float(np.median(cpu_on)) / float(np.median(cpu_off)):.2f}x with the view"
    )


if __name__ == "__main__":
    main()
