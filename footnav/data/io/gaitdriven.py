"""Gait-driven inertial navigation mini-data set: one foot, every footprint's position (Cetin & Koroglu 2026).

M. Cetin, M. T. Koroglu, "A Stride-Wise Annotated Mini-Dataset for Gait-Driven Learning-Based
Inertial Navigation", Turkish Journal of Electrical Engineering and Computer Sciences, 2026
(github.com/mtahakoroglu/gait-driven-inertial-navigation-dataset). LORD MicroStrain 3DM-GX5-25 on
one shoe, 200 Hz, hallway walks at paces from slow to fast.

MATLAB file ``SensorConnectData_NN_LLIO.mat`` (``scipy.io.loadmat``) per trial:

* ``imu_data`` N x 6: acc x, y, z (m/s^2) then gyro x, y, z (rad/s), sensor axes;
* ``timestamps`` 1 x N: time in s (starts at 0, ~5 ms steps); in the other published layout
  (the pyshoe re-annotation's ``*_LLIO.mat``) ``timestamps`` holds one time per stride (the
  footprints' times, checked against the samples they name) and ``timestamps_all`` 1 x N the
  per-sample times; both layouts give the same Recording (``meta["time_layout"]`` says which);
* ``strideIndex`` 1 x K: the sample at which each stride ends (the foot on the ground);
* ``GCP`` K x 2: that footprint's (x, y) in m, marked by hand on a 0.597 m floor-tile grid, the
  first footprint at the origin;
* ``traveled_distance`` (m), ``traverse_time`` (s), ``pyshoeTrajectory`` N x 2 (the publisher's
  own pyshoe SHOE + EKF trajectory, a baseline), and derived products (``euler_angles``,
  ``acc_n``, ``GCP_wcf``, ``traj_wcf``, ...) that the reader does not use.

What the data show (trials 31, 33, ..., 45, checked when this reader was written):

* ``strideIndex`` holds 0-BASED indices, although the files come from MATLAB: the publisher's CSV
  (``..._strideIndex_timestamp_gcpX_gcpY.csv``) gives each footprint's time stamp, and it equals
  ``timestamps[strideIndex]`` with 0-based indexing exactly in every trial (1-based would be off
  by one sample, 5 ms); the last ``strideIndex`` is N - 1 in every trial (the walk ends standing).
  The reader refuses an index outside ``0..N-1``.
* ``GCP`` and ``pyshoeTrajectory`` share one frame (the publisher's trajectory fits the
  footprints, after a 2-D rigid fit, to 0.3-2.3 m as stored, and to 1.4-6.0 m if only one of the
  two is mirrored). That frame is a z-DOWN navigation frame, so its x-y plane is the mirror image
  of a z-up frame's; the reader negates y of both (a mirror no rotation can undo) to give footnav's
  right-handed z-up frame, and records it in ``meta["truth_conversion"]``.
* Mountings differ between trials: at rest trials 31-37 read gravity as about (+5, +2, -8) m/s^2,
  trials 39-45 as about (-5, -2, -8) m/s^2 -- the sensor's z axis points roughly down. The
  reader keeps the sensor's axes. footnav's estimators level the body frame from gravity over
  the full circle (``roll = atan2(f_y, f_z)``, :mod:`footnav.nav.initial_alignment`), so any
  mounting is valid input; unlike :func:`~footnav.data.io.pyshoe.read_pyshoe`, which turns its
  dataset's one documented z-down mounting to z up so that every body frame of that set reads +g
  on z, there is no single mounting here to normalise to.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from footnav.core.errors import InvalidInputError
from footnav.core.types import FootTruth, Recording
from footnav.data.io._mat import mat_imu, mat_vector, read_mat
from footnav.data.io._text import build_imu, changes_of, remap_indices

__all__ = ["GAITDRIVEN_VARIABLES", "read_gaitdriven"]

FORMAT = "gaitdriven"
#: Variables that identify a gait-driven trial file (``load`` guesses the format from them).
GAITDRIVEN_VARIABLES = ("imu_data", "timestamps", "strideIndex", "GCP")
#: GCP's z-down x-y plane -> z-up: negate y.
_MIRROR_Y = np.array([1.0, -1.0])


def _scalar(mat: dict, name: str) -> float | None:
    if name not in mat:
        return None
    arr = np.asarray(mat[name], dtype=np.float64).reshape(-1)
    return float(arr[0]) if len(arr) else None


def _stride_index(mat: dict, n: int, src: str) -> NDArray[np.int64]:
    raw = np.asarray(mat["strideIndex"]).reshape(-1)
    if not np.issubdtype(raw.dtype, np.number):
        raise InvalidInputError(f"dtype {raw.dtype} is not numeric", path=src, field="strideIndex")
    val = raw.astype(np.float64)
    bad = ~np.isfinite(val) | (val != np.round(val)) | (val < 0) | (val > n - 1)
    if bad.any():
        i = int(np.argmax(bad))
        raise InvalidInputError(
            f"strideIndex {raw[i]!r} is not a 0-based sample index in 0..{n - 1} (the data set's indices are 0-based)",
            path=src,
            field="strideIndex",
            index=i,
        )
    idx = val.astype(np.int64)
    back = np.flatnonzero(np.diff(idx) <= 0)
    if len(back):
        i = int(back[0]) + 1
        raise InvalidInputError(
            f"strideIndex {idx[i]} does not follow {idx[i - 1]}; footprints must be in time order",
            path=src,
            field="strideIndex",
            index=i,
        )
    return idx


def _sample_times(mat: dict, n: int, src: str) -> tuple[NDArray[np.float64], NDArray[np.float64] | None]:
    """Per-sample times and (per-stride layout) the per-stride ones.

    Two layouts are published: ``timestamps`` with one value per sample; or ``timestamps`` with
    one value per stride (footprint) and ``timestamps_all`` with one per sample."""
    ts = np.asarray(mat["timestamps"]).reshape(-1)
    if len(ts) == n:
        return ts.astype(np.float64), None
    if "timestamps_all" not in mat:
        raise InvalidInputError(
            f"has {len(ts)} values, imu_data has {n} rows, and there is no timestamps_all (the per-sample times of "
            "the layout whose timestamps are per stride)",
            path=src,
            field="timestamps",
        )
    per_sample = mat_vector(mat, "timestamps_all", n, src, rows_of="imu_data").astype(np.float64)
    stride_ts = ts.astype(np.float64)
    bad = ~np.isfinite(stride_ts)
    if bad.any():
        raise InvalidInputError("non-finite stride time", path=src, field="timestamps", index=int(np.argmax(bad)))
    return per_sample, stride_ts


def _index_of_times(stride_ts: NDArray[np.float64], ts: NDArray[np.float64], src: str) -> NDArray[np.int64]:
    """Sample index nearest to each per-stride time (within half a sampling interval)."""
    dt = float(np.median(np.diff(ts)))
    j = np.clip(np.searchsorted(ts, stride_ts), 1, len(ts) - 1)
    j = np.where(np.abs(ts[j - 1] - stride_ts) <= np.abs(ts[j] - stride_ts), j - 1, j)
    off = np.abs(ts[j] - stride_ts) > 0.5 * dt
    if off.any():
        i = int(np.argmax(off))
        raise InvalidInputError(
            f"stride time {stride_ts[i]!r} s is no sample time of timestamps_all ({ts[0]!r} .. {ts[-1]!r} s)",
            path=src,
            field="timestamps",
            index=i,
        )
    return j.astype(np.int64)


def _check_stride_times(
    stride_ts: NDArray[np.float64], ts: NDArray[np.float64], idx: NDArray[np.int64], src: str
) -> None:
    """Per-stride times must be the times of the footprint samples (one per strideIndex)."""
    if len(stride_ts) != len(idx):
        raise InvalidInputError(
            f"has {len(stride_ts)} values (per stride), strideIndex has {len(idx)}", path=src, field="timestamps"
        )
    dt = float(np.median(np.diff(ts)))
    off = np.abs(ts[idx] - stride_ts) > 0.5 * dt
    if off.any():
        i = int(np.argmax(off))
        raise InvalidInputError(
            f"stride time {stride_ts[i]!r} s differs from timestamps_all[strideIndex[{i}]] = {ts[idx[i]]!r} s by more "
            "than half a sampling interval",
            path=src,
            field="timestamps",
            index=i,
        )


def read_gaitdriven(path: Any, *, drop_duplicates: bool = False, acc_full_scale_mps2: float | None = None) -> Recording:
    """Read one trial of the gait-driven mini-data set (Cetin & Koroglu, Turk. J. EE&CS 2026).

    Parameters
    ----------
    path
        The trial's ``*_LLIO.mat`` (either time layout: ``timestamps`` per sample, or per stride
        with ``timestamps_all`` per sample).
    drop_duplicates
        Drop samples repeating the previous time stamp (footprint indices are remapped); else
        they raise.
    acc_full_scale_mps2
        Accelerometer full scale for clipping detection, if known.

    Returns
    -------
    Recording
        ``left`` = the one foot (SI, sensor axes kept, ``meta["foot"]`` unknown);
        ``truth_left`` = :class:`FootTruth` with ``frame="footprints"``: ``t =
        timestamps[strideIndex]`` (s), ``position = [GCP_x, -GCP_y, 0]`` (m, z up; y negated,
        see the module docstring), ``events["footprint"] = strideIndex`` (0-based sample
        indices), ``meta["traveled_distance_m"]``, ``meta["pyshoe_trajectory"]`` (N, 2) = the
        publisher's pyshoe trajectory with y negated the same way, a baseline.

    Raises
    ------
    InvalidInputError
        Not a MATLAB file, a variable missing or of the wrong shape, a footprint index outside
        the recording (named: path, field, first bad index).
    """
    mat, p = read_mat(path, what="gait-driven .mat file", required=("imu_data", "timestamps"))
    src = str(p)
    raw = mat_imu(mat, "imu_data", src)
    n = len(raw)
    ts, stride_ts = _sample_times(mat, n, src)
    imu, keep = build_imu(
        ts,
        raw[:, :3],
        raw[:, 3:],
        path=src,
        fmt=FORMAT,
        drop_duplicates=drop_duplicates,
        acc_full_scale_mps2=acc_full_scale_mps2,
        meta={
            "foot": "unknown (one foot)",
            "body_rotation": {
                "applied": None,
                "sensor_frame": "sensor axes kept; the mounting differs between trials (estimators level from gravity)",
            },
        },
    )

    truth = None
    if "GCP" in mat and ("strideIndex" in mat or stride_ts is not None):
        if "strideIndex" in mat:
            idx_file = _stride_index(mat, n, src)
            index_source = "strideIndex"
        else:  # per-stride layout without strideIndex: the sample at each footprint's time
            idx_file = _index_of_times(stride_ts, ts, src)
            index_source = "timestamps (per stride) matched to timestamps_all"
        if stride_ts is not None:
            _check_stride_times(stride_ts, ts, idx_file, src)
        gcp = np.asarray(mat["GCP"], dtype=np.float64)
        if gcp.shape != (len(idx_file), 2):
            raise InvalidInputError(
                f"expected shape ({len(idx_file)}, 2) (one (x, y) per strideIndex), got {gcp.shape}",
                path=src,
                field="GCP",
            )
        bad = ~np.isfinite(gcp).all(axis=1)
        if bad.any():
            i = int(np.argmax(bad))
            raise InvalidInputError(f"non-finite footprint {gcp[i].tolist()}", path=src, field="GCP", index=i)
        idx = remap_indices(idx_file, keep)
        xy = gcp * _MIRROR_Y + 0.0  # + 0.0: no -0.0 from negating the origin
        meta: dict[str, Any] = {
            "source": src,
            "position_source": (
                "footprints marked by hand on a 0.597 m floor-tile grid (GCP), one per strideIndex; compare the "
                "estimate at those samples after one 2-D rigid fit (footnav.analysis.metrics.footprint_errors)"
            ),
            "truth_conversion": {
                "mirror_y": True,
                "why": "GCP and pyshoeTrajectory are in a z-down navigation frame whose x-y plane mirrors a z-up "
                "frame's; y negated for both",
            },
            "stride_index_base": 0,
            "stride_index_source": index_source,
            "time_layout": "timestamps per stride, timestamps_all per sample"
            if stride_ts is not None
            else "timestamps per sample",
            "stride_index_file": idx_file,
            "gcp_as_stored": gcp,
            "reference": "Cetin & Koroglu, A Stride-Wise Annotated Mini-Dataset for Gait-Driven Learning-Based "
            "Inertial Navigation, Turk. J. EE&CS 2026",
        }
        dist = _scalar(mat, "traveled_distance")
        if dist is not None:
            meta["traveled_distance_m"] = dist
        ttime = _scalar(mat, "traverse_time")
        if ttime is not None:
            meta["traverse_time_s"] = ttime
        if "pyshoeTrajectory" in mat:
            pt = np.asarray(mat["pyshoeTrajectory"], dtype=np.float64)
            if pt.shape != (n, 2):
                raise InvalidInputError(f"expected shape ({n}, 2), got {pt.shape}", path=src, field="pyshoeTrajectory")
            meta["pyshoe_trajectory"] = pt[keep] * _MIRROR_Y
        truth = FootTruth(
            t=imu.t[idx],
            position=np.column_stack((xy, np.zeros(len(xy)))),
            events={"footprint": idx},
            frame="footprints",
            meta=meta,
        )

    changes = changes_of("foot", imu)
    if truth is not None:
        changes.append("truth: GCP and pyshoeTrajectory y negated (z-down frame's mirrored x-y plane -> z up)")
    return Recording(
        left=imu,
        truth_left=truth,
        name=p.stem,
        meta={"format": FORMAT, "source": src, "units_converted": imu.meta["units_converted"], "changes": changes},
    )
