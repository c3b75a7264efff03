"""Clipped accelerometers and the simulator's sampling: the figures of docs/height.md, section 7.

Prints, each in its own part (``--parts``, default all):

``shared``   per shared recording and foot, the share of samples whose accelerometer is at its
             range as the EKF's clip model finds them (an axis within ``FULL_SCALE_RATIO[0]`` of
             the full scale the reader records, or on a plateau), and the peak per axis;
``stairs``   gaitmap's healthy stair recordings: each foot's end height up and down with and
             without ``clip_excess_mps2``, and how far the feet and the two ways disagree;
``swings``   the same recordings per stride: strapdown alone over each swing from the forward
             filter's state, its vertical velocity at the first ZUPT sample, the largest
             accelerometer axis before the stance, the stride's rise; and the least-squares
             body-frame accelerometer bias that zeroes the swings' end velocities;
``level``    gaitmap's level walk with motion capture: 2-D / 3-D ATE and height RMSE per foot,
             with and without the clip model;
``sim``      the simulator's storey with the accelerometer clipped at 3-4.5 g, with and without;
``sampling`` the simulator's storey at 100 Hz from point samples against interval means of a
             1600 Hz simulation, noise-free and with noise.

Usage::

    FOOTNAV_DATA=../shared/data PYTHONPATH=$PWD python tools/clipping_figures.py [--parts stairs,sim]
"""

from __future__ import annotations

import argparse
import warnings
from dataclasses import replace
from pathlib import Path

import numpy as np

import footnav
from footnav.analysis.evaluation import evaluate
from footnav.core.types import FULL_SCALE_RATIO, GRAVITY_MPS2, ImuData, clipped_acc
from footnav.data.datasets import data_dir, dataset_names, load_dataset
from footnav.data.io.gaitmap import read_gaitmap
from footnav.nav.mechanization import strapdown
from footnav.nav.quaternion import as_matrix

G = GRAVITY_MPS2
EXCESS = 10.0 * G
STAIRS = ("imu_sample_healthy_stair_up.csv", "imu_sample_healthy_stair_down.csv")
STOREY = [(1.4, 0.0), ("stairs", 12, 0.17), (2.8, 180.0), ("stairs", 12, -0.17), (1.4, 0.0)]


def _pct(a: float, b: float) -> float:
    return 100.0 * abs(a - b) / max(abs(a), abs(b))


def _clip_mask(imu: ImuData) -> np.ndarray:
    found = imu.meta.get("clipped") or {}
    if not found.get("acc"):
        return np.zeros(imu.n_samples, dtype=bool)
    return clipped_acc(imu.acc, acc_full_scale_mps2=found.get("acc_full_scale_mps2"), fraction=FULL_SCALE_RATIO[0]).any(
        axis=1
    )


def shared() -> None:
    print("## share of samples with the accelerometer at its range (the clip model's rule)")
    for name in dataset_names():
        rec = load_dataset(name)
        for foot, imu in (("left", rec.left), ("right", rec.right)):
            if imu is None:
                continue
            m = _clip_mask(imu)
            peak = np.abs(imu.acc).max(axis=0) / G
            print(
                f"{name:32s} {foot:5s} {m.sum():4d} of {imu.n_samples:6d} ({100 * m.mean():.3f} %)  "
                f"peak |a| per axis {np.round(peak, 2)} g"
            )
    root = Path(data_dir()) / "gaitmap_example"
    for f in STAIRS:
        rec = read_gaitmap(root / f)
        for foot, imu in (("left", rec.left), ("right", rec.right)):
            m = _clip_mask(imu)
            print(f"{f:32s} {foot:5s} {m.sum():4d} of {imu.n_samples:6d} ({100 * m.mean():.3f} %)")


def stairs() -> None:
    print("## gaitmap stairs: end height (m) up / down per foot, default pipeline")
    recs = [read_gaitmap(Path(data_dir()) / "gaitmap_example" / f) for f in STAIRS]
    for label, params in (
        ("default", {}),
        ("clip_excess 10 g", {"clip_excess_mps2": EXCESS}),
        ("free", {"vertical": "free"}),
        ("free, clip_excess 10 g", {"vertical": "free", "clip_excess_mps2": EXCESS}),
    ):
        dz = []
        for rec in recs:
            res = footnav.make_pipeline(estimator_params=params).run(rec.left, rec.right)
            dz.append([float(tr.position[-1, 2] - tr.position[0, 2]) for tr in (res.left, res.right)])
        up, down = dz
        print(
            f"{label:24s} up {up[0]:+.2f} / {up[1]:+.2f}  down {down[0]:+.2f} / {down[1]:+.2f}  feet disagree "
            f"{_pct(*up):.1f} / {_pct(*down):.1f} %  "
            f"up vs down {_pct(up[0], -down[0]):.1f} / {_pct(up[1], -down[1]):.1f} %"
        )


def swings() -> None:
    print("## gaitmap stairs per stride (vertical='free'): strapdown over the swing from the forward filter's state")
    for f in STAIRS:
        rec = read_gaitmap(Path(data_dir()) / "gaitmap_example" / f)
        sl, sr = footnav.make_pipeline().detector.detect_pair(rec.left, rec.right)
        for foot, imu, st in (("left", rec.left, sl), ("right", rec.right, sr)):
            est = footnav.make_pipeline(estimator_params={"vertical": "free"}).estimator
            tr = est.estimate(imu, st)
            fwd = footnav.make_pipeline(estimator_params={"vertical": "free", "smoother": "none"}).estimator.estimate(
                imu, st
            )
            iv, z = st.intervals, tr.position[:, 2]
            mid = ((iv[:, 0] + iv[:, 1] - 1) // 2).astype(int)
            clip = _clip_mask(imu)
            vz, ys, js, rows = [], [], [], []
            for k in range(1, len(iv) - 1):
                a, b = int(iv[k, 1]) - 1, int(iv[k + 1, 0])
                s = ImuData(t=imu.t[a : b + 1].copy(), acc=imu.acc[a : b + 1].copy(), gyr=imu.gyr[a : b + 1].copy())
                q, v, p = strapdown(s, fwd.quaternion[a], fwd.velocity[a], fwd.position[a])
                c = np.array([as_matrix(x) for x in q])
                ys.append(v[-1])
                js.append(np.einsum("kij,k->ij", c, np.diff(s.t, prepend=s.t[0])))
                rise = z[mid[k + 1]] - z[mid[k]]
                peak = np.abs(imu.acc[a : b + 1]).max() / G
                rows.append((rise, p[-1, 2] - p[0, 2], v[-1, 2], peak, bool(clip[a : b + 1].any())))
                vz.append(v[-1, 2])
            r = np.array(rows)
            stair = np.abs(r[:, 0]) > 0.1
            bias, *_ = np.linalg.lstsq(np.concatenate(js), np.concatenate(ys), rcond=None)
            res = np.concatenate(ys) - np.concatenate(js) @ bias
            unclipped = stair & (r[:, 4] == 0)
            print(
                f"{f[18:-4]:10s} {foot:5s}: stair strides {stair.sum()}, rise median {np.median(r[stair, 0]):+.3f} m, "
                f"strapdown {np.median(r[stair, 1]):+.3f} m, "
                f"v_z at the first ZUPT sample median {np.median(r[stair, 2]):+.2f} m/s "
                f"(clipped strides {np.median(r[stair & (r[:, 4] > 0), 2]):+.2f}, "
                f"unclipped {np.median(r[unclipped, 2]) if unclipped.any() else np.nan:+.2f}); "
                f"{int((stair & (r[:, 4] > 0)).sum())} clipped; bias fit {np.round(bias, 2)} m/s^2: rms |v_end| "
                f"{np.sqrt(np.mean(np.concatenate(ys) ** 2)):.3f} -> {np.sqrt(np.mean(res**2)):.3f} m/s"
            )
            clipped_est = footnav.make_pipeline(
                estimator_params={"vertical": "free", "clip_excess_mps2": EXCESS}
            ).estimator
            rise_off = np.diff(z[mid])
            rise_on = np.diff(clipped_est.estimate(imu, st).position[mid, 2])
            has = np.array([clip[int(iv[k, 1]) : int(iv[k + 1, 0]) + 1].any() for k in range(len(iv) - 1)])
            on_stairs = np.abs(rise_off) > 0.1
            for label, sel in (("clipped", on_stairs & has), ("unclipped", on_stairs & ~has)):
                if sel.any():
                    print(
                        f"{'':10s} {label:9s} stair strides {sel.sum():2d}: mean rise {rise_off[sel].mean():+.3f} m, "
                        f"with clip_excess 10 g {rise_on[sel].mean():+.3f} m"
                    )
            if foot == "right":
                res1 = footnav.make_pipeline().run(rec.left, imu)
                res2 = footnav.make_pipeline().run(rec.left, replace(imu, acc=imu.acc - bias))
                print(
                    f"{'':10s} right foot's end height, default pipeline: "
                    f"{res1.right.position[-1, 2] - res1.right.position[0, 2]:+.2f} m, "
                    f"with that bias removed from its data "
                    f"{res2.right.position[-1, 2] - res2.right.position[0, 2]:+.2f} m"
                )


def level() -> None:
    print("## gaitmap level walk with motion capture (left / right, m)")
    rec = load_dataset("gaitmap")
    for label, params in (
        ("default", {}),
        ("clip_excess 10 g", {"clip_excess_mps2": EXCESS}),
        ("free", {"vertical": "free"}),
        ("free, clip_excess 10 g", {"vertical": "free", "clip_excess_mps2": EXCESS}),
    ):
        d = {(m.foot, m.name): m.value for m in evaluate(footnav.make_pipeline(estimator_params=params), rec).metrics}
        print(
            f"{label:24s} "
            + "  ".join(
                f"{n} {d[('left', n)]:.3f} / {d[('right', n)]:.3f}" for n in ("ate_2d", "ate_3d", "height_rmse")
            )
        )


def sim() -> None:
    print(
        "## simulator storey, accelerometer clipped; end height (m, true 0), seeds 0-3 x 2 feet, "
        "vertical='free': mean / worst"
    )
    for rate in (100.0, 400.0):
        sims = [footnav.simulate("path", seed=s, rate_hz=rate, segments=STOREY) for s in range(4)]
        for fs_g in (None, 3.0, 3.5, 4.0, 4.5):
            errs: dict[float, list] = {0.0: [], EXCESS: []}
            share = []
            for rec in sims:
                feet = [
                    imu
                    if fs_g is None
                    else ImuData.from_arrays(
                        imu.t, np.clip(imu.acc, -fs_g * G, fs_g * G), imu.gyr, acc_full_scale_mps2=fs_g * G
                    )
                    for imu in (rec.left, rec.right)
                ]
                share += [_clip_mask(x).mean() for x in feet]
                for ex in errs:
                    res = footnav.make_pipeline(estimator_params={"clip_excess_mps2": ex, "vertical": "free"}).run(
                        *feet
                    )
                    errs[ex] += [tr.position[-1, 2] - tr.position[0, 2] for tr in (res.left, res.right)]
            cells = "  ".join(
                f"clip_excess {ex / G:.0f} g: {np.mean(v):+.3f} / {max(v, key=abs):+.3f}" for ex, v in errs.items()
            )
            print(f"{rate:.0f} Hz range {fs_g} g ({100 * np.mean(share):.2f} % clipped): {cells}")


def _decimate(imu: ImuData, m: int, mean: bool) -> ImuData:
    idx = m + m * np.arange((imu.n_samples - 2 * m) // m)
    if not mean:
        return ImuData(t=imu.t[idx].copy(), acc=imu.acc[idx].copy(), gyr=imu.gyr[idx].copy())
    w = np.ones(m + 1)
    w[0] = w[-1] = 0.5
    w /= m  # the mean over [t - dt/2, t + dt/2] by the trapezoid on the fine samples
    off = np.arange(m + 1) - m // 2
    return ImuData(
        t=imu.t[idx].copy(),
        acc=sum(w[j] * imu.acc[idx + off[j]] for j in range(m + 1)),
        gyr=sum(w[j] * imu.gyr[idx + off[j]] for j in range(m + 1)),
    )


def sampling() -> None:
    print(
        "## simulator storey: end height (m, true 0), default pipeline / vertical='free', "
        "seeds 0-5 x 2 feet: mean / worst"
    )
    for noise in (False, True):
        rows: dict[str, list] = {}
        for seed in range(6):
            base = footnav.simulate("path", seed=seed, rate_hz=100.0, segments=STOREY, noise=noise)
            fine = footnav.simulate("path", seed=seed, rate_hz=1600.0, segments=STOREY, noise=noise)
            cases = {
                "100 Hz simulated": (base.left, base.right),
                "1600 Hz point samples every 16th": tuple(_decimate(x, 16, False) for x in (fine.left, fine.right)),
                "1600 Hz means over 1/100 s": tuple(_decimate(x, 16, True) for x in (fine.left, fine.right)),
                "1600 Hz point samples every 4th": tuple(_decimate(x, 4, False) for x in (fine.left, fine.right)),
                "1600 Hz means over 1/400 s": tuple(_decimate(x, 4, True) for x in (fine.left, fine.right)),
            }
            for label, feet in cases.items():
                a = footnav.make_pipeline().run(*feet)
                b = footnav.make_pipeline(estimator_params={"vertical": "free"}).run(*feet)
                rows.setdefault(label, []).extend(
                    (x.position[-1, 2] - x.position[0, 2], y.position[-1, 2] - y.position[0, 2])
                    for x, y in ((a.left, b.left), (a.right, b.right))
                )
        print("noise" if noise else "noise-free")
        for label, v in rows.items():
            v = np.array(v)
            w0, w1 = v[np.argmax(np.abs(v[:, 0])), 0], v[np.argmax(np.abs(v[:, 1])), 1]
            print(f"  {label:34s} {v[:, 0].mean():+.4f} / {w0:+.4f}  free {v[:, 1].mean():+.4f} / {w1:+.4f}")


PARTS = {"shared": shared, "stairs": stairs, "swings": swings, "level": level, "sim": sim, "sampling": sampling}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--parts", default=",".join(PARTS))
    args = ap.parse_args(argv)
    warnings.simplefilter("ignore")
    for part in args.parts.split(","):
        PARTS[part]()
        print(flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
