"""Particle-filter fusion cost: the pipeline with ParticleFusion(n_particles=1000) against independent feet.

Run:  python benchmarks/bench_particle.py [--minutes 10] [--repeat 5]
      python benchmarks/bench_particle.py --accuracy [--seeds 5]     # accuracy instead of time
      python benchmarks/bench_particle.py --square [--seeds 5]       # paper vs footnav mode, cross-track
      python benchmarks/bench_particle.py --square --mirrored-yaw-rate 0 2e-4 5e-4 1e-3  # the paper's drift
      python benchmarks/bench_particle.py --paper-speed [--repeat 5]  # paper mode's fusion alone, a 4-min walk

The issue's target: the particle filter with 1000 particles adds < 20 % to the pipeline runtime.
Prints the machine, then the warm best-of-``repeat`` runtime of the whole pipeline (threshold
detector, 9-state EKF with whole-walk smoothing, fusion) on a simulated two-foot walk of
``--minutes`` (two laps of a square), for:

* ``independent``: each foot alone (the baseline of the target);
* ``joint filter, no PF``: both feet in the joint filter the particle fusion runs in
  (:func:`footnav.fusion.joint.start_joint` / ``finish_joint``), no coupling: what any coupled
  fusion costs before its own work;
* ``particle`` with 2, 100 (seed 004) and 1000 particles: 2 particles is the cost of the PF
  machinery (a stop, an EKF update and a smoother checkpoint per stance end) without particles.

and the increase of the 1000-particle pipeline over each of the others.

With ``--accuracy``: the final foot separation E_s (horizontal; the true one is 0.2 m) and the
final position error E_p of each foot against independent feet on the walks of the acceptance
test (seeds 0 .. ``--seeds``-1, gyro bias walk 5e-5 rad/s^2/sqrt(Hz)), and the 2-D ATE per foot
and E_s on the shared real two-foot recordings.

With ``--square``: the square of Lee, Cho & Park (2022), Sec. 4 (93 m round, ``--laps`` laps,
``--turn`` ccw/cw), the paper's MTw noise; per fusion the RMS and final cross-track error per foot,
E_s and E_p, mean +- std over seeds, for each ``--mirrored-yaw-rate`` (the simulator's
``mirrored_yaw_rate_radps``, the paper's symmetric drift of Sec. 2.1; negative values as
``--mirrored-yaw-rate=-1e-3``). The figures are in :mod:`footnav.fusion.particle`'s docstring.
"""

from __future__ import annotations

import argparse
import os
import platform
import time
import warnings

import numpy as np
from _common import WALK_SPEED_MPS, best_of, cpu_name  # benchmarks/_common.py (scripts run from benchmarks/)

import footnav
from footnav.core.component import Fusion
from footnav.fusion.independent import IndependentFusion
from footnav.fusion.joint import check_two_feet, finish_joint, start_joint
from footnav.fusion.particle import ParticleFusion


class _JointOnly(Fusion):
    """Both feet in the joint filter, nothing else (a baseline, not a method)."""

    name = "joint-only"
    needs_two_feet = True

    def __init__(self) -> None:
        pass

    def fuse(self, estimator, left, stance_left, right=None, stance_right=None):
        check_two_feet(self, estimator, right, stance_right)
        filt = start_joint(estimator, left, stance_left, right, stance_right, 0.2)
        return finish_joint(estimator, filt, stance_left, stance_right, {"fusion": self.describe()})


def accuracy(n_seeds: int) -> None:
    from footnav.analysis.evaluation import trajectory_at
    from footnav.analysis.metrics import ate_rmse
    from footnav.data.datasets import load_dataset
    from footnav.estimators.ekf import EkfEstimator

    det = footnav.make_detector("threshold")
    fusions = {"independent": IndependentFusion(), "particle": ParticleFusion()}

    def fuse(fusion, rec):
        return fusion.fuse(EkfEstimator(), rec.left, det.detect(rec.left), rec.right, det.detect(rec.right))

    walks = [
        ("straight 100 m", "straight", {"distance_m": 100.0}),
        ("rectangle 105 x 68 m cw", "rectangle", {"width_m": 105.0, "height_m": 68.0, "direction": "cw"}),
        ("rectangle 105 x 68 m ccw", "rectangle", {"width_m": 105.0, "height_m": 68.0, "direction": "ccw"}),
    ]
    print(f"simulator, seeds 0..{n_seeds - 1}, gyro bias walk 5e-5 rad/s^2/sqrt(Hz); means over seeds (m)")
    for label, scenario, opts in walks:
        rows = {name: [] for name in fusions}
        for seed in range(n_seeds):
            rec = footnav.simulate(scenario, seed=seed, gyr_bias_walk_radps2_sqrthz=5e-5, **opts)
            for name, fusion in fusions.items():
                res = fuse(fusion, rec)
                es = np.linalg.norm(res.left.position[-1, :2] - res.right.position[-1, :2])
                pairs = ((res.left, rec.truth_left), (res.right, rec.truth_right))
                ep = [np.linalg.norm(tr.position[-1, :2] - t.position[-1, :2]) for tr, t in pairs]
                rows[name].append([es, abs(es - 0.2), *ep])
        for name, r in rows.items():
            r = np.mean(r, axis=0)
            print(
                f"  {label:26s} {name:12s} E_s {r[0]:.3f}  |E_s - 0.2| {r[1]:.3f}  "
                f"E_p {r[2]:.3f} / {r[3]:.3f} (mean {0.5 * (r[2] + r[3]):.3f})"
            )
    print("real recordings: 2-D ATE left / right (m), E_s horizontal (m)")
    for name in ("azure_fgo", "gaitmap"):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # the readers' data-quality notes
            rec = load_dataset(name)
        truth_es = np.linalg.norm(rec.truth_left.position[-1, :2] - rec.truth_right.position[-1, :2])
        for label, fusion in fusions.items():
            res = fuse(fusion, rec)
            ate = []
            for traj, truth in ((res.left, rec.truth_left), (res.right, rec.truth_right)):
                est, inside = trajectory_at(traj, truth.t)
                ate.append(ate_rmse(est, truth.position[inside], dims=2))
            es = np.linalg.norm(res.left.position[-1, :2] - res.right.position[-1, :2])
            print(f"  {name:10s} {label:12s} ATE {ate[0]:.3f} / {ate[1]:.3f}  E_s {es:.3f} (truth {truth_es:.3f})")


def square(n_seeds: int, laps: int = 3, mirrored: tuple[float, ...] = (0.0,), turn: str = "ccw") -> None:
    """Cross-track error on the square of Lee, Cho & Park (2022), Sec. 4: paper mode, footnav mode,
    independent feet (smoothed and forward-only), the range constraint and the step vector, for
    each value of the simulator's ``mirrored_yaw_rate_radps`` (the paper's symmetric drift,
    Sec. 2.1): RMS and final cross-track error per foot, final separation E_s and position error
    E_p (Zhao et al. 2019), mean +- std over seeds."""
    import sys

    sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "tests", "fusion"))
    from test_particle_paper import cross_track
    from test_particle_paper import square as square_walk

    from footnav.estimators.ekf import EkfEstimator

    det = footnav.make_detector("threshold")
    runs = {
        "independent": (IndependentFusion(), EkfEstimator()),
        "independent, forward only": (IndependentFusion(), EkfEstimator(smoother="none")),
        "range": (footnav.make_fusion("range"), EkfEstimator()),
        "step-vector": (footnav.make_fusion("step-vector"), EkfEstimator()),
        "particle, mode=paper": (ParticleFusion(mode="paper"), EkfEstimator()),
        "particle, mode=footnav": (ParticleFusion(mode="footnav"), EkfEstimator()),
    }
    sign = 1.0 if turn == "ccw" else -1.0
    print(
        f"square 93 m round x {laps} laps ({turn}), MTw noise, seeds 0..{n_seeds - 1}: per foot, mean +- std "
        "over seeds (m); E_s the final foot separation (truth 0.2), E_p the final position error"
    )
    for b in mirrored:
        rows: dict[str, list] = {name: [] for name in runs}
        for seed in range(n_seeds):
            rec = square_walk(seed, laps=laps, mirrored_yaw_rate_radps=b, turn_sign=sign)
            sl, sr = det.detect(rec.left), det.detect(rec.right)
            for name, (fusion, est) in runs.items():
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    res = fusion.fuse(est, rec.left, sl, rec.right, sr)
                ct = np.mean([cross_track(res.left, rec.truth_left), cross_track(res.right, rec.truth_right)], axis=0)
                es = np.linalg.norm(res.left.position[-1, :2] - res.right.position[-1, :2])
                ep = np.mean([final_error(res.left, rec.truth_left), final_error(res.right, rec.truth_right)])
                rows[name].append([*ct, es, ep])
        print(f"mirrored_yaw_rate_radps = {b:g}")
        for name, v in rows.items():
            v = np.array(v)
            print(
                f"  {name:26s} RMS {v[:, 0].mean():.3f} +- {v[:, 0].std():.3f}   final {v[:, 1].mean():.3f} +- "
                f"{v[:, 1].std():.3f}   E_s {v[:, 2].mean():.3f}   E_p {v[:, 3].mean():.3f} +- {v[:, 3].std():.3f}"
            )


def final_error(traj, truth) -> float:
    """Horizontal error of the foot's last sample, both walks moved to start at the foot's first
    footprint (as :func:`cross_track`), m."""
    k0 = (traj.steps[0, 0] + traj.steps[0, 1]) // 2
    e = (traj.position[-1, :2] - traj.position[k0, :2]) - (truth.position[-1, :2] - truth.position[k0, :2])
    return float(np.linalg.norm(e))


def paper_speed(repeat: int) -> None:
    """Paper mode's fusion (Lee, Cho & Park 2022) alone, warm, on a 300 m straight walk: the
    timing tests/fusion/test_particle_paper.py used to assert (under 5 s)."""
    from footnav.estimators.ekf import EkfEstimator

    rec = footnav.simulate("straight", seed=0, distance_m=300.0)
    det = footnav.make_detector("threshold")
    stances = det.detect(rec.left), det.detect(rec.right)

    def fuse():
        return ParticleFusion(mode="paper").fuse(EkfEstimator(), rec.left, stances[0], rec.right, stances[1])

    fuse()  # compile
    best, _ = best_of(fuse, repeat)
    print(
        f"machine: {cpu_name()}, {os.cpu_count()} cores, Python {platform.python_version()}, "
        f"footnav {footnav.__version__}"
    )
    print(f"paper mode, {rec.left.duration_s / 60:.1f} min two-foot walk: {best:.2f} s (best of {repeat})")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--minutes", type=float, default=10.0)
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--accuracy", action="store_true", help="E_s and E_p instead of the runtime")
    ap.add_argument("--seeds", type=int, default=5, help="simulator seeds for --accuracy")
    ap.add_argument("--square", action="store_true", help="cross-track error on the paper's square (--seeds)")
    ap.add_argument(
        "--mirrored-yaw-rate",
        type=float,
        nargs="+",
        default=[0.0],
        metavar="RADPS",
        help="--square: the simulator's mirrored_yaw_rate_radps values to run (the paper's "
        "symmetric drift, Lee, Cho & Park 2022, Sec. 2.1), e.g. 0 2e-4 5e-4 1e-3",
    )
    ap.add_argument("--laps", type=int, default=3, help="--square: laps of the square")
    ap.add_argument("--turn", choices=("ccw", "cw"), default="ccw", help="--square: left (ccw) or right turns")
    ap.add_argument(
        "--paper-speed",
        action="store_true",
        help="the paper mode's fusion alone on a ~4-minute straight walk (warm best of --repeat)",
    )
    args = ap.parse_args()
    if args.paper_speed:
        paper_speed(args.repeat)
        return
    if args.square:
        square(args.seeds, args.laps, tuple(args.mirrored_yaw_rate), args.turn)
        return
    if args.accuracy:
        accuracy(args.seeds)
        return
    speed_mps = WALK_SPEED_MPS
    side_m = args.minutes * 60 * speed_mps / 8  # two laps of a square
    rec = footnav.simulate("path", seed=11, segments=[(side_m, 90.0)] * 8, gyr_bias_walk_radps2_sqrthz=5e-5)
    runs = {
        "independent": IndependentFusion(),
        "joint filter, no PF": _JointOnly(),
        "particle, 2 particles": ParticleFusion(n_particles=2),
        "particle, 100 particles": ParticleFusion(n_particles=100),
        "particle, 1000 particles": ParticleFusion(n_particles=1000),
    }
    print(
        f"machine: {platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}, "
        f"footnav {footnav.__version__}"
    )
    print(
        f"walk: {rec.left.duration_s / 60:.1f} min, two feet at {rec.left.rate_hz:.0f} Hz, "
        f"{rec.left.n_samples} samples per foot"
    )
    times = {}
    for label, fusion in runs.items():
        pipe = footnav.make_pipeline("threshold", "ekf", fusion)
        res = pipe.run(rec)  # warm: compile or load numba's cache
        if label == "independent":
            print(
                f"stances: {res.stance_left.n_stances} left, {res.stance_right.n_stances} right "
                "(a PF update at the end of each)"
            )
        best = []
        for _ in range(args.repeat):
            t0 = time.perf_counter()
            pipe.run(rec)
            best.append(time.perf_counter() - t0)
        times[label] = min(best)
        print(f"{label:26s} {times[label]:.3f} s")
    top = times["particle, 1000 particles"]
    for base in ("independent", "joint filter, no PF", "particle, 2 particles"):
        print(f"1000 particles vs {base:22s} +{100 * (top / times[base] - 1):.0f} %")


if __name__ == "__main__":
    main()
