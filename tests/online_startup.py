"""The default pipeline online against offline on the shared recordings: the figures of
docs/online.md ("The adaptive detector online").

Run ``FOOTNAV_DATA=/work/shared/data python tests/online_startup.py [name ...]`` (from the
repository, chunks of 50 samples): per foot, the stances of the live mask that the offline
default does not have (added) and those it has that the live mask lacks (removed), the largest
distance between the live step-wise smoothed samples and the offline step-wise smoothed run's,
whether ``close()`` equals the offline run, and the latency of the steps after the start-up
(s from a step's end until it is final).

``--step-vector``: the step-vector fusion with its defaults (the fitted leg length) online
instead, on the two-foot recordings (glrt detector, whose live stances are the offline ones,
step-wise smoothing): the leg length when the first update was applied and at the end against
the offline whole-walk fit, the updates that waited for the fit, the largest distance between
a live and an offline footprint, and whether ``close()`` equals the offline run (the figures of
docs/online.md, "Both feet in one filter").

``--close N``: the default pipeline online in chunks of N samples (1: sample by sample) on the
two-foot recordings, the largest distance between ``close()`` and the offline run (issue 35's
acceptance: chunks of 1, 7 and 1,000).

``--dual-gait``: the dual-gait detector online (both feet decided together,
:mod:`footnav.pipeline.online_pair`; EKF with step-wise smoothing, independent feet) on the
two-foot recordings: per foot the live stances the offline detector does not have and those it
lacks, the largest distance between the live samples and the offline run's, whether ``close()``
equals the offline run, and the steps' latency (the figures of docs/online.md, "Dual-gait online").
"""

from __future__ import annotations

import os
import sys
import warnings

import numpy as np

sys.path.insert(0, os.path.dirname(__file__))

from online_replay import _replay

import footnav
from footnav.core.types import stance_intervals


def _differences(live, offline):
    """(stances of ``live`` that ``offline`` lacks, stances of ``offline`` that ``live`` lacks)."""
    on, off = ({tuple(r) for r in stance_intervals(m).tolist()} for m in (live, offline))
    return len(on - off), len(off - on)


def compare(rec, size=50):
    """Per foot: (added, removed, max live-offline distance m, close equal, latencies s after
    the start-up); the live stream and the offline runs of the default pipeline."""
    pipe = footnav.make_pipeline()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        off = pipe.run(rec.left, rec.right)
        step = footnav.make_pipeline(estimator_params={"smoother": "step"}).run(rec.left, rec.right)
        got, _, result, stream = _replay(pipe, rec.left, rec.right, size, max_wait_s=1e9, rate_hz=rec.left.rate_hz)
        live_stance = _live_stances(pipe, rec, size)
    rows = {}
    for f in stream.feet:
        ref = getattr(step, f.foot)
        on, offm = live_stance[f.foot], getattr(off, f"stance_{f.foot}").mask[-len(live_stance[f.foot]) :]
        added, removed = _differences(on, offm)
        dist = float(np.linalg.norm(got[f.foot] - ref.position, axis=1).max())
        same = float(np.abs(getattr(result, f.foot).position - getattr(off, f.foot).position).max()) <= 1e-9
        startup = f.startup + f.lag
        lat = [(b - a) / f.rate_hz for a, b in f.step_final_at if a >= startup]
        rows[f.foot] = (added, removed, dist, same, lat)
    return rows


def _live_stances(pipe, rec, size):
    """Each foot's final stance decisions, as the stream took them (its input buffer's)."""
    stream = pipe.online(feet=1 if rec.right is None else 2, keep=False, rate_hz=rec.left.rate_hz)
    masks = {f.foot: [] for f in stream.feet}
    for foot in stream.feet:
        imu = getattr(rec, foot.foot)
        for a in range(0, imu.n_samples, size):
            stream.push(**{foot.foot: (imu.t[a : a + size], imu.acc[a : a + size], imu.gyr[a : a + size])})
            inp = foot.input
            done = sum(len(m) for m in masks[foot.foot])
            masks[foot.foot].append(inp.rows(done, foot.n_final)[3].copy())
    for foot in stream.feet:
        foot.finish()
        done = sum(len(m) for m in masks[foot.foot])
        masks[foot.foot].append(foot.input.rows(done, foot.n_final)[3].copy())
    return {k: np.concatenate(v) for k, v in masks.items()}


def compare_step_vector(rec, size=50):
    """(leg m at the first update, at the end, offline; first update s; updates waiting; largest
    live-offline footprint distance m; close equal) of step-vector's defaults online."""
    pipe = footnav.make_pipeline("glrt", "ekf", "step-vector", estimator_params={"smoother": "step"})
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        off = pipe.run(rec.left, rec.right)
        _, steps, result, _ = _replay(pipe, rec.left, rec.right, size, max_wait_s=1e9, rate_hz=rec.left.rate_hz)
    live = result.meta["online"]["fusion"]
    fit = live["leg_length_fit"]
    legs = fit["per_update"]["leg_length_m"]
    dist = 0.0
    for foot in ("left", "right"):
        mine = np.array([s.position for s in steps if s.foot == foot]).reshape(-1, 3)
        ref = getattr(off, foot).footprints
        n = min(len(mine), len(ref))
        dist = max(dist, float(np.linalg.norm(mine[:n] - ref[:n], axis=1).max()) if n else 0.0)
    same = all(
        float(np.abs(getattr(result, f).position - getattr(off, f).position).max()) <= 1e-9 for f in ("left", "right")
    )
    return (
        legs[0] if legs else None,
        legs[-1] if legs else None,
        off.meta["fusion"]["leg_length_m"],
        fit["first_update_s"],
        fit["updates_waiting"],
        dist,
        same,
    )


def compare_dual_gait(rec, size=50):
    """Per foot: (added, removed, max live-offline distance m, close equal, latencies s)."""
    pipe = footnav.make_pipeline("dual-gait", "ekf", "independent", estimator_params={"smoother": "step"})
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        off = pipe.run(rec.left, rec.right)
        got, _, result, stream = _replay(pipe, rec.left, rec.right, size, max_wait_s=1e9, rate_hz=rec.left.rate_hz)
    rows = {}
    for f in stream.feet:
        ref, live = getattr(off, f.foot), f.trajectory()[1].mask
        offm = getattr(off, f"stance_{f.foot}").mask[-len(live) :]
        added, removed = _differences(live, offm)
        n = min(len(got[f.foot]), len(ref.position))
        dist = float(np.linalg.norm(got[f.foot][-n:] - ref.position[-n:], axis=1).max())
        same = float(np.abs(getattr(result, f.foot).position - ref.position).max()) <= 1e-9
        lat = [(b - a) / f.rate_hz for a, b in f.step_final_at]
        rows[f.foot] = (added, removed, dist, same, lat)
    return rows


def _recordings(names, two_feet=False):
    """(name, recording) of ``names`` (every dataset when empty), loaded quietly; with
    ``two_feet`` only those with both feet."""
    from footnav.data.datasets import dataset_names, load_dataset

    root = os.environ.get("FOOTNAV_DATA")
    for name in names or dataset_names(root):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            rec = load_dataset(name, root)
        if not (two_feet and rec.right is None):
            yield name, rec


def _print_stances(names, compare_one, two_feet=False):
    print(f"{'recording':28s} foot  added removed  max_dist_m  close=offline  latency_s(median,max)")
    for name, rec in _recordings(names, two_feet):
        for foot, (added, removed, dist, same, lat) in compare_one(rec).items():
            la = f"{np.median(lat):.2f}, {max(lat):.2f}" if lat else "-"
            print(f"{name:28s} {foot:5s} {added:5d} {removed:7d}  {dist:10.3g}  {same!s:13s}  {la}", flush=True)


def main_close(names, size):
    worst = 0.0
    for name, rec in _recordings(names, two_feet=True):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            off = footnav.make_pipeline().run(rec.left, rec.right)
            _, _, result, _ = _replay(
                footnav.make_pipeline(), rec.left, rec.right, size, max_wait_s=1e9, rate_hz=rec.left.rate_hz
            )
        d = max(float(np.abs(getattr(result, f).position - getattr(off, f).position).max()) for f in ("left", "right"))
        worst = max(worst, d)
        print(f"{name:28s} close() - offline {d:.3g} m", flush=True)
    print(f"largest: {worst:.3g} m")


def main_step_vector(names):
    def f(x):
        return "-" if x is None else f"{x:.3f}"

    print(
        f"{'recording':28s} leg_first  leg_last  leg_offline  first_update_s  waiting  "
        "max_footprint_dist_m  close=offline"
    )
    for name, rec in _recordings(names, two_feet=True):
        try:
            first, last, offline, t0, waiting, dist, same = compare_step_vector(rec)
        except footnav.FootnavError as exc:
            print(f"{name:28s} {type(exc).__name__}: {exc}", flush=True)
            continue
        print(
            f"{name:28s} {f(first):>9s}  {f(last):>8s}  {offline:11.3f}  {f(t0):>14s}  "
            f"{waiting:7d}  {dist:20.3g}  {same!s}",
            flush=True,
        )


if __name__ == "__main__":
    args = sys.argv[1:]
    size = int(args.pop(args.index("--close") + 1)) if "--close" in args else None
    names = [a for a in args if not a.startswith("--")]
    if size is not None:
        main_close(names, size)
    elif "--step-vector" in sys.argv:
        main_step_vector(names)
    else:
        dual = "--dual-gait" in sys.argv
        _print_stances(names, compare_dual_gait if dual else compare, two_feet=dual)
