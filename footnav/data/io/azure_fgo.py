"""azure_fgo (Azurehappen/Constrained-ZUPT-FGO): both feet at 60 Hz with per-sample position truth.

Folder contents::

    imuMeasLeft.csv, imuMeasRight.csv   time_index,acc_x,acc_y,acc_z,gyro_x,gyro_y,gyro_z,is_zero_vel
    positionGt.csv                      time_index,pos_left_x,pos_left_y,pos_left_z,pos_right_x,...
    ImuFootLeft.mat, posLeft.mat, posFoot.mat   (optional full-length sources, see below)

* ``time_index`` counts samples at 60 Hz: t = time_index / 60 s.
* acc in m/s^2, gyro in rad/s, sensor axes (z up at rest): kept as the body frame unchanged.
* ``is_zero_vel`` is the publisher's threshold detector, NOT truth: it is kept in each foot's
  ``ImuData.meta["publisher_zero_velocity"]`` (bool per sample), never in ``FootTruth.stance``.
* ``positionGt.csv`` is in m, one row per IMU sample, in a right-handed frame with z DOWN. The
  reader turns it 180 degrees about x, (x, y, z) -> (x, -y, -z), a proper rotation; flipping z
  alone would mirror the x-y plane so that no rotation could align a correct estimate.

Full-length sources (``full_length=True``): ``ImuFootLeft.mat`` (17,402 x 17) holds the RIGHT foot in
columns 1-6 and the LEFT foot in columns 7-12 despite its name (columns 13-17 undocumented, kept in
meta); ``posLeft.mat`` is the left-foot truth, ``posFoot.mat`` the right-foot truth, same z-down
frame. The CSV files are rows 5027-12227 of these (checked bit for bit on the published files).
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path as FilePath
from typing import Any

import numpy as np
from numpy.typing import NDArray

from footnav.core.errors import DataNotFoundError, InvalidInputError
from footnav.core.types import FootTruth, Recording
from footnav.data.io._text import ROTATE_180_ABOUT_X, build_imu, changes_of, parse_table, read_text, split_header

__all__ = ["read_azure_fgo", "AZURE_FGO_RATE_HZ", "AZURE_FGO_FILES"]

FORMAT = "azure_fgo"
#: Sampling rate of the recording; time_index / rate = t (7,201 rows = 120 s).
AZURE_FGO_RATE_HZ = 60.0
#: The files of the CSV variant.
AZURE_FGO_FILES = {"left": "imuMeasLeft.csv", "right": "imuMeasRight.csv", "truth": "positionGt.csv"}
_IMU_COLUMNS = ("time_index", "acc_x", "acc_y", "acc_z", "gyro_x", "gyro_y", "gyro_z", "is_zero_vel")
_TRUTH_COLUMNS = ("time_index",) + tuple(f"pos_{f}_{a}" for f in ("left", "right") for a in "xyz")
#: Full-length MATLAB sources: file, variable, columns of each foot (0-based, end exclusive).
_MAT_IMU = ("ImuFootLeft.mat", "ImuFootLeft")
_MAT_IMU_COLUMNS = {"right": (0, 6), "left": (6, 12)}  # swapped despite the file name (README)
_MAT_TRUTH = {"left": ("posLeft.mat", "posLeft"), "right": ("posFoot.mat", "posFoot")}
#: Row of the full-length files where the CSV excerpt starts.
CSV_OFFSET_IN_MAT = 5027
_TRUTH_ROTATION_NOTE = "truth frame z down; turned 180 deg about x: (x, y, z) -> (x, -y, -z) (proper rotation)"


def _folder_of(path: Any) -> FilePath:
    p = FilePath(path)
    if not p.exists():
        raise DataNotFoundError(f"azure_fgo folder {str(p)!r} does not exist")
    return p if p.is_dir() else p.parent


def _read_imu_csv(path: FilePath) -> tuple[dict[str, NDArray[np.float64]], NDArray[np.int64], str]:
    tf = read_text(path, what="azure_fgo IMU file")
    header = split_header(tf.lines[0], ",")
    missing = [c for c in _IMU_COLUMNS if c not in header]
    if missing:
        raise InvalidInputError(
            f"missing columns {missing}; expected {list(_IMU_COLUMNS)}, found {header}", path=tf.path, line=1
        )
    data, lines = parse_table(tf, 1, header, delimiter=",")
    col = {name: data[:, j] for j, name in enumerate(header)}
    zv = col["is_zero_vel"]
    bad = (zv != 0) & (zv != 1)
    if bad.any():
        i = int(np.argmax(bad))
        raise InvalidInputError(
            f"is_zero_vel={float(zv[i])!r}; expected 0 or 1", path=tf.path, line=int(lines[i]), field="is_zero_vel"
        )
    return col, lines, tf.path


def _truth(t: NDArray[np.float64], pos_z_down: NDArray[np.float64], source: str, extra: dict[str, Any]) -> FootTruth:
    return FootTruth(
        t=t,
        position=pos_z_down @ ROTATE_180_ABOUT_X.T,
        frame="azure_fgo_gt",
        meta={
            "source": source,
            "rotation": _TRUTH_ROTATION_NOTE,
            "rotation_matrix": ROTATE_180_ABOUT_X.tolist(),
            "time_alignment": "one truth row per IMU sample (time_index); the publisher does not document "
            "the IMU-to-truth alignment, a lag of a few samples is possible: compare with tolerance",
            **extra,
        },
    )


def read_azure_fgo(
    folder: Any,
    *,
    rate_hz: float = AZURE_FGO_RATE_HZ,
    full_length: bool = False,
    drop_duplicates: bool = False,
    acc_full_scale_mps2: float | None = None,
) -> Recording:
    """Read the azure_fgo recording: both feet, 60 Hz, position truth for each foot.

    Parameters
    ----------
    folder
        The folder holding the files (a path to one of its files also works).
    rate_hz
        Sampling rate; t = time_index / rate_hz (60 Hz).
    full_length
        Read the 290 s MATLAB sources instead of the 120 s CSV excerpt (no ``is_zero_vel`` there;
        the left/right column swap of ``ImuFootLeft.mat`` is undone). t = row / rate_hz.
    drop_duplicates
        Drop rows repeating the previous time index (recorded); without it they raise.
    acc_full_scale_mps2
        Accelerometer full scale for clipping detection, if known (not documented).

    Returns
    -------
    Recording
        ``left``/``right`` ImuData in SI units, sensor axes (z up at rest); ``truth_left``/
        ``truth_right`` FootTruth in m, z up (``frame="azure_fgo_gt"``, turned 180 degrees about x
        from the publisher's z-down frame), ``t`` on the IMU clock. The publisher's threshold
        zero-velocity output is in ``ImuData.meta["publisher_zero_velocity"]`` (not truth).
    """
    root = _folder_of(folder)
    if full_length:
        return _read_mat(root, rate_hz, drop_duplicates, acc_full_scale_mps2)
    paths = {k: root / v for k, v in AZURE_FGO_FILES.items()}
    for k in ("left", "right"):
        if not paths[k].exists():
            raise DataNotFoundError(f"azure_fgo IMU file {str(paths[k])!r} does not exist (folder {str(root)!r})")
    feet = {}
    for foot in ("left", "right"):
        col, lines, src = _read_imu_csv(paths[foot])
        imu, keep = build_imu(
            col["time_index"] / rate_hz,
            np.column_stack([col["acc_x"], col["acc_y"], col["acc_z"]]),
            np.column_stack([col["gyro_x"], col["gyro_y"], col["gyro_z"]]),
            path=src,
            fmt=FORMAT,
            line_numbers=lines,
            drop_duplicates=drop_duplicates,
            acc_full_scale_mps2=acc_full_scale_mps2,
            meta={"foot": foot, "time_source": f"time_index / {rate_hz:g} Hz"},
        )
        zv = col["is_zero_vel"][keep].astype(bool)
        zv.setflags(write=False)
        meta = dict(imu.meta)
        meta["publisher_zero_velocity"] = zv
        meta["publisher_zero_velocity_note"] = (
            "is_zero_vel column: the publisher's threshold detector output, not truth"
        )
        feet[foot] = replace(imu, meta=meta)

    truths: dict[str, FootTruth | None] = {"left": None, "right": None}
    files = {k: str(paths[k]) for k in ("left", "right")}
    if paths["truth"].exists():
        tf = read_text(paths["truth"], what="azure_fgo truth file")
        header = split_header(tf.lines[0], ",")
        missing = [c for c in _TRUTH_COLUMNS if c not in header]
        if missing:
            raise InvalidInputError(f"missing columns {missing}; found {header}", path=tf.path, line=1)
        data, _ = parse_table(tf, 1, header, delimiter=",")
        col = {name: data[:, j] for j, name in enumerate(header)}
        t_ref = col["time_index"] / rate_hz
        for foot in ("left", "right"):
            pos = np.column_stack([col[f"pos_{foot}_{a}"] for a in "xyz"])
            truths[foot] = _truth(t_ref, pos, tf.path, {"unit": "m"})
        files["truth"] = tf.path

    return Recording(
        left=feet["left"],
        right=feet["right"],
        truth_left=truths["left"],
        truth_right=truths["right"],
        name="azure_fgo",
        meta={
            "format": FORMAT,
            "source": str(root),
            "files": files,
            "rate_hz": rate_hz,
            "units_converted": {},
            "truth_rotation": _TRUTH_ROTATION_NOTE if truths["left"] is not None else None,
            "changes": changes_of("left", feet["left"])
            + changes_of("right", feet["right"])
            + (["truth: " + _TRUTH_ROTATION_NOTE] if truths["left"] is not None else []),
        },
    )


def _load_mat_variable(path: FilePath, name: str, ncols_min: int) -> NDArray[np.float64]:
    from scipy.io import loadmat

    if not path.exists():
        raise DataNotFoundError(f"azure_fgo file {str(path)!r} does not exist")
    try:
        mat = loadmat(path, variable_names=[name])
    except Exception as exc:  # scipy raises several types for corrupt files
        raise InvalidInputError(f"cannot read MATLAB file ({exc})", path=str(path)) from None
    if name not in mat:
        raise InvalidInputError(f"no variable {name!r}", path=str(path), field=name)
    arr = np.asarray(mat[name], dtype=np.float64)
    if arr.ndim != 2 or arr.shape[1] < ncols_min:
        raise InvalidInputError(f"expected shape (N, >={ncols_min}), got {arr.shape}", path=str(path), field=name)
    return arr


def _read_mat(root: FilePath, rate_hz: float, drop_duplicates: bool, acc_full_scale_mps2: float | None) -> Recording:
    imu_path = root / _MAT_IMU[0]
    raw = _load_mat_variable(imu_path, _MAT_IMU[1], 12)
    t = np.arange(len(raw)) / rate_hz
    feet = {}
    for foot, (a, b) in _MAT_IMU_COLUMNS.items():
        imu, _ = build_imu(
            t,
            raw[:, a : a + 3],
            raw[:, a + 3 : b],
            path=str(imu_path),
            fmt=FORMAT,
            drop_duplicates=drop_duplicates,
            acc_full_scale_mps2=acc_full_scale_mps2,
            meta={
                "foot": foot,
                "time_source": f"row / {rate_hz:g} Hz",
                "mat_columns": f"{a + 1}-{b} (1-based) of {_MAT_IMU[1]}",
            },
        )
        feet[foot] = imu
    truths = {}
    files = {"imu": str(imu_path)}
    for foot, (fname, var) in _MAT_TRUTH.items():
        p = root / fname
        pos = _load_mat_variable(p, var, 3)[:, :3]
        truths[foot] = _truth(np.arange(len(pos)) / rate_hz, pos, str(p), {"unit": "m"})
        files[f"truth_{foot}"] = str(p)
    return Recording(
        left=feet["left"],
        right=feet["right"],
        truth_left=truths["left"],
        truth_right=truths["right"],
        name="azure_fgo_full",
        meta={
            "format": FORMAT,
            "source": str(root),
            "files": files,
            "rate_hz": rate_hz,
            "column_swap": f"{_MAT_IMU[0]}: columns 1-6 = right foot, 7-12 = left foot (despite the name)",
            "undocumented_columns": raw[:, 12:].copy(),
            "csv_offset_in_mat": CSV_OFFSET_IN_MAT,
            "truth_rotation": _TRUTH_ROTATION_NOTE,
            "changes": changes_of("left", feet["left"])
            + changes_of("right", feet["right"])
            + ["truth: " + _TRUTH_ROTATION_NOTE],
        },
    )
