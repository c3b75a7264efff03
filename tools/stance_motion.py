"""How still a detected stance is: the figures of docs/height.md, section 8.

Per shared recording and foot (default: x-io, azure_fgo, gaitmap, the pyshoe trials), each in
its own part (``--parts``, default all; the motion-capture foot's vertical speed at the detected
stance starts is ``tools/height_decomposition.py``'s):

``profile`` the median |w| (rad/s) and ||f| - g_stance| (m/s^2) over each tenth of the detected
            stances (not the first): the foot turns and accelerates through its stance;
``lever``   the lever from a fixed pivot on the ground to the sensor (body frame, cm) that best
            explains the stances' specific force as a rigid body rolling about it,
            f = C^T g + alpha x r + w x (w x r) (least squares over every stance, each stance's
            gravity direction its own unknown; the angular acceleration alpha from the gyro
            smoothed over 20 ms), once for the whole stance and once per half; and how far that
            rolling moves the sensor along the stride during the rows the default update keeps,
            v = C (w x r) summed over them (% of the walk's length; positive: forward), the
            most a contact-point update could add to the length;
``tilt``    the tilt between the attitude the gyro carries from the end of each stance through
            the swing (from the forward filter's state there) and the accelerometer's gravity
            direction over the middle half of the next stance, along and across the stride
            (mrad), and that tilt times the stride length (mm);
``edges``   how much of each stance the default update keeps (``zupt_edges="settled"``);
``yaw``     the foot's mean rate about the vertical over the rows the default update keeps, per
            stance (not the first), less the filter's gyro bias, turned to nav by the filter's
            attitude (deg/s; median, quartiles, and the
            share of stances above the 15-state filter's ZARU std of 0.005 rad/s): what a
            zero-angular-rate update in walking stances would take for gyro bias.

Usage::

    FOOTNAV_DATA=../shared/data PYTHONPATH=$PWD python tools/stance_motion.py [names...] [--parts lever,tilt]
"""

from __future__ import annotations

import argparse
import warnings

import numpy as np
from scipy.ndimage import uniform_filter1d  # the gyro smoothed for alpha

import footnav
from footnav.data.datasets import dataset_names, load_dataset
from footnav.nav import quaternion as quat
from footnav.nav.mechanization import strapdown

PARTS = ("profile", "lever", "tilt", "edges", "yaw")

#: The ZARU std of docs/accuracy.md's 15-state column, rad/s.
ZARU_STD_RADPS = 0.005


def _skew(w: np.ndarray) -> np.ndarray:
    z = np.zeros(w.shape[:-1])
    return np.stack(
        [
            np.stack([z, -w[..., 2], w[..., 1]], -1),
            np.stack([w[..., 2], z, -w[..., 0]], -1),
            np.stack([-w[..., 1], w[..., 0], z], -1),
        ],
        -2,
    )


def _relative_rotations(w: np.ndarray, dt: float, mid: int) -> np.ndarray:
    """R_k with x_body(k) = R_k^T x_body(mid), from the gyro (trapezoidal rotation vectors)."""
    n = len(w)
    rot = np.zeros((n, 3, 3))
    rot[mid] = np.eye(3)
    for k in range(mid + 1, n):
        rot[k] = rot[k - 1] @ quat.as_matrix(quat.from_rotvec(0.5 * (w[k - 1] + w[k]) * dt))
    for k in range(mid - 1, -1, -1):
        rot[k] = rot[k + 1] @ quat.as_matrix(quat.from_rotvec(-0.5 * (w[k] + w[k + 1]) * dt))
    return rot


def fit_lever(imu, stance, gyro_bias, *, split: bool) -> np.ndarray:
    """The pivot-to-sensor lever (m, body frame; (3,), or (6,) early / late half with ``split``)."""
    dt = 1.0 / imu.rate_hz
    w = imu.gyr - gyro_bias
    alpha = np.gradient(uniform_filter1d(w, max(1, int(0.02 * imu.rate_hz)), axis=0), imu.t, axis=0)
    nr = 6 if split else 3
    normal, rhs = np.zeros((nr, nr)), np.zeros(nr)
    for a, b in stance.intervals[1:]:
        if b - a < 6:
            continue
        mid = (b - a) // 2
        g_cols = np.transpose(_relative_rotations(w[a:b], dt, mid), (0, 2, 1)).reshape(-1, 3)
        lever = _skew(alpha[a:b]) + _skew(w[a:b]) @ _skew(w[a:b])
        if split:
            cols = np.zeros((b - a, 3, 6))
            early = np.arange(b - a) < mid
            cols[early, :, :3], cols[~early, :, 3:] = lever[early], lever[~early]
        else:
            cols = lever
        cols = cols.reshape(-1, nr)
        f = imu.acc[a:b].reshape(-1)
        # each stance's own gravity direction projected out
        proj = np.linalg.solve(g_cols.T @ g_cols, g_cols.T)
        cp = cols - g_cols @ (proj @ cols)
        fp = f - g_cols @ (proj @ f)
        normal += cp.T @ cp
        rhs += cp.T @ fp
    return np.linalg.solve(normal, rhs)


def updated_motion(estimator, imu, stance, traj, gyro_bias, lever) -> float:
    """Forward motion (% of the length) of a sensor rolling about ``lever`` in the rows
    ``estimator`` updates."""
    rows = estimator._zupt(imu, stance)
    vel = np.einsum("nij,nj->ni", quat.as_matrix(traj.quaternion), np.cross(imu.gyr - gyro_bias, lever))
    step_dt = np.gradient(imu.t)
    moved = length = 0.0
    iv = np.asarray(stance.intervals)
    for (a0, _b0), (a1, b1) in zip(iv[:-1], iv[1:]):
        step = traj.position[a1, :2] - traj.position[a0, :2]
        stride = float(np.linalg.norm(step))
        if stride < 0.2:
            continue
        keep = rows[a1:b1]
        move = (vel[a1:b1][keep, :2] * step_dt[a1:b1][keep, None]).sum(axis=0)
        moved += float(move @ step) / stride
        length += stride
    return 100 * moved / length if length else float("nan")


def stance_yaw_rates(imu, rows, stance, quaternion, gyro_bias) -> np.ndarray:
    """Per stance after the first, the mean rate (rad/s) about the nav vertical over the updated
    ``rows``: the gyro less ``gyro_bias`` (3,), turned to nav by the trajectory's ``quaternion``
    (N, 4), so that the foot's roll from heel to toe does not leak into it."""
    w_up = np.einsum("nj,nj->n", quat.as_matrix(quaternion)[:, 2, :], imu.gyr - gyro_bias)
    out = []
    for a, b in np.asarray(stance.intervals)[1:]:
        keep = rows[a:b]
        if keep.sum() >= 2:
            out.append(float(w_up[a:b][keep].mean()))
    return np.array(out)


def _runs(rec):
    for side in ("left", "right"):
        imu = getattr(rec, side)
        if imu is None:
            continue
        pipe = footnav.make_pipeline(estimator_params={"vertical": "free", "smoother": "none"})
        stance = pipe.detector.detect(imu)
        yield side, imu, stance, pipe


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("names", nargs="*")
    ap.add_argument("--parts", default=",".join(PARTS))
    args = ap.parse_args(argv)
    parts = args.parts.split(",")
    names = args.names or [
        n for n in dataset_names() if n in ("xio_short", "xio_long", "azure_fgo", "gaitmap") or n.startswith("pyshoe_")
    ]
    warnings.simplefilter("ignore")
    for name in names:
        rec = load_dataset(name)
        for side, imu, stance, pipe in _runs(rec):
            tag = f"{name:28s} {side:5s}"
            iv = np.asarray(stance.intervals)
            if "profile" in parts:
                g = np.median(np.linalg.norm(imu.acc[stance.mask], axis=1))
                rows = []
                for a, b in iv[1:-1]:
                    phase = (np.arange(a, b) - a) / (b - a)
                    tenth = np.minimum((phase * 10).astype(int), 9)
                    w = np.linalg.norm(imu.gyr[a:b], axis=1)
                    f = np.abs(np.linalg.norm(imu.acc[a:b], axis=1) - g)
                    rows.append(
                        [np.median(w[tenth == i]) if np.any(tenth == i) else np.nan for i in range(10)]
                        + [np.median(f[tenth == i]) if np.any(tenth == i) else np.nan for i in range(10)]
                    )
                prof = np.nanmedian(np.array(rows), axis=0)
                dur = np.median(iv[1:, 1] - iv[1:, 0]) / imu.rate_hz
                print(
                    f"{tag} profile: stance {dur:.2f} s; |w| by tenth "
                    + " ".join(f"{x:.2f}" for x in prof[:10])
                    + " | ||f|-g| "
                    + " ".join(f"{x:.2f}" for x in prof[10:])
                )
            traj = pipe.estimator.estimate(imu, stance) if {"lever", "tilt", "yaw"} & set(parts) else None
            bias = np.asarray(traj.meta.get("gyro_bias_radps", np.zeros(3))) if traj is not None else None
            if "lever" in parts:
                one, two = fit_lever(imu, stance, bias, split=False), fit_lever(imu, stance, bias, split=True)
                moved = updated_motion(pipe.estimator, imu, stance, traj, bias, one)
                print(
                    f"{tag} lever (cm): whole {np.round(one * 100, 1)} "
                    f"early {np.round(two[:3] * 100, 1)} late {np.round(two[3:] * 100, 1)}; "
                    f"updated motion {moved:+.2f} % of the length"
                )
            if "tilt" in parts:
                rows = []
                for (_a0, b0), (a1, b1) in zip(iv[:-1], iv[1:]):
                    e, m0, m1 = b0 - 1, a1 + (b1 - a1) // 4, a1 + 3 * (b1 - a1) // 4
                    if m1 - m0 < 4:
                        continue
                    q, _, _ = strapdown(
                        imu.slice(e, m1 + 1),
                        traj.quaternion[e],
                        traj.velocity[e],
                        traj.position[e],
                        gyro_bias_radps=bias,
                    )
                    c = quat.as_matrix(q[(m0 + m1) // 2 - e])
                    f = imu.acc[m0 : m1 + 1].mean(axis=0)
                    up = c @ (f / np.linalg.norm(f))  # the accelerometer's up in nav, by the carried attitude
                    step = traj.position[a1, :2] - traj.position[e, :2]
                    length = float(np.linalg.norm(step))
                    if length < 0.2:
                        continue
                    fwd = step / length
                    rows.append((up[0] * fwd[0] + up[1] * fwd[1], -up[0] * fwd[1] + up[1] * fwd[0], length))
                r = np.array(rows)
                if len(r):
                    print(
                        f"{tag} tilt: along {np.median(r[:, 0]) * 1e3:+.1f} mrad "
                        f"(IQR {np.percentile(r[:, 0], 25) * 1e3:+.1f}.."
                        f"{np.percentile(r[:, 0], 75) * 1e3:+.1f}), across {np.median(r[:, 1]) * 1e3:+.1f} mrad; "
                        f"x stride {np.median(r[:, 0] * r[:, 2]) * 1e3:+.1f} mm ({len(r)} strides)"
                    )
            if "yaw" in parts:
                r = stance_yaw_rates(imu, pipe.estimator._zupt(imu, stance), stance, traj.quaternion, bias)
                q1, q2, q3 = np.degrees(np.percentile(r, [25, 50, 75]))
                print(
                    f"{tag} yaw: {q2:+.2f} deg/s median ({q1:+.2f}..{q3:+.2f}) about the vertical in the updated "
                    f"rows; {np.mean(np.abs(r) > ZARU_STD_RADPS) * 100:.0f} % of {len(r)} stances above "
                    f"{ZARU_STD_RADPS} rad/s"
                )
            if "edges" in parts:
                est = footnav.make_pipeline().estimator
                z = est.zupt_rows(imu.t, imu.acc, np.asarray(stance.mask, bool), first_whole=True)
                if z is not None:
                    lost = [(b - a - z[a:b].sum()) / imu.rate_hz * 1e3 for a, b in iv[1:]]
                    start = [(np.argmax(z[a:b]) if z[a:b].any() else b - a) / imu.rate_hz * 1e3 for a, b in iv[1:]]
                    print(
                        f"{tag} edges: of each stance the update leaves out {np.median(lost):.0f} ms (median), "
                        f"{np.median(start):.0f} ms at its start; "
                        f"stance {np.median(iv[1:, 1] - iv[1:, 0]) / imu.rate_hz * 1e3:.0f} ms"
                    )


if __name__ == "__main__":
    main()
