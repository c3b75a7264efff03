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

``--gyro-shift 0,0.5,1`` runs each recording once per shift, with the gyro resampled at
``t + shift / rate_hz`` (linear interpolation; a positive shift takes each gyro sample from
later), and adds the swing's closing speed: integrated freely from the smoothed state at the
last updated sample of one stance to the first of the next, the median speed (m/s) the foot
arrives with. A time offset between the two sensors would show as a shift that both closes the
swings best and removes the shortfall (docs/heading.md: it does not).
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import warnings
from typing import Any

import numpy as np
from scipy.optimize import least_squares

import footnav
from footnav.analysis.evaluation import trajectory_at
from footnav.analysis.metrics import rigid_align
from footnav.core.types import FootTrajectory, ImuData, StanceResult
from footnav.data.datasets import dataset_names, load_dataset
from footnav.nav.heading import turn_increments
from footnav.nav.mechanization import strapdown

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


def shift_gyro(imu: ImuData, samples: float) -> ImuData:
    """``imu`` with its gyro resampled at ``t + samples / rate_hz`` (held at the ends)."""
    if samples == 0:
        return imu
    at = imu.t + samples / imu.rate_hz
    gyr = np.column_stack([np.interp(at, imu.t, imu.gyr[:, i]) for i in range(3)])
    return dataclasses.replace(imu, gyr=gyr)


def closing_speed(estimator: Any, imu: ImuData, stance: StanceResult, traj: FootTrajectory) -> float:
    """Median speed (m/s) a freely integrated swing arrives at the next stance's update with,
    from the run's own stances and trajectory (the updated rows are the estimator's)."""
    bias = np.asarray(traj.meta.get("gyro_bias_radps", np.zeros(3)))
    rows = estimator._zupt(imu, stance)
    speeds = []
    for (a0, b0), (a1, b1) in zip(stance.intervals[:-1], stance.intervals[1:]):
        u0, u1 = np.flatnonzero(rows[a0:b0]), np.flatnonzero(rows[a1:b1])
        if len(u0) and len(u1):
            e, s = a0 + u0[-1], a1 + u1[0]
            _, v, _ = strapdown(imu.slice(e, s + 1), traj.quaternion[e], traj.velocity[e], traj.position[e], bias)
            speeds.append(float(np.linalg.norm(v[-1])))
    return float(np.median(speeds)) if speeds else float("nan")


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--prefix", default="gaitdriven_,pyshoe_,azure_fgo,gaitmap")
    ap.add_argument("--pipeline", default="{}", help="make_pipeline keywords as JSON")
    ap.add_argument("--gyro-shift", default="", help="comma-separated gyro shifts (samples)")
    args = ap.parse_args()
    shifts = [float(x) for x in args.gyro_shift.split(",")] if args.gyro_shift else []
    warnings.simplefilter("ignore")
    pipe = footnav.make_pipeline(**json.loads(args.pipeline))
    labels = ("rigid", "scale", "drift", "drift + scale")
    extra = " shift (samples) | closing speed (m/s) |" if shifts else ""
    print("| recording | T (s) | " + " | ".join(labels) + " | omega (deg/min) | s - 1 (%) |" + extra)
    print("|---|---|" + "---|" * (len(labels) + 2 + 2 * bool(shifts)))
    for name in [n for n in dataset_names() if n.startswith(tuple(args.prefix.split(",")))]:
        rec = load_dataset(name)
        truth = rec.truth_left
        if truth is None or len(truth.t) < 3:
            continue
        for shift in shifts or [0.0]:
            imu = shift_gyro(rec.left, shift)
            result = pipe.run(imu)
            est, inside = trajectory_at(result.left, truth.t)
            t, ref = truth.t[inside], truth.position[inside][:, :2]
            pick = np.linspace(0, len(t) - 1, min(len(t), MAX_POINTS)).round().astype(int)
            fits = decompose(est[pick, :2], ref[pick], t[pick])
            both = fits["drift + scale"]
            row = (
                f" {shift:+.2f} | {closing_speed(pipe.estimator, imu, result.stance_left, result.left):.3f} |"
                if shifts
                else ""
            )
            print(
                f"| {name} | {t[-1] - t[0]:.0f} | "
                + " | ".join(f"{fits[k][0]:.3f}" for k in labels)
                + f" | {both[1]:+.1f} | {both[2]:+.2f} |"
                + row
            )


if __name__ == "__main__":
    main()
