"""OpenShoe data set text file (vdouet/OpenShoe_C): one foot at 820 Hz, no header.

Format: one sample per line, 6 comma-separated numbers ``acc_x, acc_y, acc_z`` (m/s^2),
``gyr_x, gyr_y, gyr_z`` (rad/s), in the sensor's axes (z up: +g on z at rest). There is no time
column: t = row index / rate_hz. No truth.
"""

from __future__ import annotations

from pathlib import Path as FilePath
from typing import Any

import numpy as np

from footnav.core.types import Recording
from footnav.data.io._text import build_imu, changes_of, parse_table, read_text

__all__ = ["read_openshoe", "OPENSHOE_RATE_HZ", "OPENSHOE_COLUMNS"]

FORMAT = "openshoe"
#: Sampling rate of the OpenShoe hardware the data set was recorded with.
OPENSHOE_RATE_HZ = 820.0
OPENSHOE_COLUMNS = ("acc_x", "acc_y", "acc_z", "gyr_x", "gyr_y", "gyr_z")


def read_openshoe(
    path: Any,
    rate_hz: float = OPENSHOE_RATE_HZ,
    *,
    drop_duplicates: bool = False,
    acc_full_scale_mps2: float | None = None,
) -> Recording:
    """Read an OpenShoe data set file (one foot, no header, no time column).

    Parameters
    ----------
    path
        Text file of 6 comma-separated columns acc (m/s^2) then gyro (rad/s).
    rate_hz
        Sampling rate: t = row index / rate_hz (820 Hz).
    drop_duplicates
        Accepted for a uniform reader signature; without a time column no row can repeat a time
        stamp, so it has no effect (identical consecutive rows are legitimate quantised samples).
    acc_full_scale_mps2
        Accelerometer full scale for clipping detection, if known. Not documented for this data
        set; without it only the plateau rule (a large extreme value repeated) applies.

    Returns
    -------
    Recording
        ``left`` = the foot, SI units, sensor axes; no truth. ``meta["acc_max_abs_mps2"]`` gives
        the largest accelerometer reading (about 17 g in the published file).
    """
    tf = read_text(path)
    data, lines = parse_table(tf, 0, OPENSHOE_COLUMNS, delimiter=",")
    t = np.arange(len(data)) / rate_hz
    imu, _ = build_imu(
        t,
        data[:, 0:3],
        data[:, 3:6],
        path=tf.path,
        fmt=FORMAT,
        line_numbers=lines,
        drop_duplicates=drop_duplicates,
        acc_full_scale_mps2=acc_full_scale_mps2,
        meta={
            "foot": "unknown (one foot)",
            "time_source": f"row index / {rate_hz:g} Hz (the file has no time column)",
            "acc_max_abs_mps2": float(np.abs(data[:, 0:3]).max()),
        },
    )
    return Recording(
        left=imu,
        name=FilePath(tf.path).stem,
        meta={
            "format": FORMAT,
            "source": tf.path,
            "rate_hz": rate_hz,
            "units_converted": imu.meta["units_converted"],
            "changes": changes_of("foot", imu),
        },
    )
