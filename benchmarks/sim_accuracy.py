"""Accuracy of a pipeline on the simulator's acceptance walks, through the evaluation harness.

Run:  python benchmarks/sim_accuracy.py [--seeds 0 1 2] [--rate-hz 100]

Walks: straight 100 m, rectangle 105 x 68 m counter-clockwise and clockwise. Prints the harness's
table (2-D ATE after rigid alignment, loop closure for the closed rectangle) and each error as a
percentage of the distance walked.
"""

from __future__ import annotations

import argparse

import footnav
from footnav.analysis import metrics


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--seeds", type=int, nargs="+", default=[0, 1, 2])
    ap.add_argument("--rate-hz", type=float, default=100.0)
    args = ap.parse_args()
    pipe = footnav.make_pipeline()
    walks = [("straight", {"distance_m": 100.0})] + [
        ("rectangle", {"width_m": 105.0, "height_m": 68.0, "direction": d}) for d in ("ccw", "cw")
    ]
    print(f"pipeline: {pipe!r}, {args.rate_hz:g} Hz")
    print("walk                seed  foot   distance_m  ate_2d_m  ate_%   end_err_m  end_%")
    for scenario, opts in walks:
        for seed in args.seeds:
            rec = footnav.simulate(scenario, seed=seed, rate_hz=args.rate_hz, **opts)
            res = pipe.run(rec.left, rec.right)
            for foot, traj, truth in (("left", res.left, rec.truth_left), ("right", res.right, rec.truth_right)):
                dist = metrics.travelled_distance(truth.position, dims=2)
                ate = metrics.ate_rmse(traj.position, truth.position, dims=2)
                aligned = metrics.rigid_align(traj.position, truth.position, dims=2).aligned
                end = float(((aligned[-1, :2] - truth.position[-1, :2]) ** 2).sum() ** 0.5)
                name = scenario + ("" if scenario == "straight" else "-" + opts["direction"])
                print(
                    f"{name:18s}  {seed:4d}  {foot:5s}  {dist:10.1f}  {ate:8.3f}  {100 * ate / dist:5.2f}  "
                    f"{end:9.3f}  {100 * end / dist:5.2f}"
                )


if __name__ == "__main__":
    main()
