"""Cost of the height model (issue 31): the default pipeline (vertical="floors", the update on
each stance's settled part) against vertical="free" and against zupt_edges="detected", and
hold_floors and settled_mask alone.

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
    from footnav.nav.stance_edges import settled_mask

    imu = straight_walk(args.minutes, 100.0).left
    n = imu.n_samples
    variants = {
        "vertical='free'": {"vertical": "free"},
        "default": {},
        "zupt_edges='detected'": {"zupt_edges": "detected"},
    }
    pipes = {v: footnav.make_pipeline(estimator_params=params) for v, params in variants.items()}
    for p in pipes.values():
        p.run(imu)  # compile / warm
    best = {v: float("inf") for v in pipes}
    for _ in range(args.rounds):
        for v, p in pipes.items():
            t, _ = best_of(lambda p=p: p.run(imu), 2)
            best[v] = min(best[v], t)
    traj = pipes["vertical='free'"].run(imu).left
    t_hold, _ = best_of(lambda: hold_floors(traj), 3)
    later = traj.steps[1:]
    t_edges, _ = best_of(lambda: settled_mask(imu.t, imu.acc, later, 0.01, 0.25), 3)
    print(f"machine: {cpu_name()}; {n} samples ({args.minutes:g} min at 100 Hz), {len(traj.steps)} stances")
    for v, t in best.items():
        print(f"default pipeline, {v}: {t / n * 1e6:.3f} us/sample")
    print(f"hold_floors alone: {t_hold / n * 1e6:.4f} us/sample; settled_mask alone: {t_edges / n * 1e6:.4f} us/sample")
    free, detected = best["vertical='free'"], best["zupt_edges='detected'"]
    print(
        f"ratio default / free: {best['default'] / free:.3f}; "
        f"default / detected edges: {best['default'] / detected:.3f}"
    )


if __name__ == "__main__":
    main()
