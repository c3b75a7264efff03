"""Cost of the height model (issue 31): the default pipeline with vertical="floors" against
vertical="free", and hold_floors alone.

    python benchmarks/bench_vertical.py [--minutes 60] [--rounds 3]

Both pipelines run in this one process on the same simulated one-foot walk, alternated
``--rounds`` times (best of 2 each); us/sample per foot.
"""

from __future__ import annotations

import argparse
import warnings

from _common import best_of, cpu_name, straight_walk  # benchmarks/_common.py (scripts run from benchmarks/)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--minutes", type=float, default=60.0)
    ap.add_argument("--rounds", type=int, default=3)
    args = ap.parse_args()
    warnings.simplefilter("ignore")

    import footnav
    from footnav.nav.floors import hold_floors

    imu = straight_walk(args.minutes, 100.0).left
    n = imu.n_samples
    pipes = {v: footnav.make_pipeline(estimator_params={"vertical": v}) for v in ("free", "floors")}
    for p in pipes.values():
        p.run(imu)  # compile / warm
    best = {v: float("inf") for v in pipes}
    for _ in range(args.rounds):
        for v, p in pipes.items():
            t, _ = best_of(lambda p=p: p.run(imu), 2)
            best[v] = min(best[v], t)
    traj = pipes["free"].run(imu).left
    t_hold, _ = best_of(lambda: hold_floors(traj), 3)
    print(f"machine: {cpu_name()}; {n} samples ({args.minutes:g} min at 100 Hz), {len(traj.steps)} stances")
    for v, t in best.items():
        print(f"default pipeline, vertical={v!r}: {t / n * 1e6:.3f} us/sample")
    print(f"hold_floors alone: {t_hold / n * 1e6:.4f} us/sample; ratio floors / free: {best['floors'] / best['free']:.3f}")


if __name__ == "__main__":
    main()
