"""The default pipeline online against offline on the shared recordings: the figures of
docs/online.md ("The adaptive detector online").

Run ``FOOTNAV_DATA=/work/shared/data python tests/online_startup.py [name ...]`` (from the
repository, chunks of 50 samples): per foot, the stances of the live mask that the offline
default does not have (added) and those it has that the live mask lacks (removed), the largest
distance between the live step-wise smoothed samples and the offline step-wise smoothed run's,
whether ``close()`` equals the offline run, and the latency of the steps after the start-up
(s from a step's end until it is final).
"""

from __future__ import annotations

import os
import sys
import warnings

import numpy as np

sys.path.insert(0, os.path.dirname(__file__))

from online_replay import _replay

import footnav
from footnav.types import stance_intervals


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
        on, offm = live_stance[f.foot], getattr(off, f"stance_{f.foot}").mask[-len(live_stance[f.foot]):]
        so = {tuple(r) for r in stance_intervals(offm).tolist()}
        sn = {tuple(r) for r in stance_intervals(on).tolist()}
        dist = float(np.linalg.norm(got[f.foot] - ref.position, axis=1).max())
        same = float(np.abs(getattr(result, f.foot).position - getattr(off, f.foot).position).max()) <= 1e-9
        startup = f.startup + f.lag
        lat = [(b - a) / f.rate_hz for a, b in f.step_final_at if a >= startup]
        rows[f.foot] = (len(sn - so), len(so - sn), dist, same, lat)
    return rows


def _live_stances(pipe, rec, size):
    """Each foot's final stance decisions, as the stream took them (its input buffer's)."""
    stream = pipe.online(feet=1 if rec.right is None else 2, keep=False, rate_hz=rec.left.rate_hz)
    masks = {f.foot: [] for f in stream.feet}
    for foot in stream.feet:
        imu = getattr(rec, foot.foot)
        for a in range(0, imu.n_samples, size):
            stream.push(**{foot.foot: (imu.t[a:a + size], imu.acc[a:a + size], imu.gyr[a:a + size])})
            inp = foot.input
            done = sum(len(m) for m in masks[foot.foot])
            masks[foot.foot].append(inp.rows(done, foot.n_final)[3].copy())
    for foot in stream.feet:
        foot.finish()
        done = sum(len(m) for m in masks[foot.foot])
        masks[foot.foot].append(foot.input.rows(done, foot.n_final)[3].copy())
    return {k: np.concatenate(v) for k, v in masks.items()}


def main(names):
    from footnav.data.datasets import dataset_names, load_dataset

    print(f"{'recording':28s} foot  added removed  max_dist_m  close=offline  latency_s(median,max)")
    for name in names or dataset_names():
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            rec = load_dataset(name, os.environ.get("FOOTNAV_DATA"))
        for foot, (added, removed, dist, same, lat) in compare(rec).items():
            la = f"{np.median(lat):.2f}, {max(lat):.2f}" if lat else "-"
            print(f"{name:28s} {foot:5s} {added:5d} {removed:7d}  {dist:10.3g}  {same!s:13s}  {la}", flush=True)


if __name__ == "__main__":
    main(sys.argv[1:])
