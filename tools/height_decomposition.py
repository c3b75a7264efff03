"""Where the height drift of flat walks comes from: per recording and per stride (issue 31).

For every shared recording with a closed loop or a height truth (x-io loops, pyshoe VICON trials,
azure_fgo, gaitmap), runs the default pipeline's detector once and the EKF in several variants,
each removing one candidate cause, and prints per variant:

* ``dz``: end minus start height (m); ``d2``: 2-D end-to-start distance (m, loops only);
* ``vrmse``: vertical RMSE against the truth (m; estimate interpolated to the truth's times,
  the best constant height offset removed); ``ate2``: 2-D rigidly aligned RMSE (m);
* ``dz/stride``: median and mean of the height change from one stance's middle to the next;
* per stride, the default estimate's height error against the truth (flat without one) fitted to
  the filter's spread of the vertical residual at the first ZUPT sample (-v_z T / 2), the pitch
  a forward residual implies times the stride length, and the strapdown's own error;
* the truth's vertical velocity at the detected stance starts (and 20 ms before, 20-100 ms after);
* ``swing``/``stance``: the per-stride height change split into what the integration did between
  two stances and what changed within the stances (the filter's corrections: with
  ``smoother="none"`` the forward ZUPT corrections, with the smoother its redistribution).

And per recording the at-rest specific force |f| (median over the still samples of the first
stance) against the gravity footnav uses (``GRAVITY_MPS2``), with the per-stride climb that
mismatch would cause uncorrected, 0.5 (|f| - g) T_swing^2.

Variants (each one change against the default ``make_pipeline()``):

``base``      the default filter (9 states, whole-walk RTS smoother, the update on each stance's
              settled part) with its own height
              (``vertical="free"``, as every variant but ``floors``: the subject of the decomposition);
``floors``    the default pipeline: level strides held level (``vertical="floors"``);
``detected``  the update over the whole detected stance (``zupt_edges="detected"``, the default
              before 2026-12-02: docs/height.md, section 8);
``fwd``       ``smoother="none"``: the forward filter alone;
``gcal``      acc scaled by g / |f_rest| of the first standstill (= gravity set to the sensor's
              own at-rest reading, up to a common scale);
``acc2``      ``acc_noise_mps2_sqrthz=2.0``;
``gyr1e-4``   ``gyr_noise_radps_sqrthz=1e-4`` (attitude barely allowed to move in a swing);
``bias15``    ``bias_states=True``;
``trim20``    every stance shortened by 20 ms at each end (ZUPT only while surely still);
``start50``, ``start100``  every stance's start delayed by 50 / 100 ms (the foot still settling);
``end50``     every stance's end advanced by 50 ms (heel already rising);
``settle_acc=..`` (custom only) each stance's ZUPT starts where the foot has settled by its own data:
              ||f| - g_rest| < settle_acc and |w| < settle_gyr (rad/s) for settle_w s, at most trim_frac in;
``<variant>`` more can be given on the command line as ``name:param=value+param=value``.

Usage::

    FOOTNAV_DATA=../shared/data PYTHONPATH=$PWD python tools/height_decomposition.py [names...]
        [--variants base,fwd,...] [--per-stride]
"""

from __future__ import annotations

import argparse
import sys
import warnings
from dataclasses import replace

import numpy as np

import footnav
from footnav.analysis.metrics import rigid_align
from footnav.core.types import GRAVITY_MPS2, StanceResult
from footnav.data.datasets import dataset_names, load_dataset
from footnav.nav.floors import hold_floors

STILL_GYR_RADPS = 0.05  # the estimator's own still_gyr_max_radps default

VARIANTS: dict[str, dict] = {
    "base": {},
    "floors": {"est": {"vertical": "floors"}},
    "detected": {"est": {"zupt_edges": "detected"}},
    "fwd": {"est": {"smoother": "none"}},
    "gcal": {"gcal": True},
    "acc2": {"est": {"acc_noise_mps2_sqrthz": 2.0}},
    "gyr1e-4": {"est": {"gyr_noise_radps_sqrthz": 1e-4}},
    "bias15": {"est": {"bias_states": True}},
    "trim20": {"trim_s": 0.02},
    "start50": {"trim_start_s": 0.05},
    "start100": {"trim_start_s": 0.1},
    "end50": {"trim_end_s": 0.05},
}


def default_names() -> list[str]:
    return [
        n for n in dataset_names() if n in ("xio_short", "xio_long", "azure_fgo", "gaitmap") or n.startswith("pyshoe_")
    ]


def at_rest_norm(imu, stance: StanceResult) -> tuple[float, int, int]:
    """Median |f| over the still samples of the first stance, and that stance's range."""
    s0, s1 = (int(x) for x in stance.intervals[0])
    an = np.linalg.norm(imu.acc[s0:s1], axis=1)
    still = np.linalg.norm(imu.gyr[s0:s1], axis=1) < STILL_GYR_RADPS
    return float(np.median(an[still] if still.sum() >= 10 else an)), s0, s1


def trimmed(stance: StanceResult, n_start: int, n_end: int, frac: float = 1.0) -> StanceResult:
    """Every stance (but the first, which aligns the filter) shortened by n_start / n_end samples,
    each at most ``frac`` of the stance's length."""
    mask = stance.mask.copy()
    for a, b in stance.intervals[1:]:
        a, b = int(a), int(b)
        n0, n1 = min(n_start, int(frac * (b - a))), min(n_end, int(frac * (b - a)))
        if b - a > n0 + n1 + 2:
            mask[a : a + n0] = False
            mask[b - n1 : b] = False
    return replace(stance, mask=mask)


def settled(imu, stance: StanceResult, acc_mps2: float, gyr_radps: float, window_s: float, frac: float) -> StanceResult:
    """Every stance but the first starts where the foot has settled by its own data: the first
    sample from which ``window_s`` of samples all have ||f| - g_rest| < acc_mps2 and |w| < gyr_radps
    (g_rest: the first stance's still |f|), at most ``frac`` of the stance in."""
    g_rest, _, _ = at_rest_norm(imu, stance)
    ok = (np.abs(np.linalg.norm(imu.acc, axis=1) - g_rest) < acc_mps2) & (np.linalg.norm(imu.gyr, axis=1) < gyr_radps)
    w = max(1, round(float(window_s / np.median(np.diff(imu.t)))))
    run = np.convolve(ok.astype(int), np.ones(w, dtype=int))[w - 1 :]  # run[i] = ok[i-w+1..i].sum()
    good = np.zeros(len(ok), dtype=bool)
    good[: len(ok) - w + 1] = run[w - 1 :] == w  # ok[i..i+w-1] all
    mask = stance.mask.copy()
    for a, b in stance.intervals[1:]:
        a, b = int(a), int(b)
        cap = int(frac * (b - a))
        first = np.flatnonzero(good[a : a + cap + 1])
        n0 = int(first[0]) if len(first) else cap
        mask[a : a + n0] = False
    return replace(stance, mask=mask)


def swing_ins(imu, traj_fwd) -> dict:
    """Per swing, pure strapdown from the forward filter's state at the last stance sample to the
    first sample of the next stance: the vertical velocity there (what the first ZUPT sees) and the
    height change (what the integration alone says), and the climb a filter predicts from that
    residual when it spreads it over the swing as a random walk: -v_z T_swing / 2."""
    from footnav.core.types import ImuData
    from footnav.nav.mechanization import strapdown

    steps = np.asarray(traj_fwd.steps)
    g0 = np.asarray(traj_fwd.meta.get("gyro_bias_radps", np.zeros(3)))
    vz, dz, pred = [], [], []
    for k in range(len(steps) - 1):
        a, b = int(steps[k, 1]) - 1, int(steps[k + 1, 0])
        s = ImuData(t=imu.t[a : b + 1].copy(), acc=imu.acc[a : b + 1].copy(), gyr=imu.gyr[a : b + 1].copy())
        _, v, p = strapdown(s, traj_fwd.quaternion[a], traj_fwd.velocity[a], traj_fwd.position[a], gyro_bias_radps=g0)
        vz.append(v[-1, 2])
        dz.append(p[-1, 2] - p[0, 2])
        pred.append(-v[-1, 2] * (imu.t[b] - imu.t[a]) / 2)
    return {"vz": float(np.median(vz)), "dz": float(np.median(dz)), "pred": float(np.median(pred))}


def per_stride(traj) -> dict:
    """Height change per stride (stance middle to stance middle), split into swing and stance."""
    z = traj.position[:, 2]
    steps = np.asarray(traj.steps)
    if len(steps) < 3:
        return {"n": len(steps)}
    mid = ((steps[:, 0] + steps[:, 1] - 1) // 2).astype(int)
    d = np.diff(z[mid])
    swing = z[steps[1:, 0]] - z[steps[:-1, 1] - 1]  # last stance sample -> first of the next
    stance = d - swing  # what changed inside the (half) stances
    t_swing = traj.t[steps[1:, 0]] - traj.t[steps[:-1, 1] - 1]
    return {
        "n": len(d),
        "med": float(np.median(d)),
        "mean": float(np.mean(d)),
        "swing": float(np.mean(swing)),
        "stance": float(np.mean(stance)),
        "t_swing_med": float(np.median(t_swing)),
        "t_swing": t_swing,
        "d": d,
    }


def regression(imu, stance, truth, traj_fwd, traj) -> dict | None:
    """Per stride (stance middle to the next), the height error of ``traj`` against the truth
    (0 for a recording without height truth: flat) fitted by least squares to
    ``a (-v_z T / 2) + b (v_fwd L / (g T)) + c (strapdown's own error) + d``: the filter's spread
    of the vertical residual at the first ZUPT sample, the pitch a forward residual implies times
    the stride length, and what the integration got wrong by itself over the swing."""
    from footnav.core.types import ImuData
    from footnav.nav.mechanization import strapdown

    iv = stance.intervals
    if len(iv) < 6:
        return None
    g0 = np.asarray(traj_fwd.meta.get("gyro_bias_radps", np.zeros(3)))
    mid = (iv[:, 0] + iv[:, 1] - 1) // 2
    if truth is not None and len(truth.t) > 10:
        ok = np.isfinite(truth.position[:, 2])
        zt = np.interp(imu.t[mid], truth.t[ok], truth.position[ok, 2])
    else:
        zt = np.zeros(len(mid))
    rows = []
    for k in range(1, len(iv) - 1):
        a, b = int(iv[k, 1]) - 1, int(iv[k + 1, 0])
        s = ImuData(t=imu.t[a : b + 1].copy(), acc=imu.acc[a : b + 1].copy(), gyr=imu.gyr[a : b + 1].copy())
        _, v, p = strapdown(s, traj_fwd.quaternion[a], traj_fwd.velocity[a], traj_fwd.position[a], gyro_bias_radps=g0)
        d = p[-1] - p[0]
        length = float(np.linalg.norm(d[:2]))
        if length < 0.05:
            continue
        u, dt = d[:2] / length, imu.t[b] - imu.t[a]
        true_dz = zt[k + 1] - zt[k]
        err = traj.position[mid[k + 1], 2] - traj.position[mid[k], 2] - true_dz
        rows.append((err, -v[-1, 2] * dt / 2, (v[-1, :2] @ u) * length / (GRAVITY_MPS2 * dt), d[2] - true_dz))
    r = np.array(rows)
    x = np.column_stack([r[:, 1], r[:, 2], r[:, 3], np.ones(len(r))])
    coef = np.linalg.lstsq(x, r[:, 0], rcond=None)[0]
    r2 = 1.0 - np.sum((r[:, 0] - x @ coef) ** 2) / np.sum((r[:, 0] - r[:, 0].mean()) ** 2)
    return {"n": len(r), "mean": r.mean(axis=0), "coef": coef, "r2": float(r2)}


OFFSETS_S = (-0.02, 0.0, 0.02, 0.05, 0.1)


def truth_vz_at_stance_start(imu, stance, truth) -> np.ndarray | None:
    """The truth's vertical velocity (central difference over 20 ms) at the detected stance
    starts plus ``OFFSETS_S``, medians over the stances after the first (m/s)."""
    if truth is None or len(truth.t) < 10:
        return None
    ok = np.isfinite(truth.position[:, 2])
    t, z = truth.t[ok], truth.position[ok, 2]
    ts = imu.t[stance.intervals[1:, 0]]
    h = 0.01
    return np.array(
        [np.median((np.interp(ts + o + h, t, z) - np.interp(ts + o - h, t, z)) / (2 * h)) for o in OFFSETS_S]
    )


def vertical_rmse(traj, truth) -> tuple[float, float]:
    """Vertical RMSE (best constant offset removed) and 2-D aligned ATE against the truth."""
    if truth is None or len(truth.t) < 10:
        return np.nan, np.nan
    t = truth.t
    keep = (t >= traj.t[0]) & (t <= traj.t[-1]) & np.all(np.isfinite(truth.position), axis=1)
    t, ref = t[keep], truth.position[keep]
    est = np.column_stack([np.interp(t, traj.t, traj.position[:, i]) for i in range(3)])
    ez = est[:, 2] - ref[:, 2]
    vr = float(np.sqrt(np.mean((ez - ez.mean()) ** 2)))
    al = rigid_align(est, ref, dims=2)
    moved = al.apply(est) if hasattr(al, "apply") else est
    a2 = float(np.sqrt(np.mean(np.sum((moved[:, :2] - ref[:, :2]) ** 2, axis=1))))
    return vr, a2


def run_variant(imu, stance, spec: dict):
    est_params = {"vertical": "free", **spec.get("est", {})}
    est = footnav.make_pipeline(estimator_params=est_params).estimator
    if spec.get("gcal"):
        g_rest, _, _ = at_rest_norm(imu, stance)
        imu = replace(imu, acc=imu.acc * (GRAVITY_MPS2 / g_rest))
    if spec.get("settle_acc"):
        stance = settled(
            imu,
            stance,
            spec["settle_acc"],
            spec.get("settle_gyr", 0.5),
            spec.get("settle_w", 0.02),
            spec.get("trim_frac", 0.25),
        )
    if spec.get("trim_s") or spec.get("trim_start_s") or spec.get("trim_end_s"):
        fs = 1.0 / np.median(np.diff(imu.t))
        n0 = round(float(spec.get("trim_start_s", spec.get("trim_s", 0.0)) * fs))
        n1 = round(float(spec.get("trim_end_s", spec.get("trim_s", 0.0)) * fs))
        stance = trimmed(stance, n0, n1, spec.get("trim_frac", 1.0))
    traj = est.estimate(imu, stance)
    # the pipeline holds level strides level after the estimator (vertical="floors", the default)
    return hold_floors(traj, level_rise_max_m=est.level_rise_max_m) if est.vertical == "floors" else traj


def parse_variant(text: str) -> tuple[str, dict]:
    if text in VARIANTS:
        return text, VARIANTS[text]
    name, _, params = text.partition(":")
    spec: dict = {"est": {}}
    for kv in filter(None, params.split("+")):
        k, v = kv.split("=")
        if k == "gcal":
            spec["gcal"] = v.lower() in ("1", "true")
        elif k in ("trim_s", "trim_start_s", "trim_end_s", "trim_frac", "settle_acc", "settle_gyr", "settle_w"):
            spec[k] = float(v)
        else:
            spec["est"][k] = (
                v.lower() == "true"
                if v.lower() in ("true", "false")
                else (float(v) if v.replace(".", "").replace("e-", "").replace("-", "").isdigit() else v)
            )
    return name, spec


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("names", nargs="*")
    ap.add_argument("--variants", default=",".join(VARIANTS))
    ap.add_argument("--per-stride", action="store_true", help="print each stride's height change (base only)")
    args = ap.parse_args(argv)
    names = args.names or default_names()
    variants = [parse_variant(v) for v in args.variants.split(",")]
    warnings.simplefilter("ignore")
    det = footnav.make_pipeline().detector
    print(f"gravity used by footnav: GRAVITY_MPS2 = {GRAVITY_MPS2} m/s^2")
    print(
        "pred_g/str: 0.5 (|f_rest| - g) T_swing^2; ins: strapdown alone per swing from the forward filter's state,"
        " v_z at the first stance sample (m/s), its height change (mm), and -v_z T/2 (mm),"
        " the climb a filter makes of that residual"
    )
    print(
        "rec                          foot  fs_hz |f|rest   dg     T_sw  pred_g/str "
        "| variant  dz      d2     vrmse  ate2   dz/str_med dz/str_mean swing   stance"
    )
    summary: dict[str, list] = {v[0]: [] for v in variants}
    for name in names:
        rec = load_dataset(name)
        s_left, s_right = det.detect_pair(rec.left, rec.right)
        for foot, imu, stance, truth in (
            ("left", rec.left, s_left, rec.truth_left),
            ("right", rec.right, s_right, rec.truth_right),
        ):
            if imu is None:
                continue
            fs = 1.0 / np.median(np.diff(imu.t))
            g_rest, _, _ = at_rest_norm(imu, stance)
            dg = g_rest - GRAVITY_MPS2
            fwd = run_variant(imu, stance, VARIANTS["fwd"])
            ins = swing_ins(imu, fwd)
            reg = regression(imu, stance, truth, fwd, run_variant(imu, stance, VARIANTS["base"]))
            if reg is not None:
                m, c = reg["mean"] * 1e3, reg["coef"]
                print(
                    f"{name[:28]:28s} {foot:5s} per stride (mean, mm): "
                    f"error {m[0]:+.1f} = a x {m[1]:+.1f} (-v_z T/2) + b x {m[2]:+.1f} "
                    f"(v_fwd L/(gT)) + c x {m[3]:+.1f} (strapdown's own) + d: a {c[0]:.2f} b {c[1]:.2f} c {c[2]:.2f} "
                    f"d {c[3] * 1e3:+.1f} mm, R2 {reg['r2']:.2f} ({reg['n']} strides)"
                )
            print(
                f"{name[:28]:28s} {foot:5s} ins: v_z {ins['vz']:+.3f} m/s, dz {ins['dz'] * 1e3:+.1f} mm, "
                f"-v_z T/2 {ins['pred'] * 1e3:+.1f} mm per stride (medians)"
            )
            tv = truth_vz_at_stance_start(imu, stance, truth)
            if tv is not None:
                print(
                    f"{name[:28]:28s} {foot:5s} truth v_z at the detected stance start {OFFSETS_S} s: "
                    f"{np.round(tv, 3)} m/s (medians)"
                )
            first = True
            for vname, spec in variants:
                try:
                    traj = run_variant(imu, stance, spec)
                except Exception as exc:  # noqa: BLE001 -- a variant that fails (any error of the run) is reported, the others still run
                    print(f"{name:28s} {foot:5s} {vname}: failed: {exc}")
                    continue
                ps = per_stride(traj)
                vr, a2 = vertical_rmse(traj, truth)
                p = traj.position
                dz, d2 = p[-1, 2] - p[0, 2], float(np.linalg.norm(p[-1, :2] - p[0, :2]))
                head = "".ljust(60)
                if first:
                    tsw = ps.get("t_swing_med", np.nan)
                    head = (
                        f"{name[:28]:28s} {foot:5s} {fs:5.0f} {g_rest:7.4f} {dg:+.4f} {tsw:5.2f} "
                        f"{0.5 * dg * tsw**2 * 1e3:+6.2f}mm"
                    )
                    first = False
                print(
                    f"{head} | {vname:8s} {dz:+.3f} {d2:6.3f} {vr:6.3f} {a2:6.3f} "
                    f"{ps.get('med', np.nan) * 1e3:+8.1f}mm {ps.get('mean', np.nan) * 1e3:+8.1f}mm "
                    f"{ps.get('swing', np.nan) * 1e3:+7.1f} {ps.get('stance', np.nan) * 1e3:+7.1f}"
                )
                summary[vname].append((name, foot, dz, d2, vr, a2))
                if args.per_stride and vname == variants[0][0] and "d" in ps:
                    print("   per-stride dz (mm):", np.array2string(ps["d"] * 1e3, precision=0, max_line_width=150))
        sys.stdout.flush()
    print("\nsummary per variant: x-io dz short/long, pyshoe vrmse median/worst, azure ate2 L/R, xio d2")
    for vname, rows in summary.items():
        by = {(n, f): r for n, f, *r in rows}
        xs = [by.get((n, "left"), [np.nan] * 4) for n in ("xio_short", "xio_long")]
        py = [r[2] for (n, f), r in by.items() if n.startswith("pyshoe_")]
        az = [by.get(("azure_fgo", f), [np.nan] * 4) for f in ("left", "right")]
        print(
            f"{vname:10s} xio dz {xs[0][0]:+.3f}/{xs[1][0]:+.3f} d2 {xs[0][1]:.3f}/{xs[1][1]:.3f} | pyshoe vrmse "
            f"{np.median(py) if py else np.nan:.3f}/{np.max(py) if py else np.nan:.3f} | "
            f"azure vrmse {az[0][2]:.3f}/{az[1][2]:.3f} "
            f"ate2 {az[0][3]:.3f}/{az[1][3]:.3f}"
        )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
