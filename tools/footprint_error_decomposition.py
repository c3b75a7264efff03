r"""How much of a walk's horizontal error is heading drift and how much is length scale.

Usage::

    FOOTNAV_DATA=../shared/data PYTHONPATH=$PWD python tools/footprint_error_decomposition.py \
        [--prefix gaitdriven_,pyshoe_] [--pipeline '{"heading_aid": "dominant-directions"}']

For each shared recording with a horizontal truth (the gait-driven footprints, VICON, motion
capture), the left foot's estimate at the truth's times (at most 400 of them, evenly spread) is
fitted to the truth by four models, each a transform of the estimate's increments
``d_k = p_{k+1} - p_k``:

* ``rigid``: one heading and offset (the metric of docs/accuracy.md);
* ``scale``: that and one length scale ``s`` (Umeyama 1991's similarity, ``rigid_align``);
* ``drift``: a heading that grows linearly in time, ``R(theta_0 + omega t) d_k`` (a constant
  yaw-rate error, the gyro bias about the vertical);
* ``drift + scale``: both.

It prints the RMSE (m) left by each, the fitted ``omega`` (deg/min) and ``s - 1`` (%; positive:
the estimate is shorter than the truth). A model's RMSE is what a perfect correction of the
errors it names would leave; the gap between two rows is what that error costs.
"""

from __future__ import annotations

import argparse
import json
import warnings

import numpy as np
from scipy.optimize import least_squares

import footnav
from footnav.analysis.evaluation import trajectory_at
from footnav.analysis.metrics import rigid_align
from footnav.data.datasets import dataset_names, load_dataset
from footnav.nav.heading import turn_increments

MAX_POINTS = 400


def _residual(x, est, ref, t, drift, scale):
    return (_turned(x, est, t, drift, scale) - ref).ravel()


def _turned(x, est, t, drift, scale):
    """The estimate's increments scaled, turned by theta_0 (+ omega t) and summed from (tx, ty)."""
    theta0, omega, log_s, tx, ty = x
    angle = theta0 + (omega if drift else 0.0) * (t - t[0])
    flat = np.column_stack([est * (np.exp(log_s) if scale else 1.0), np.zeros(len(est))])
    turned = turn_increments(flat, -angle)[:, :2]
    return turned - turned[0] + [tx, ty]


def decompose(est: np.ndarray, ref: np.ndarray, t: np.ndarray) -> dict[str, tuple[float, float, float]]:
    """RMSE (m), omega (deg/min) and s - 1 (%) of each model, started from the similarity fit."""
    sim = rigid_align(est, ref, dims=2, with_scale=True)
    theta = float(np.arctan2(sim.rotation[1, 0], sim.rotation[0, 0]))
    out = {}
    for label, drift, scale in (("rigid", 0, 0), ("scale", 0, 1), ("drift", 1, 0), ("drift + scale", 1, 1)):
        x0 = [theta, 0.0, float(np.log(sim.scale)) if scale else 0.0, *sim.aligned[0, :2]]
        fit = least_squares(_residual, x0, args=(est, ref, t, drift, scale))
        rmse = float(np.sqrt(np.mean(np.sum(fit.fun.reshape(-1, 2) ** 2, axis=1))))
        out[label] = (
            rmse,
            float(np.degrees(fit.x[1]) * 60.0) if drift else 0.0,
            (np.exp(fit.x[2]) - 1) * 100 if scale else 0.0,
        )
    return out


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--prefix", default="gaitdriven_,pyshoe_,azure_fgo,gaitmap")
    ap.add_argument("--pipeline", default="{}", help="make_pipeline keywords as JSON")
    args = ap.parse_args()
    warnings.simplefilter("ignore")
    pipe = footnav.make_pipeline(**json.loads(args.pipeline))
    labels = ("rigid", "scale", "drift", "drift + scale")
    print("| recording | T (s) | " + " | ".join(labels) + " | omega (deg/min) | s - 1 (%) |")
    print("|---|---|" + "---|" * (len(labels) + 2))
    for name in [n for n in dataset_names() if n.startswith(tuple(args.prefix.split(",")))]:
        rec = load_dataset(name)
        truth = rec.truth_left
        if truth is None or len(truth.t) < 3:
            continue
        est, inside = trajectory_at(pipe.run(rec.left).left, truth.t)
        t, ref = truth.t[inside], truth.position[inside][:, :2]
        pick = np.linspace(0, len(t) - 1, min(len(t), MAX_POINTS)).round().astype(int)
        fits = decompose(est[pick, :2], ref[pick], t[pick])
        both = fits["drift + scale"]
        print(
            f"| {name} | {t[-1] - t[0]:.0f} | "
            + " | ".join(f"{fits[k][0]:.3f}" for k in labels)
            + f" | {both[1]:+.1f} | {both[2]:+.2f} |"
        )


if __name__ == "__main__":
    main()
