"""pyshoe VICON trials (University of Toronto foot-mounted INS dataset, Wagstaff et al. 2020).

MATLAB file (``scipy.io.loadmat``) per trial:

* ``imu`` N x 6: acc x, y, z (m/s^2) then gyro x, y, z (rad/s), sensor axes;
* ``ts`` 1 x N: time in s (~200 Hz, jittered);
* ``gt`` N x 3: Vicon foot position (m), one row per IMU sample;
* ``zv_shoe_opt``, ``zv_ared_opt``, ``zv_amvd_opt``, ``zv_mbgtd_opt``, ``zv_vicon_opt`` 1 x N: each
  detector's zero-velocity output with its per-trial best threshold (``G_*_opt``) -- proxy
  labels, not hand labels; ``trial_error``, ``best_detector``, ``best_error``.

Frames, as found in the data:

* Sensor: mounted z DOWN (acc reads -g on z with the foot flat at rest). The reader turns the
  body axes 180 degrees about x, (x, y, z) -> (x, -y, -z) for acc and gyro (a proper rotation,
  not a mirror), so that acc reads +g on z at rest like every footnav body frame; recorded in
  ``meta["body_rotation"]`` with the gravity reading at rest as evidence. 13 of the 14 shared
  trials agree; ``2018-02-22-10-08-52`` reads +g on z throughout (slow, low-impact motion:
  probably a crawling trial with the foot upside down, or a different mounting). The reader
  keeps the documented mounting and warns; ``sensor_z="auto"`` decides per trial instead.
* Vicon ``gt``: z UP in every shared trial (height ~0.12 m at rest, the foot rises in swing:
  mean height during the stance labels is below the mean outside them). The reader checks this
  per file (``truth_z="auto"``) and would turn a z-down ``gt`` 180 degrees about x.
* Vicon ``gt`` is LEFT-handed: its x-y plane is the mirror image of the sensor's motion. The
  sensor is a right-handed IMU (it reads -g on its z axis mounted z down), yet in every shared
  walking trial footnav's trajectory fits ``gt`` after 2-D rigid alignment only when one of the
  two is mirrored (e.g. trial 2017-11-22-11-22-03: 1.59 m RMSE as stored, 0.08 m mirrored),
  which no rotation can produce. The file looks like a NED (z down) frame whose z alone was
  flipped. The reader negates y (``truth_mirror_y=True``) to give a right-handed z-up frame and
  records it in ``meta["truth_conversion"]``.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from footnav.core.errors import DataQualityWarning, InvalidInputError, InvalidParameterError
from footnav.core.types import GRAVITY_MPS2, FootTruth, Recording
from footnav.core.warning_log import warn
from footnav.data.io._mat import mat_imu, mat_vector, read_mat
from footnav.data.io._text import ROTATE_180_ABOUT_X, build_imu, changes_of

__all__ = ["read_pyshoe", "PYSHOE_DETECTORS"]

FORMAT = "pyshoe"
#: Zero-velocity label variables of the VICON trials, in the dataset's detector order.
PYSHOE_DETECTORS = ("shoe", "ared", "amvd", "mbgtd", "vicon")
#: Meaning of the 5 trial_error entries (see the comment where they are read).
_TRIAL_ERROR_NAMES = ("shoe", "ared", "ared (repeated; amvd unknown)", "mbgtd", "vicon")
#: Samples with |gyro| below this (rad/s) and |acc| within REST_ACC_TOL of g count as at rest.
REST_GYR_RADPS = 0.1
REST_ACC_TOL_MPS2 = 1.0
#: Fewer rest samples than this: fall back to the mean accelerometer reading of the whole trial.
MIN_REST_SAMPLES = 20


def _gravity_z_sign(acc: NDArray[np.float64], gyr: NDArray[np.float64]) -> tuple[float, str]:
    """Sign of the accelerometer's z reading at rest, and how it was found."""
    rest = (np.linalg.norm(gyr, axis=1) < REST_GYR_RADPS) & (
        np.abs(np.linalg.norm(acc, axis=1) - GRAVITY_MPS2) < REST_ACC_TOL_MPS2
    )
    if rest.sum() >= MIN_REST_SAMPLES:
        mean = acc[rest].mean(axis=0)
        how = f"mean acc over {int(rest.sum())} rest samples = {np.round(mean, 2).tolist()} m/s^2"
    else:
        mean = acc.mean(axis=0)
        how = f"mean acc over the whole trial = {np.round(mean, 2).tolist()} m/s^2 (too few rest samples)"
    return float(np.sign(mean[2])), how


# complexity: one branch per variant of the published files
def read_pyshoe(  # noqa: C901
    path: Any,
    *,
    sensor_z: str = "down",
    truth_z: str = "auto",
    truth_mirror_y: bool = True,
    stance_proxy: str | None = None,
    drop_duplicates: bool = False,
    acc_full_scale_mps2: float | None = None,
) -> Recording:
    """Read one pyshoe VICON trial (.mat): one foot, Vicon position truth, proxy stance labels.

    Parameters
    ----------
    path
        The trial's .mat file.
    sensor_z
        Mounting of the sensor's z axis: ``"down"`` (default, the dataset's documented mounting:
        rotate the body axes 180 degrees about x), ``"up"`` (keep the axes) or ``"auto"`` (decide
        per trial from gravity at rest). When the data contradict the choice (acc would read -g on
        z at rest) a DataQualityWarning says so: the foot may rest upside down (crawling) or the
        sensor may have been mounted the other way.
    truth_z
        ``"auto"`` (decide from the trajectory: the foot is lower in stance than in swing),
        ``"up"`` or ``"down"`` (rotate ``gt`` 180 degrees about x).
    truth_mirror_y
        Negate ``gt``'s y to undo its left-handedness (see the module docstring); False keeps it.
    stance_proxy
        Detector whose labels become ``FootTruth.stance``: one of ``PYSHOE_DETECTORS`` or
        ``"best"`` (the trial's ``best_detector``); default ``"vicon"`` if ``zv_vicon_opt`` is
        present, else ``"best"``. Note that the vicon detector is not always the most accurate
        one (``truth.meta["trial_error"]``).
    drop_duplicates
        Drop samples repeating the previous time stamp (and their gt/label rows); else they raise.
    acc_full_scale_mps2
        Accelerometer full scale for clipping detection, if known.

    Returns
    -------
    Recording
        ``left`` = the foot (SI, body frame with z up at rest, ``meta["body_rotation"]``);
        ``truth_left`` = FootTruth(``frame="vicon"``, z up, ``stance`` = the proxy labels with
        ``meta["stance_source"]``, every ``zv_*`` label in ``meta["zv_labels"]``).
    """
    mat, p = read_mat(path, what="pyshoe .mat file", required=("imu", "ts"))
    src = str(p)
    raw = mat_imu(mat, "imu", src)
    n = len(raw)
    ts = mat_vector(mat, "ts", n, src).astype(np.float64)
    acc, gyr = raw[:, :3], raw[:, 3:]

    if sensor_z not in ("auto", "up", "down"):
        raise InvalidParameterError(f"sensor_z must be 'auto', 'up' or 'down', got {sensor_z!r}")
    sensor_z_arg = sensor_z
    sign, how = _gravity_z_sign(acc, gyr)
    data_says = "down" if sign < 0 else "up"
    if sensor_z == "auto":
        sensor_z = data_says
    elif sensor_z != data_says:
        # Either the foot rests upside down (the VICON set has crawling trials) or this trial's
        # sensor was mounted differently: the reader cannot tell, so it keeps the requested axes.
        warn(
            f"{src}: the sensor reads {'+' if sign > 0 else '-'}g on z at rest ({how}), but sensor_z={sensor_z!r}: "
            f"after conversion acc reads {'-' if sign > 0 else '+'}g on z at rest. Either the foot rests upside "
            "down (e.g. a crawling trial) or the sensor was mounted the other way in this trial; pass "
            "sensor_z='auto' to decide from gravity. Recorded in meta['body_rotation']",
            DataQualityWarning,
            stacklevel=2,
        )
    if sensor_z == "down":
        acc, gyr = acc @ ROTATE_180_ABOUT_X.T, gyr @ ROTATE_180_ABOUT_X.T
        body_rotation = {
            "applied": "180 deg about x: (x, y, z) -> (x, -y, -z) for acc and gyr",
            "matrix": ROTATE_180_ABOUT_X.tolist(),
            "sensor_frame": "sensor z axis mounted down (toward the sole); turned to z up",
        }
    else:
        body_rotation = {"applied": None, "sensor_frame": "sensor z axis taken as up; axes kept"}
    body_rotation["evidence"] = how
    body_rotation["gravity_at_rest_says"] = f"sensor z {data_says}"
    body_rotation["decided_by"] = (
        "gravity at rest (sensor_z='auto')" if sensor_z_arg == "auto" else f"sensor_z={sensor_z_arg!r}"
    )

    imu, keep = build_imu(
        ts,
        acc,
        gyr,
        path=src,
        fmt=FORMAT,
        drop_duplicates=drop_duplicates,
        acc_full_scale_mps2=acc_full_scale_mps2,
        meta={
            "foot": "unknown (one foot)",
            "body_rotation": body_rotation,
            "changes": [f"body axes {body_rotation['applied'] or 'kept (sensor z up at rest)'}"],
        },
    )

    labels = {}
    for det in PYSHOE_DETECTORS:
        key = f"zv_{det}_opt"
        if key in mat:
            lab = mat_vector(mat, key, n, src)
            if not np.isin(lab, (0, 1)).all():
                raise InvalidInputError(f"labels must be 0 or 1, found {np.unique(lab)[:5]}", path=src, field=key)
            labels[det] = lab.astype(bool)[keep]
    best = str(np.asarray(mat["best_detector"]).reshape(-1)[0]).strip() if "best_detector" in mat else None
    if stance_proxy is None:
        stance_proxy = "vicon" if "vicon" in labels else best
    elif stance_proxy == "best":
        stance_proxy = best
    if stance_proxy is not None and stance_proxy not in labels:
        raise InvalidParameterError(
            f"stance_proxy {stance_proxy!r} has no labels in {src}; available: {sorted(labels)}"
        )

    truth = None
    if "gt" in mat or labels:
        if "gt" in mat:
            gt = np.asarray(mat["gt"], dtype=np.float64)
            if gt.shape != (n, 3):
                raise InvalidInputError(f"expected shape ({n}, 3), got {gt.shape}", path=src, field="gt")
            gt = gt[keep]
            t_ref = imu.t
        else:
            gt, t_ref = np.empty((0, 3)), np.empty(0)
        truth_rotation: dict[str, Any] = {"applied": None}
        if len(gt):
            if truth_z not in ("auto", "up", "down"):
                raise InvalidParameterError(f"truth_z must be 'auto', 'up' or 'down', got {truth_z!r}")
            ref = labels.get(stance_proxy) if stance_proxy else None
            if ref is not None and 0 < ref.sum() < len(ref):
                z_stance = float(np.nanmean(gt[ref, 2]))
                z_swing = float(np.nanmean(gt[~ref, 2]))
                gt_z = "up" if z_stance < z_swing else "down"
                evidence = (
                    f"mean gt z during {stance_proxy} stance labels {z_stance:.3f} m, outside {z_swing:.3f} m: "
                    f"the foot is {'lower' if gt_z == 'up' else 'higher'} in stance"
                )
            else:
                gt_z, evidence = "up", "no stance labels to check against; assumed z up (dataset's Vicon frame)"
            if truth_z == "auto":
                truth_z = gt_z
            elif truth_z != gt_z:
                warn(
                    f"{src}: truth_z={truth_z!r} forced, but the data say z {gt_z} ({evidence})",
                    DataQualityWarning,
                    stacklevel=2,
                )
            if truth_z == "down":
                gt = gt @ ROTATE_180_ABOUT_X.T
                truth_rotation = {
                    "applied": "180 deg about x: (x, y, z) -> (x, -y, -z)",
                    "matrix": ROTATE_180_ABOUT_X.tolist(),
                }
            truth_rotation["evidence"] = evidence
        truth_conversion: dict[str, Any] = {"mirror_y": False}
        if len(gt) and truth_mirror_y:
            gt = gt * np.array([1.0, -1.0, 1.0])
            truth_conversion = {
                "mirror_y": True,
                "why": "gt is stored in a left-handed frame (its x-y plane mirrors the right-handed IMU's motion); "
                "y negated to make it right-handed, z up",
            }
        meta: dict[str, Any] = {
            "source": src,
            "position_source": "Vicon foot position, one row per IMU sample (align start and heading before comparing)",
            "truth_rotation": truth_rotation,
            "truth_conversion": truth_conversion,
            "zv_labels": labels,
            "best_detector": best,
        }
        if "trial_error" in mat:
            err = np.asarray(mat["trial_error"], dtype=np.float64).reshape(-1)
            # Upstream lists [shoe, ared, ared, mbgtd, vicon] (ared twice) and entries 2 and 3 are
            # equal in every shared trial although the ared and amvd labels differ: entry 3 is not
            # the amvd error, so it is not labelled as such.
            meta["trial_error"] = err
            if len(err) == 5:
                meta["trial_error_m"] = dict(zip(_TRIAL_ERROR_NAMES, map(float, err)))
        if "best_error" in mat:
            meta["best_error"] = float(np.asarray(mat["best_error"], dtype=np.float64).reshape(-1)[0])
        meta["thresholds"] = {
            det: float(np.asarray(mat[f"G_{det}_opt"]).reshape(-1)[0])
            for det in PYSHOE_DETECTORS
            if f"G_{det}_opt" in mat
        }
        if stance_proxy is not None:
            meta["stance_source"] = (
                f"proxy labels zv_{stance_proxy}_opt: the {stance_proxy} detector's output with its per-trial best "
                "threshold, not hand labels"
            )
        truth = FootTruth(
            t=t_ref,
            position=gt,
            stance=None if stance_proxy is None else labels[stance_proxy],
            frame="vicon",
            meta=meta,
        )

    changes = changes_of("foot", imu)
    return Recording(
        left=imu,
        truth_left=truth,
        name=p.stem,
        meta={
            "format": FORMAT,
            "source": src,
            "body_rotation": body_rotation,
            "units_converted": imu.meta["units_converted"],
            "changes": changes,
        },
    )
