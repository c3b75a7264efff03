"""Regenerate docs/accuracy.md: every estimator and fusion on the shared recordings and the simulator.

Run:  python docs/make_accuracy.py [--data-dir ../shared/data] [--seeds 5] [--gaitmap-python PY]

Every number in accuracy.md comes from footnav.evaluate on the shared recordings; the reference
figures are those of shared/data/README.md (gaitmap 2.6 RtsKalman with defaults, each foot alone,
and the x-io publisher's own method).
"""

from __future__ import annotations

import argparse
import platform
import warnings
from pathlib import Path

import footnav
from footnav.analysis import metrics
from footnav.analysis.evaluation import evaluate
from footnav.data.datasets import data_dir, dataset_names, load_dataset

REFERENCE = {
    ("azure_fgo", "ate_2d", "left"): "0.36 (gaitmap RtsKalman)",
    ("azure_fgo", "ate_2d", "right"): "0.76 (gaitmap RtsKalman)",
    ("xio_short", "loop_closure_2d", "left"): "1.09 (gaitmap RtsKalman); 0.082 (publisher)",
    ("xio_long", "loop_closure_2d", "left"): "1.76 (gaitmap RtsKalman); 0.421 (publisher)",
}
SHOWN = (
    "ate_2d",
    "ate_3d",
    "height_rmse",
    "loop_closure_2d",
    "loop_closure_2d_percent",
    "loop_closure_3d",
    "loop_closure_dz",
    "final_separation",
    "path_length",
    "reference_path_length",
    "stances",
    "stance_f1",
    "steps_missed",
    "steps_false",
)
#: Development sets of issue 13, summarised in their own section (one row per trial is too many).
DEV_SETS = ("ipol_", "gaitdriven_")
#: A footnav stride matches a motion-capture stride when both its ends are this close (s): a third
#: of a stride, so a neighbouring stride never matches.
STRIDE_MATCH_S = 0.4
#: Detectors compared across gaits: the default and the walking-tuned one it replaced.
GAIT_DETECTORS = ("adaptive", "threshold")


#: Per-foot estimator variants compared on every recording (name -> estimator parameters).
ESTIMATORS = {
    "ekf (9 states, forward only)": ("ekf", {"smoother": "none"}),
    "ekf (9 states, step-wise RTS)": ("ekf", {"smoother": "step"}),
    "ekf (9 states, whole-walk RTS; default)": ("ekf", {}),
    "ekf (15 states + ZARU, whole-walk RTS)": ("ekf", {"bias_states": True, "zaru_std_radps": 0.005}),
    "ekf (closed loop: start = end)": ("ekf", {"closed_loop": True}),
    "madgwick (+ 9-state KF)": ("madgwick", {}),
}
#: Recordings whose walk returns to its start (the closed-loop variant applies only to them).
LOOPS = ("xio_short", "xio_long")
#: Simulator walks of the fusion table and the gyro that makes the feet drift apart.
SIM_WALKS = [
    ("straight", {"distance_m": 100.0}, "straight 100 m"),
    ("rectangle", {"width_m": 105.0, "height_m": 68.0, "direction": "cw"}, "rectangle 105 x 68 m CW"),
    ("rectangle", {"width_m": 105.0, "height_m": 68.0, "direction": "ccw"}, "rectangle 105 x 68 m CCW"),
]
DRIFTY_GYRO = {"gyr_bias_walk_radps2_sqrthz": 1e-4}

#: gaitmap 2.6.0's own stride lengths (m) on the gaitmap example's mocap strides (its
#: ``stride_events_sample.csv``, ``min_vel`` to ``min_vel``, in file order), from the IMU data
#: (``imu_sample.csv``) through ``StrideLevelTrajectory`` and ``SpatialParameterCalculation``:
#: "rts" with ``trajectory_method=RtsKalman()``, "default" with gaitmap's defaults (gyro
#: integration + forward-backward integration, Rampp/Kanzler). gaitmap is not a footnav dependency:
#: re-measure with ``--gaitmap-python PY`` (PY = a Python with ``pip install gaitmap==2.6.0``),
#: which runs GAITMAP_STRIDE_SCRIPT with it.
GAITMAP_STRIDE_LENGTH_M = {
    "left": {
        "rts": [
            1.4288,
            1.3667,
            1.3578,
            1.4722,
            1.4134,
            1.4527,
            1.6085,
            1.4408,
            1.4266,
            1.3962,
            1.3437,
            1.4596,
            1.4463,
            0.2985,
            1.3227,
            1.3826,
            1.3826,
            1.5127,
            1.5358,
            1.5571,
            1.3911,
            1.3978,
            1.4595,
            1.4287,
            1.4590,
            1.4589,
            1.3615,
            1.1816,
        ],
        "default": [
            1.4311,
            1.3467,
            1.3451,
            1.4463,
            1.4016,
            1.4277,
            1.3547,
            1.4503,
            1.4055,
            1.2631,
            1.2999,
            1.1792,
            1.1929,
            0.2187,
            1.2945,
            1.4577,
            1.3535,
            1.3557,
            1.3545,
            1.2751,
            1.3950,
            1.4389,
            1.2041,
            1.2901,
            1.2533,
            1.2526,
            1.3245,
            1.1755,
        ],
    },
    "right": {
        "rts": [
            1.4549,
            1.3628,
            1.2973,
            1.4006,
            1.4063,
            1.5179,
            1.4833,
            1.5446,
            1.4674,
            1.4420,
            1.2302,
            1.3669,
            1.4000,
            1.1715,
            0.6595,
            1.3983,
            1.3199,
            1.4697,
            1.4733,
            1.4302,
            1.3544,
            1.3714,
            1.3361,
            1.2922,
            1.3139,
            1.2930,
            1.4070,
            1.2938,
            1.3161,
        ],
        "default": [
            1.4636,
            1.3369,
            1.2434,
            1.3848,
            1.3946,
            1.5353,
            1.4938,
            1.3313,
            1.4811,
            1.4413,
            1.1753,
            1.3436,
            1.2007,
            1.1565,
            0.6756,
            1.3774,
            1.2932,
            1.4628,
            1.4675,
            1.5021,
            1.3265,
            1.3559,
            1.3150,
            1.2800,
            1.3111,
            1.2638,
            1.4093,
            1.2770,
            1.3146,
        ],
    },
}
GAITMAP_STRIDE_SCRIPT = """
import json, sys, warnings
import pandas as pd
from gaitmap.parameters import SpatialParameterCalculation
from gaitmap.trajectory_reconstruction import RtsKalman, StrideLevelTrajectory
warnings.simplefilter("ignore")
d, fs = sys.argv[1], 204.8
imu = pd.read_csv(f"{d}/imu_sample.csv", header=[0, 1], index_col=0)
ev = pd.read_csv(f"{d}/stride_events_sample.csv", header=0)
ev["sensor"] = ev["foot"] + "_sensor"
ev = ev.set_index("sensor").drop("foot", axis=1)
events = {k: v.reset_index(drop=True) for k, v in ev.groupby(level=0)}
out = {}
for name, algo in (("rts", StrideLevelTrajectory(trajectory_method=RtsKalman())), ("default", StrideLevelTrajectory())):
    tr = algo.estimate(imu, events, sampling_rate_hz=fs)
    par = SpatialParameterCalculation().calculate(
        stride_event_list=events, positions=tr.position_, orientations=tr.orientation_, sampling_rate_hz=fs
    ).parameters_
    for s in events:
        out.setdefault(s[: -len("_sensor")], {})[name] = par[s]["stride_length"].round(4).tolist()
print(json.dumps(out))
"""


def _fmt(x: float | None) -> str:
    return "" if x is None else f"{x:.3f}"


def _value(report, name, foot):
    try:
        return report.value(name, foot)
    except (KeyError, LookupError, ValueError):
        return None


def estimator_section(root, names) -> list[str]:
    """Each foot alone through every estimator variant, on every recording with truth."""
    available = footnav.list_components()["estimator"]
    rows = [
        "## Estimators, each foot alone",
        "",
        "Detector `adaptive` (defaults), fusion `independent`. 2-D ATE (m) per foot; for the "
        "x-io loops the end-to-start distance (m) instead. Reference figures as above.",
        "",
        "| recording | " + " | ".join(ESTIMATORS) + " | reference |",
        "|---|" + "---|" * (len(ESTIMATORS) + 1),
    ]
    for name in names:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            rec = load_dataset(name, root)
            cells = []
            for _label, (est, params) in ESTIMATORS.items():
                if est not in available or (params.get("closed_loop") and name not in LOOPS):
                    cells.append("")
                    continue
                report = evaluate(footnav.make_pipeline("adaptive", est, "independent", estimator_params=params), rec)
                metric = "loop_closure_2d" if name in LOOPS else "ate_2d"
                feet = ["left"] + (["right"] if rec.right is not None else [])
                cells.append(" / ".join(_fmt(_value(report, metric, f)) for f in feet))
        ref = REFERENCE.get((name, "ate_2d", "left")) or REFERENCE.get((name, "loop_closure_2d", "left")) or ""
        if (name, "ate_2d", "right") in REFERENCE:
            ref = "0.36 / 0.76 (gaitmap RtsKalman)"
        if name.startswith("pyshoe_") and "best_error" in rec.truth_left.meta:
            ref = f"{rec.truth_left.meta['best_error']:.3f} (pyshoe best detector)"
        rows.append(f"| {name} | " + " | ".join(cells) + f" | {ref} |")
    return rows + [""]


#: gaitmap's stair recordings (both feet, one staircase; no truth: the feet and the two ways must agree).
STAIRS = ("imu_sample_healthy_stair_up.csv", "imu_sample_healthy_stair_down.csv")
#: The simulator's storey: 12 stairs of 0.17 m up, a U-turn on the landing, 12 down.
SIM_STOREY = [(1.4, 0.0), ("stairs", 12, 0.17), (2.8, 180.0), ("stairs", 12, -0.17), (1.4, 0.0)]


def _pct(a: float, b: float) -> str:
    return f"{100.0 * abs(a - b) / max(abs(a), abs(b)):.1f} %"


def height_section(root, names) -> list[str]:
    """Height: the default (level strides held level) against ``vertical="free"`` on every
    recording with a height truth or a closed loop, gaitmap's stairs, the simulator's storey."""
    variants = {'default (`vertical="floors"`)': {}, '`vertical="free"`': {"vertical": "free"}}
    rows = [
        "## Height",
        "",
        "Default pipeline against the same with the EKF's `vertical='free'` (the filter's height as it is; "
        "docs/height.md says why it climbs). `height_rmse`: vertical RMSE after removing the best constant "
        "offset (m); `loop_closure_dz`: end minus start height of a closed walk (m); `ate_3d` (m). Left / right "
        "where there are two feet.",
        "",
        "| recording | metric | " + " | ".join(variants) + " |",
        "|---|---|" + "---|" * len(variants),
    ]
    for name in names:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            rec = load_dataset(name, root)
            if rec.truth_left is None:
                continue
            reports = [evaluate(footnav.make_pipeline(estimator_params=p), rec) for p in variants.values()]
        feet = ["left"] + (["right"] if rec.right is not None else [])
        for metric in ("loop_closure_dz", "height_rmse", "ate_3d"):
            cells = [" / ".join(_fmt(_value(r, metric, f)) for f in feet) for r in reports]
            if any(c.strip(" /") for c in cells):
                rows.append(f"| {name} | {metric} | " + " | ".join(cells) + " |")
    rows += [
        "",
        "gaitmap's healthy stair recordings (one staircase, both feet, 204.8 Hz; no truth): each foot's "
        "end-minus-start height (m), the floors counted, and how far the feet, and the way up and the way "
        "down, disagree.",
        "",
        "| variant | up: left / right | down: left / right | feet disagree (up / down) | up vs down (left / right) |",
        "|---|---|---|---|---|",
    ]
    gm = Path(root) / "gaitmap_example"
    if all((gm / f).is_file() for f in STAIRS):
        from footnav.data.io.gaitmap import read_gaitmap

        recs = [read_gaitmap(gm / f) for f in STAIRS]
        for label, params in variants.items():
            dz, floors = [], []
            for rec in recs:
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    res = footnav.make_pipeline(estimator_params=params).run(rec.left, rec.right)
                feet = (res.left, res.right)
                dz.append([float(tr.position[-1, 2] - tr.position[0, 2]) for tr in feet])
                floors.append([tr.meta.get("vertical", {}).get("floors_changed") for tr in feet])
            up, down = dz
            fl = "" if floors[0][0] is None else f" (floors {floors[0][0]:+d} / {floors[0][1]:+d})"
            fd = "" if floors[1][0] is None else f" (floors {floors[1][0]:+d} / {floors[1][1]:+d})"
            rows.append(
                f"| {label} | {up[0]:+.2f} / {up[1]:+.2f}{fl} | {down[0]:+.2f} / {down[1]:+.2f}{fd} | "
                f"{_pct(*up)} / {_pct(*down)} | {_pct(up[0], -down[0])} / {_pct(up[1], -down[1])} |"
            )
    rows += [
        "",
        "Simulator: a storey of 12 stairs (0.17 m rise) up, a U-turn on the landing, 12 down, seeds 0-5, "
        "both feet; end height minus start (m, mean / worst of 12) and floors counted up / down (all runs). "
        "At 100 Hz the simulated gait's jerk jumps leave about 2 mm per step low (tests/estimators/test_vertical.py).",
        "",
        "| rate | " + " | ".join(variants) + " |",
        "|---|" + "---|" * len(variants),
    ]
    for rate in (100.0, 400.0):
        cells = []
        for params in variants.values():
            ends, ups, downs = [], set(), set()
            for seed in range(6):
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    rec = footnav.simulate("path", seed=seed, rate_hz=rate, segments=SIM_STOREY)
                    res = footnav.make_pipeline(estimator_params=params).run(rec.left, rec.right)
                for tr in (res.left, res.right):
                    ends.append(float(tr.position[-1, 2] - tr.position[0, 2]))
                    v = tr.meta.get("vertical")
                    if v:
                        ups.add(v["floors_up"])
                        downs.add(v["floors_down"])
            worst = max(ends, key=abs)
            counted = f", floors {sorted(ups)} / {sorted(downs)}" if ups else ""
            cells.append(f"{sum(ends) / len(ends):+.3f} / {worst:+.3f}{counted}")
        rows.append(f"| {rate:.0f} Hz | " + " | ".join(cells) + " |")
    return rows + [""]


def fusion_section(root) -> list[str]:
    """Every two-foot fusion with two detectors on the two-foot recordings with truth."""
    fusions = footnav.list_components()["fusion"]
    rows = [
        "## Fusions on the real two-foot recordings",
        "",
        "Estimator `ekf` (defaults). 2-D ATE (m) left / right and the final foot separation E_s "
        "(m; seed 001 eq. 8). Reference: gaitmap RtsKalman 0.36 / 0.76 m on azure_fgo, each foot alone.",
        "",
        "| recording | detector | " + " | ".join(fusions) + " |",
        "|---|---|" + "---|" * len(fusions),
    ]
    for name in ("azure_fgo", "gaitmap"):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            rec = load_dataset(name, root)
            for det in ("adaptive", "dual-gait"):
                cells = []
                for fus in fusions:
                    report = evaluate(footnav.make_pipeline(det, "ekf", fus), rec)
                    cells.append(
                        f"{_fmt(_value(report, 'ate_2d', 'left'))} / {_fmt(_value(report, 'ate_2d', 'right'))}, "
                        f"E_s {_fmt(_value(report, 'final_separation', 'both'))}"
                    )
                rows.append(f"| {name} | {det} | " + " | ".join(cells) + " |")
    return rows + [""]


def simulator_section(n_seeds: int) -> list[str]:
    """Fusions on the simulator (seed 001's walks), mean over seeds."""
    import numpy as np

    fusions = footnav.list_components()["fusion"]
    rows = [
        "## Fusions on the simulator",
        "",
        f"Seed 001's walks at 100 Hz, {n_seeds} seeds each, detector `adaptive`, estimator `ekf`; a "
        f"consumer-grade gyro (bias random walk {DRIFTY_GYRO['gyr_bias_walk_radps2_sqrthz']:g} rad/s^2/sqrt(Hz), "
        "10x the simulator's default) so that the feet drift apart as in seed 001's experiments. "
        "Mean over seeds of the final foot separation E_s (the true one is 0.2 m) and of the final "
        "position error E_p of each foot (m). Seed 001 Table I: E_s 7.33 -> 0.42 m (straight), "
        "33 / 31 -> 0.37 / 0.32 m (rectangle CW / CCW).",
        "",
        "| walk | " + " | ".join(fusions) + " |",
        "|---|" + "---|" * len(fusions),
    ]
    for scenario, opts, label in SIM_WALKS:
        acc: dict[str, list] = {f: [] for f in fusions}
        for seed in range(n_seeds):
            rec = footnav.simulate(scenario, seed=seed, **DRIFTY_GYRO, **opts)
            for fus in fusions:
                res = footnav.make_pipeline("adaptive", "ekf", fus).run(rec.left, rec.right)
                es = float(np.linalg.norm(res.left.position[-1, :2] - res.right.position[-1, :2]))
                ep = [
                    float(np.linalg.norm(tr.position[-1, :2] - truth.position[-1, :2]))
                    for tr, truth in ((res.left, rec.truth_left), (res.right, rec.truth_right))
                ]
                acc[fus].append((es, *ep))
        cells = []
        for fus in fusions:
            es, epl, epr = np.mean(acc[fus], axis=0)
            cells.append(f"E_s {es:.2f}, E_p {epl:.2f} / {epr:.2f}")
        rows.append(f"| {label} | " + " | ".join(cells) + " |")
    return rows + [""]


#: Heading aids beside the default (issue 32): name -> pipeline keywords.
HEADING_AIDS = {
    "default": {},
    "dominant-directions": {"heading_aid": "dominant-directions"},
    "magnetometer": {"heading_aid": "magnetometer"},
    "ekf 15 states + ZARU": {"estimator_params": {"bias_states": True, "zaru_std_radps": 0.005}},
}
#: The simulator's hallway block (benchmarks/bench_consistency.py's): one lap is 5.6 minutes.
BLOCK_LAP = [(150.0, 90.0), (60.0, 90.0)] * 2


def heading_section(root, n_seeds: int) -> list[str]:
    """Heading on long walks: the gait-driven hallway walks and the simulator's 11- and 62-minute
    walks, each heading aid and the 15-state filter beside the default."""
    import numpy as np

    rows = [
        "## Heading on long walks",
        "",
        "Each heading aid (docs/heading.md) and the 15-state filter with ZARU beside the default "
        "pipeline. Gait-driven hallway walks (development set, 8 walks, one foot): footprint RMSE (m), "
        "median / worst; they have no magnetometer. Simulator: laps of a 150 x 60 m block at 100 Hz "
        f"with the simulator's magnetometer (50 uT, dip 60 deg, 1 uT hard iron), seeds 0-{n_seeds - 1}, "
        "left foot's 2-D ATE (m), mean / worst; the default sensor is consumer MEMS grade (gyro bias "
        f"walk 1e-5 rad/s^2/sqrt(Hz)), the drifty one {DRIFTY_GYRO['gyr_bias_walk_radps2_sqrthz']:g}. "
        "The simulator's stance foot is still unless `stance_twist_deg` turns it in each walking stance, "
        "as real shoes do (docs/heading.md).",
        "",
        "| walk | "
        + " | ".join(f"`{k}`" if k in ("dominant-directions", "magnetometer") else k for k in HEADING_AIDS)
        + " |",
        "|---|" + "---|" * len(HEADING_AIDS),
    ]
    gd = [n for n in dataset_names(root) if n.startswith("gaitdriven_")]
    if gd:
        vals: dict[str, list] = {k: [] for k in HEADING_AIDS}
        for name in gd:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                rec = load_dataset(name, root)
                for label, kw in HEADING_AIDS.items():
                    if label == "magnetometer":
                        continue
                    value = _value(evaluate(footnav.make_pipeline(**kw), rec), "footprint_rmse", "left")
                    if value is not None:
                        vals[label].append(value)
        rows.append(
            "| gait-driven walks (8), footprint RMSE | "
            + " | ".join(f"{np.median(v):.3f} / {np.max(v):.3f}" if v else "no magnetometer" for v in vals.values())
            + " |"
        )
    for laps, sensor, label in (
        (2, {}, "11.3 min, default sensor"),
        (2, {"stance_twist_deg": 1.0}, "11.3 min, default sensor, stance twist 1 deg"),
        (2, DRIFTY_GYRO, "11.3 min, drifty gyro"),
        (11, {}, "62 min, default sensor"),
        (11, DRIFTY_GYRO, "62 min, drifty gyro"),
    ):
        ates: dict[str, list] = {k: [] for k in HEADING_AIDS}
        for seed in range(n_seeds):
            rec = footnav.simulate("path", seed=seed, segments=BLOCK_LAP * laps, magnetometer=True, **sensor)
            for key, kw in HEADING_AIDS.items():
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    res = footnav.make_pipeline(**kw).run(rec.left, rec.right)
                ates[key].append(metrics.ate_rmse(res.left.position, rec.truth_left.position, dims=2))
        rows.append(
            f"| simulator, {laps} laps ({label}) | "
            + " | ".join(f"{np.mean(v):.2f} / {np.max(v):.2f}" for v in ates.values())
            + " |"
        )
    return rows + [""]


def gait_section(root, names) -> list[str]:
    """The default detector against the walking-tuned one on every gait of the development sets."""
    import numpy as np

    rows = [
        "## Stance detection across gaits (development sets)",
        "",
        "Estimator `ekf`, fusion `independent` (defaults); only the detector changes. These are the "
        "development recordings of issue 13: the detector is also measured on subjects, sensors and "
        "walks that are not in `shared/data`, so read these as dev figures.",
        "",
        "### pyshoe VICON: walking, running, stairs, crawling (2-D ATE, m)",
        "",
        "| trial | " + " | ".join(GAIT_DETECTORS) + " | pyshoe's best detector, tuned per trial |",
        "|---|" + "---|" * (len(GAIT_DETECTORS) + 1),
    ]
    per_det: dict[str, list[float]] = {d: [] for d in GAIT_DETECTORS}
    for name in (n for n in names if n.startswith("pyshoe_")):
        rec = load_dataset(name, root)
        cells = []
        for det in GAIT_DETECTORS:
            value = evaluate(footnav.make_pipeline(det), rec).value("ate_2d", "left")
            per_det[det].append(value)
            cells.append(_fmt(value))
        best = rec.truth_left.meta.get("best_error")
        rows.append(f"| {name[7:]} | " + " | ".join(cells) + f" | {_fmt(best)} |")
    rows.append(
        "| **median / worst** | "
        + " | ".join(f"{np.median(v):.3f} / {np.max(v):.3f}" for v in per_det.values())
        + " | |"
    )
    rows += [
        "",
        "### gait-driven hallway walks at varied paces (footprint RMSE / final footprint error, m)",
        "",
        "One rigid 2-D fit of the estimate at every stride index to the hand-marked footprints "
        "(`metrics.footprint_errors`). The publisher's own pyshoe trajectory (LSTM zero-velocity "
        "detector) is scored the same way.",
        "",
        "| trial | " + " | ".join(GAIT_DETECTORS) + " | publisher's pyshoe |",
        "|---|" + "---|" * (len(GAIT_DETECTORS) + 1),
    ]
    per_det = {d: [] for d in GAIT_DETECTORS}
    for name in (n for n in names if n.startswith("gaitdriven_")):
        rec = load_dataset(name, root)
        cells = []
        for det in GAIT_DETECTORS:
            report = evaluate(footnav.make_pipeline(det), rec)
            per_det[det].append(report.value("footprint_rmse", "left"))
            cells.append(
                f"{_fmt(report.value('footprint_rmse', 'left'))} / "
                f"{_fmt(report.value('footprint_final_error', 'left'))}"
            )
        truth = rec.truth_left
        theirs = metrics.footprint_errors(
            truth.meta["pyshoe_trajectory"], truth.position, index=truth.events["footprint"]
        )
        rows.append(f"| {name[11:]} | " + " | ".join(cells) + f" | {theirs.rmse_m:.3f} / {theirs.final_m:.3f} |")
    rows.append(
        "| **median / worst RMSE** | "
        + " | ".join(f"{np.median(v):.3f} / {np.max(v):.3f}" for v in per_det.values())
        + " | |"
    )
    rows += [
        "",
        "### IPOL: hand-checked footsteps of both feet, subjects 1-8 (steps found / missed / false, F1)",
        "",
        "Stance is the gap between two labelled swings of a foot, compared inside each trial's "
        "boundaries, matched one to one (`metrics.step_detection_from_swings`, 0.1 s tolerance).",
        "",
        "| subject | " + " | ".join(GAIT_DETECTORS) + " |",
        "|---|" + "---|" * len(GAIT_DETECTORS),
    ]
    totals = {d: np.zeros(4) for d in GAIT_DETECTORS}  # found, missed, false, detected + reference
    by_subject: dict[str, dict[str, np.ndarray]] = {}
    for name in (n for n in names if n.startswith("ipol_")):
        subject = name[5:].split("-")[0]
        rec = load_dataset(name, root)
        for det in GAIT_DETECTORS:
            report = evaluate(footnav.make_pipeline(det), rec)
            for foot in ("left", "right"):
                f, m, x = (report.value(k, foot) for k in ("steps_found", "steps_missed", "steps_false"))
                counts = np.array([f, m, x, 2 * f + m + x])
                by_subject.setdefault(subject, {d: np.zeros(4) for d in GAIT_DETECTORS})[det] += counts
                totals[det] += counts

    def cell(c: np.ndarray) -> str:
        return f"{c[0]:.0f} / {c[1]:.0f} / {c[2]:.0f}, F1 {2 * c[0] / c[3]:.3f}"

    for subject, counts in sorted(by_subject.items()):
        rows.append(f"| {subject} | " + " | ".join(cell(counts[d]) for d in GAIT_DETECTORS) + " |")
    rows.append("| **all** | " + " | ".join(cell(totals[d]) for d in GAIT_DETECTORS) + " |")
    return rows + [""]


def _gaitmap_stride_lengths(root, python: str | None) -> dict:
    """gaitmap's own stride lengths: re-measured with ``python`` when given, else the recorded ones."""
    if not python:
        return GAITMAP_STRIDE_LENGTH_M
    import json
    import subprocess

    done = subprocess.run(
        [python, "-c", GAITMAP_STRIDE_SCRIPT, str(Path(root) / "gaitmap_example")],
        capture_output=True,
        text=True,
        check=True,
        timeout=1800,
    )
    return json.loads(done.stdout.strip().splitlines()[-1])


def stride_section(root, gaitmap_python: str | None = None) -> list[str]:
    """footnav's strides.csv on the gaitmap example against the heel marker, gaitmap's beside it."""
    import numpy as np

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        rec = load_dataset("gaitmap", root)
        res = footnav.make_pipeline().run(rec.left, rec.right)
    table = res.strides()
    theirs = _gaitmap_stride_lengths(root, gaitmap_python)
    ours_err, rts_err, default_err, rows = [], [], [], []
    n_ref = 0
    ref_len, ref_dur, rts_all = [], [], []
    for foot, imu, truth in (("left", rec.left, rec.truth_left), ("right", rec.right, rec.truth_right)):
        borders = truth.meta["strides"]
        t0, t1 = imu.t[borders[:, 0]], imu.t[borders[:, 1]]
        heel = np.stack([[np.interp(tt, truth.t, truth.position[:, j]) for j in range(2)] for tt in (t0, t1)])
        ref = np.linalg.norm(heel[1] - heel[0], axis=0)  # heel marker displacement, min_vel to min_vel
        n_ref += len(ref)
        ref_len.extend(ref)
        ref_dur.extend(t1 - t0)
        rts_all.extend(theirs[foot]["rts"])
        est = table[table["foot"] == foot]
        start, end = est["start_s"].to_numpy(), est["end_s"].to_numpy()
        found = 0
        for k, (a, b, length) in enumerate(zip(t0, t1, ref)):
            i = int(np.argmin(np.abs(start - a) + np.abs(end - b)))
            if abs(start[i] - a) >= STRIDE_MATCH_S or abs(end[i] - b) >= STRIDE_MATCH_S:
                continue
            found += 1
            ours_err.append(est["length_m"].iloc[i] - length)
            rts_err.append(theirs[foot]["rts"][k] - length)
            default_err.append(theirs[foot]["default"][k] - length)
        rows.append((foot, len(ref), found))

    # averages: every stride of strides.csv against only the steady ones (docs/batch.md's filter)
    steady = table[
        ~table["first"]
        & ~table["last"]
        & ~table["standstill"]
        & (table["turn_deg"].abs() < 20)
        & (table["kind"] == "level")
    ]
    mocap_cadence = 120.0 / np.asarray(ref_dur)

    def avg(length, cadence, n) -> str:
        return f"{n} | {np.mean(length):.3f} | {np.mean(cadence):.1f}"

    averages = [
        "| strides | n | mean length (m) | mean cadence (steps/min) |",
        "|---|---|---|---|",
        f"| footnav, every stride of `strides.csv` | {avg(table['length_m'], table['cadence_spm'], len(table))} |",
        f"| footnav, without `first`, `last`, `standstill`, turns > 20 deg, stairs | "
        f"{avg(steady['length_m'], steady['cadence_spm'], len(steady))} |",
        f"| motion capture (heel marker), gaitmap's `min_vel` strides | {avg(ref_len, mocap_cadence, len(ref_len))} |",
        f"| gaitmap 2.6 StrideLevelTrajectory + RtsKalman (length), mocap borders (cadence) | "
        f"{avg(rts_all, mocap_cadence, len(rts_all))} |",
    ]

    def cell(e) -> str:
        e = np.asarray(e)
        return f"{np.mean(np.abs(e)):.3f} / {np.mean(e):+.3f} / {np.max(np.abs(e)):.3f}"

    return [
        "## Stride length (gaitmap example, motion capture)",
        "",
        (
            "`footnav run` writes `strides.csv` (`PipelineResult.strides()`, `footnav/nav/strides.py`): a stride "
            "runs from one mid-stance of a foot to its next, and its length is the horizontal displacement "
            "between the two mid-stance positions (gaitmap's definition). Truth: the heel marker (`L_FCC` / "
            "`R_FCC`) displacement between the borders of each motion-capture stride of "
            "`stride_events_sample.csv` (gaitmap's `min_vel` to `min_vel`; the same numbers as gaitmap's "
            "`position_sample.csv`). footnav's strides (default pipeline, its own stances and mid-stances) "
            f"are matched to these when both ends lie within {STRIDE_MATCH_S:g} s; gaitmap's figures are on the "
            "same matched strides, from the IMU data with the mocap stride borders given to it "
            "(gaitmap 2.6.0 `StrideLevelTrajectory` + `SpatialParameterCalculation`, "
            "`GAITMAP_STRIDE_LENGTH_M` in docs/make_accuracy.py; our measurement, not a published figure)."
        ),
        "",
        "Matched strides: " + ", ".join(f"{f} {m} of {n}" for f, n, m in rows) + ".",
        "",
        "| method | MAE / mean error / max abs error (m) |",
        "|---|---|",
        f"| footnav `strides.csv` (defaults) | {cell(ours_err)} |",
        f"| gaitmap 2.6 StrideLevelTrajectory + RtsKalman | {cell(rts_err)} |",
        f"| gaitmap 2.6 StrideLevelTrajectory, defaults (forward-backward integration) | {cell(default_err)} |",
        "",
        (
            "Averages: the first and last strides of each foot run across the standing at the start and the "
            "end, so averaging every stride of `strides.csv` biases cadence low; the flags `first`, `last`, "
            "`standstill`, `turn_deg` and `kind` leave them out (docs/batch.md). gaitmap's stride list "
            "starts and ends while walking and holds the turns."
        ),
        "",
        *averages,
        "",
    ]


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--data-dir")
    ap.add_argument("--seeds", type=int, default=5)
    ap.add_argument("--out", default=str(Path(__file__).with_name("accuracy.md")))
    ap.add_argument("--gaitmap-python", help="a Python with gaitmap 2.6 installed: re-measure gaitmap's stride lengths")
    ap.add_argument("--only-strides", action="store_true", help="print the stride section only (no file written)")
    args = ap.parse_args()
    root = data_dir(args.data_dir)
    if args.only_strides:
        print("\n".join(stride_section(root, args.gaitmap_python)))
        return
    pipe = footnav.make_pipeline()
    lines = [
        "# Accuracy on the shared real recordings",
        "",
        "Generated by `python docs/make_accuracy.py` (do not edit by hand) with footnav "
        f"{footnav.__version__} on Python {platform.python_version()}.",
        "",
        f"Pipeline: `{pipe!r}` (the defaults: adaptive detector, 9-state EKF with whole-walk RTS "
        "smoothing, each foot alone).",
        "",
        "Metrics (definitions in `footnav/analysis/metrics/`): `ate_2d`/`ate_3d` = RMSE after rigid "
        "alignment to the truth (m); `loop_closure_2d`/`_3d` = end-to-start distance of a walk that returns to "
        "its start (m, % of path); `final_separation` = E_s of seed 001 (m); `stance_f1`, "
        "`steps_missed`/`steps_false` against the recording's stance labels (for pyshoe these are "
        "proxy labels of the best detector per trial, not hand labels).",
        "",
        "The pyshoe reference is the per-trial error the dataset stores for its best zero-velocity "
        "detector with a per-trial optimised threshold (`best_error`; the dataset's own error "
        "definition, not necessarily the same alignment as ours).",
        "",
        "| recording | foot | metric | footnav | reference |",
        "|---|---|---|---|---|",
    ]
    names = [n for n in dataset_names(root) if not n.startswith(DEV_SETS)]
    for name in names:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # duplicates/gaps/clipping are recorded in meta
            rec = load_dataset(name, root)
            report = evaluate(pipe, rec)
        for m in report.metrics:
            if m.name not in SHOWN:
                continue
            ref = REFERENCE.get((name, m.name, m.foot), "")
            if name.startswith("pyshoe_") and m.name == "ate_2d" and "best_error" in rec.truth_left.meta:
                tm = rec.truth_left.meta
                ref = f"{tm['best_error']:.3f} (pyshoe's own error of its best detector, {tm.get('best_detector')})"
            value = f"{m.value:.0f}" if m.unit == "count" else f"{m.value:.3f}"
            unit = f" {m.unit}" if m.unit and m.unit != "count" else ""
            lines.append(f"| {name} | {m.foot} | {m.name} | {value}{unit} | {ref} |")
    lines.append("")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # data oddities and stance checks are recorded in meta
        lines += gait_section(root, dataset_names(root))
    lines += stride_section(root, args.gaitmap_python)
    lines += height_section(root, names)
    lines += estimator_section(root, names)
    lines += heading_section(root, args.seeds)
    lines += fusion_section(root)
    lines += simulator_section(args.seeds)
    Path(args.out).write_text("\n".join(lines), encoding="utf-8")
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
