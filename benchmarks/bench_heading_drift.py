"""Cost of the heading-drift term in position_std (issue 14): the EKF with and without it.

    python benchmarks/bench_heading_drift.py [--minutes 60] [--repeat 3]

Both variants run in this one process on the same simulated walk and stance mask (threshold
detector), whole-walk smoother; the figure is the ratio of their best-of-N times. The term alone
(``heading_drift_cov`` on the filter's own velocity and attitude) is timed beside them.
"""

from __future__ import annotations

import argparse
import warnings

from _common import best_of, cpu_name, straight_walk  # benchmarks/_common.py (scripts run from benchmarks/)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--minutes", type=float, default=60.0)
    ap.add_argument("--rate-hz", type=float, default=100.0)
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    warnings.simplefilter("ignore")

    import footnav

    imu = straight_walk(args.minutes, args.rate_hz).left
    stance = footnav.make_detector("threshold").detect(imu)
    n = imu.n_samples
    times = {}
    for on in (False, True):
        est = footnav.make_estimator("ekf", heading_drift_in_std=on)
        est.estimate(imu, stance)  # compile / warm
        times[on], _ = best_of(lambda est=est: est.estimate(imu, stance), args.repeat)
    print(f"machine: {cpu_name()}; {n} samples ({args.minutes:g} min at {args.rate_hz:g} Hz)")
    print(f"ekf whole-walk, heading drift in std off: {times[False] / n * 1e6:.3f} us/sample")
    print(f"ekf whole-walk, heading drift in std on:  {times[True] / n * 1e6:.3f} us/sample")
    print(f"ratio on / off: {times[True] / times[False]:.3f}")
    from footnav.nav.heading_drift import heading_drift_cov

    traj = footnav.make_estimator("ekf").estimate(imu, stance)
    term, _ = best_of(
        lambda: heading_drift_cov(traj.t, traj.velocity, 0, 1e-3, 1e-5, traj.quaternion, 0.005), args.repeat
    )
    print(f"heading_drift_cov alone: {term / n * 1e9:.1f} ns/sample, {term / times[False]:.3f} of the filter's time")


if __name__ == "__main__":
    main()
