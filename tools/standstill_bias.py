"""Can a walk's later standstills correct the gyro bias? Each rest's rate, and a bias bridged
between rests.

The default estimator takes the gyro bias from the first standstill and holds it. A bias that
walks could instead be read at every rest and interpolated linearly between them (the Brownian
bridge). Per recording and foot this prints every detected stance of at least ``--min-rest`` s:
its time, the share of its samples turning slower than 0.05 rad/s, and their mean rate about the
vertical (deg/min); then the default pipeline's figures with the gyro corrected by that bridge
(piecewise linear through the rests' mean rates, the first rest's bias unchanged) beside the
default's. ``--simulate LAPS`` does the same on the simulator's 150 x 60 m block walk (seeds
``0..--seeds-1``, a 2 s standstill at each end), against the truth.

Usage::

    FOOTNAV_DATA=../shared/data PYTHONPATH=$PWD python tools/standstill_bias.py [names...] [--min-rest 1.0]
    PYTHONPATH=$PWD python tools/standstill_bias.py --simulate 2 --seeds 20
"""

from __future__ import annotations

import argparse
import warnings
from dataclasses import replace

import numpy as np

import footnav
from footnav.analysis import metrics
from footnav.analysis.evaluation import evaluate
from footnav.data.datasets import dataset_names, load_dataset

STILL_RADPS = 0.05
BLOCK_LAP = [(150.0, 90.0), (60.0, 90.0)] * 2  # docs/make_accuracy.py's lap


def rests(imu, stance, min_rest_s: float) -> list[tuple[int, int, float, np.ndarray]]:
    """Stances of at least ``min_rest_s``: (start, stop, still share, mean rate of the still
    samples (3,), rad/s)."""
    out = []
    for a, b in np.asarray(stance.intervals):
        if b - a < min_rest_s * imu.rate_hz:
            continue
        w = imu.gyr[a:b]
        still = np.linalg.norm(w, axis=1) < STILL_RADPS
        if still.sum() >= 2:
            out.append((int(a), int(b), float(still.mean()), w[still].mean(axis=0)))
    return out


def bridged(imu, found) -> footnav.ImuData | None:
    """``imu`` with the gyro less the bias change interpolated between the rests (None: < 2)."""
    if len(found) < 2:
        return None
    t_mid = np.array([imu.t[(a + b) // 2] for a, b, _, _ in found])
    bias = np.array([w for *_, w in found])
    change = np.column_stack([np.interp(imu.t, t_mid, bias[:, i] - bias[0, i]) for i in range(3)])
    return footnav.ImuData(t=imu.t, acc=imu.acc, gyr=imu.gyr - change, mag=imu.mag, meta=imu.meta)


def _vertical_dpm(imu, a, b, w) -> float:
    up = imu.acc[a:b].mean(axis=0)
    return float(np.degrees(w @ up / np.linalg.norm(up)) * 60)


def recordings(names, min_rest_s: float) -> None:
    pipe = footnav.make_pipeline()
    for name in names:
        rec = load_dataset(name)
        changed = {}
        for side in ("left", "right"):
            imu = getattr(rec, side)
            if imu is None:
                continue
            found = rests(imu, pipe.detector.detect(imu), min_rest_s)
            for a, b, share, w in found:
                print(
                    f"{name:28s} {side:5s} rest {imu.t[a] - imu.t[0]:6.1f}-{imu.t[b - 1] - imu.t[0]:6.1f} s, "
                    f"{share * 100:3.0f} % still, {_vertical_dpm(imu, a, b, w):+6.1f} deg/min about the vertical"
                )
            new = bridged(imu, found)
            if new is not None:
                changed[side] = new
        if not changed:
            print(f"{name:28s} fewer than two rests on each foot: the bridge changes nothing")
            continue
        before, after = evaluate(pipe, rec), evaluate(pipe, replace(rec, **changed))
        cells = []
        for metric in ("ate_2d", "loop_closure_2d", "footprint_rmse"):
            for side in changed:
                try:
                    cells.append(
                        f"{metric} {side} {before.value(metric, side):.3f} -> {after.value(metric, side):.3f} m"
                    )
                except (KeyError, LookupError, ValueError):
                    pass
        print(f"{name:28s} bridged: " + "; ".join(cells))


def simulated(laps: int, seeds: int, min_rest_s: float) -> None:
    pipe = footnav.make_pipeline()
    rows = []
    for seed in range(seeds):
        rec = footnav.simulate("path", seed=seed, segments=BLOCK_LAP * laps)
        imu = rec.left
        new = bridged(imu, rests(imu, pipe.detector.detect(imu), min_rest_s))
        ate = [
            metrics.ate_rmse(pipe.run(x).left.position, rec.truth_left.position, dims=2)
            for x in (imu, imu if new is None else new)
        ]
        rows.append(ate)
        print(f"{laps} laps, seed {seed:2d}: 2-D ATE default {ate[0]:6.2f} m, bridged {ate[1]:6.2f} m")
    r = np.array(rows)
    print(
        f"{laps} laps, {seeds} seeds: mean / median / worst, default {r[:, 0].mean():.2f} / "
        f"{np.median(r[:, 0]):.2f} / {r[:, 0].max():.2f} m, bridged {r[:, 1].mean():.2f} / "
        f"{np.median(r[:, 1]):.2f} / {r[:, 1].max():.2f} m; bridged better on {(r[:, 1] < r[:, 0]).sum()}"
    )


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("names", nargs="*")
    ap.add_argument("--min-rest", type=float, default=1.0, help="shortest rest, s")
    ap.add_argument("--simulate", type=int, default=0, metavar="LAPS")
    ap.add_argument("--seeds", type=int, default=5)
    args = ap.parse_args(argv)
    warnings.simplefilter("ignore")
    if args.simulate:
        simulated(args.simulate, args.seeds, args.min_rest)
    else:
        recordings(args.names or dataset_names(), args.min_rest)


if __name__ == "__main__":
    main()
