"""Replay every shared two-foot recording through the online stream and compare with the offline run.

Usage::

    python tools/replay_online.py --fusion range --chunks 1 7 1000
    python tools/replay_online.py --fusion step-vector --data-dir ../shared/data

Each recording found under ``--data-dir`` (default ``$FOOTNAV_DATA`` or ../shared/data) is run
offline (``pipe.run``) and pushed through ``pipe.online(feet=2)`` in chunks of each size given
(``tests/online_replay.py``'s replay: each foot's next chunk when it is the earlier one), with the
glrt detector and the EKF smoothing each step at its end; the coupled fusions with parameters
under which they act often (range: 0.6 m bound; step-vector: the pendulum step length, the paper
as published; particle: footnav's mode). Prints the largest position difference per recording
and chunk size, and over all of them.
"""

from __future__ import annotations

import argparse
import os
import sys
import time
import warnings
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tests"))
from online_replay import _replay  # noqa: E402

import footnav  # noqa: E402
from footnav.data.datasets import dataset_names, load_dataset  # noqa: E402

PARAMS = {
    "independent": {},
    "range": {"max_separation_m": 0.6},
    "step-vector": {"step_length": "pendulum"},
    "particle": {},
}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--fusion", default="range", choices=sorted(PARAMS))
    ap.add_argument("--chunks", type=int, nargs="+", default=[1, 7, 1000])
    ap.add_argument("--data-dir", default=os.environ.get("FOOTNAV_DATA", str(ROOT.parent / "shared" / "data")))
    args = ap.parse_args()
    warnings.simplefilter("ignore")
    data = Path(args.data_dir)
    pipe = footnav.make_pipeline(
        "glrt", "ekf", args.fusion, estimator_params={"smoother": "step"}, fusion_params=PARAMS[args.fusion]
    )
    worst, n = 0.0, 0
    for name in dataset_names(data):
        try:
            rec = load_dataset(name, data)
        except footnav.DataNotFoundError:
            continue
        if rec.right is None:
            continue
        off = pipe.run(rec.left, rec.right)
        meta = off.meta["fusion"]
        acts = meta.get("constraint_updates", meta.get("updates", meta.get("pf_updates", 0)))
        for size in args.chunks:
            t0 = time.perf_counter()
            got, _, result, _ = _replay(pipe, rec.left, rec.right, size, rate_hz=rec.left.rate_hz)
            diff = max(
                max(
                    np.abs(getattr(result, f).position - getattr(off, f).position).max(),
                    np.abs(got[f] - getattr(off, f).position).max(),
                )
                for f in ("left", "right")
            )
            worst, n = max(worst, diff), n + 1
            print(
                f"{name:32s} chunks {size:5d}  updates {acts:5d}  largest difference {diff:.3g} m  "
                f"({time.perf_counter() - t0:.1f} s)",
                flush=True,
            )
    print(f"{n} replays ({args.fusion}); largest difference {worst:.3g} m")


if __name__ == "__main__":
    main()
