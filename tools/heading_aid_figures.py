r"""docs/heading.md's figures: every shared recording with a truth and the simulator's 10-minute
walk, the default pipeline against the same with a heading aid (an aid that reads the
magnetometer: the recordings that have one, and simulator walks with hard iron and steel).

Usage::

    FOOTNAV_DATA=../shared/data PYTHONPATH=$PWD python tools/heading_aid_figures.py \
        [--aid dominant-directions] [--seeds 3]

Per recording: the figure of docs/accuracy.md (footprint RMSE for the gait-driven walks, 2-D ATE,
the x-io loops' 2-D end-to-start distance), both feet, without / with the aid, and whether the
aid changed the walk (``applied``, the correction at the end, deg). Simulator: laps of a
150 x 60 m rectangle (benchmarks/bench_consistency.py's walk) for about 10 minutes, 2-D ATE (m).
"""

from __future__ import annotations

import argparse
import warnings

import numpy as np

import footnav
from footnav.data.datasets import dataset_names, load_dataset


def figure(report, rec):
    for name in ("footprint_rmse", "loop_closure_2d", "ate_2d"):
        vals = []
        for foot in ("left", "right"):
            try:
                vals.append(report.value(name, foot))
            except (KeyError, LookupError, ValueError):
                pass
        if vals:
            return name, vals
    return None, []


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--aid", default="dominant-directions")
    ap.add_argument("--seeds", type=int, default=3)
    args = ap.parse_args()
    warnings.simplefilter("ignore")
    needs_mag = footnav.make_heading_aid(args.aid).needs_magnetometer
    names = [n for n in dataset_names() if not n.startswith("ipol_")]
    ratios = []
    for name in names:
        rec = load_dataset(name)
        if rec.truth_left is None or (needs_mag and rec.left.mag is None):
            continue
        base = footnav.evaluate(footnav.make_pipeline(), rec)
        aided_pipe = footnav.make_pipeline(heading_aid=args.aid)
        aided = footnav.evaluate(aided_pipe, rec)
        metric, a = figure(base, rec)
        _, b = figure(aided, rec)
        res = aided_pipe.run(rec.left, rec.right)
        info = res.left.meta.get("heading_aid", {})
        ratios += [y / x for x, y in zip(a, b) if x > 0]
        print(
            f"{name:28s} {metric:16s} {' / '.join(f'{x:.3f}' for x in a)} -> {' / '.join(f'{x:.3f}' for x in b)}"
            f"  applied {info.get('applied')} end {info.get('correction_end_deg', 0.0):+.2f} deg"
        )
    if ratios:
        print(f"worst ratio aided / default: {max(ratios):.3f}")
    if needs_mag:
        ipol_figures(args.aid)
    lap = [(150.0, 90.0), (60.0, 90.0)] * 2
    # the magnetometer changes no other signal: the figures of aids that do not read it are the same
    steel = {"mag_disturbances": [(75.0, 0.0, 20.0, 15.0, -10.0, 5.0), (150.0, 60.0, 30.0, 0.0, 20.0, -10.0)]}
    sensors = [({}, "default sensor"), ({"gyr_bias_walk_radps2_sqrthz": 1e-4}, "gyro bias walk 1e-4")]
    if needs_mag:
        sensors += [
            ({"gyr_bias_walk_radps2_sqrthz": 1e-4, "mag_hard_iron_ut": 5.0}, "gyro bias walk 1e-4, hard iron 5 uT"),
            ({"gyr_bias_walk_radps2_sqrthz": 1e-4, **steel}, "gyro bias walk 1e-4, steel on 24 % of the walk"),
        ]
    for gyro, label in sensors:
        rows = []
        for seed in range(args.seeds):
            rec = footnav.simulate("path", seed=seed, segments=lap * 2, magnetometer=True, **gyro)
            vals = [
                footnav.evaluate(footnav.make_pipeline(heading_aid=aid), rec).value("ate_2d", "left")
                for aid in (None, args.aid)
            ]
            rows.append(vals)
        rows = np.array(rows)
        print(
            f"simulator 2 laps of 150 x 60 m ({rec.left.duration_s / 60:.1f} min), {label}: "
            f"left ATE 2-D mean {rows[:, 0].mean():.2f} -> {rows[:, 1].mean():.2f} m, "
            f"worst {rows[:, 0].max():.2f} -> {rows[:, 1].max():.2f} m ({args.seeds} seeds)"
        )


def ipol_figures(aid: str) -> None:
    """The shared recordings with a magnetometer (ipol: 10 m out, U-turn, 10 m back; no position
    truth): on how many feet the aid applied, and the share of stances its gates passed."""
    feet = applied = 0
    shares = []
    for name in (n for n in dataset_names() if n.startswith("ipol_")):
        rec = load_dataset(name)
        res = footnav.make_pipeline(heading_aid=aid).run(rec)
        for traj in (res.left, res.right):
            info = traj.meta["heading_aid"]
            feet += 1
            applied += bool(info["applied"])
            shares.append(info["accepted"] / max(info["stances"], 1))
    if feet:
        print(
            f"ipol: applied on {applied} of {feet} feet; stances passing the gates: median {np.median(shares):.1%}, "
            f"most {max(shares):.1%}"
        )


if __name__ == "__main__":
    main()
