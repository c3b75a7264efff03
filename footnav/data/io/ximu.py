"""x-IMU ``CalInertialAndMag`` CSV export (x-io Technologies' x-IMU, as in the "Gait Tracking With
x-IMU" repository): one sensor, no time column.

Format::

    Packet number,Gyroscope X (deg/s),Gyroscope Y (deg/s),Gyroscope Z (deg/s),Accelerometer X (g),
    Accelerometer Y (g),Accelerometer Z (g),Magnetometer X (G),Magnetometer Y (G),Magnetometer Z (G)
    1,0.0610,-0.2136,0.0305,-0.0454,0.0029,1.0054,0.3121,-0.1154,-0.3916

* Not the ``xio`` format (x-io's newer Gait-Tracking CSV, which has a ``Time (s)`` column and no
  packet number): named ``ximu_cal``.
* No time column: t = row / ``rate_hz`` (256 Hz, the x-IMU's default CalInertialAndMag rate; the
  Gait-Tracking-With-x-IMU script uses 256 Hz). ``Packet number`` is a counter, not a time; steps
  other than its usual one are warned about (``meta["counter_irregular"]``).
* Units from the header, converted: deg/s -> rad/s, g -> m/s^2 (x ``GRAVITY_MPS2``), G (gauss)
  -> uT (x 100; footnav's magnetic field unit). The magnetometer is passed through as ``mag``.
* Body frame = the sensor's axes as logged. No truth.
"""

from __future__ import annotations

from typing import Any

from footnav.core.errors import InvalidInputError
from footnav.core.types import Recording
from footnav.data.io._text import read_text, split_header
from footnav.data.io.delimited import header_line, read_delimited, sniff_delimiter

__all__ = ["read_ximu_cal", "XIMU_CAL_HEADER", "XIMU_RATE_HZ", "is_ximu_cal_header"]

FORMAT = "ximu_cal"
#: The x-IMU's default CalInertialAndMag output rate (Hz).
XIMU_RATE_HZ = 256.0
XIMU_CAL_HEADER = (
    "Packet number",
    "Gyroscope X (deg/s)",
    "Gyroscope Y (deg/s)",
    "Gyroscope Z (deg/s)",
    "Accelerometer X (g)",
    "Accelerometer Y (g)",
    "Accelerometer Z (g)",
    "Magnetometer X (G)",
    "Magnetometer Y (G)",
    "Magnetometer Z (G)",
)
_REQUIRED = XIMU_CAL_HEADER[:7]


def is_ximu_cal_header(cells: list[str]) -> bool:
    """Whether header ``cells`` are an x-IMU CalInertialAndMag header (magnetometer optional)."""
    return tuple(cells[:7]) == _REQUIRED


def read_ximu_cal(
    path: Any, rate_hz: float = XIMU_RATE_HZ, *, drop_duplicates: bool = False, acc_full_scale_mps2: float | None = None
) -> Recording:
    """Read an x-IMU CalInertialAndMag CSV export (one sensor).

    Parameters
    ----------
    path
        The CSV file (header ``Packet number, Gyroscope X/Y/Z (deg/s), Accelerometer X/Y/Z (g),
        Magnetometer X/Y/Z (G)``).
    rate_hz
        Sampling rate: t = row index / rate_hz (default 256 Hz).
    drop_duplicates
        Accepted for a uniform reader signature (no time column: no row repeats a time).
    acc_full_scale_mps2
        Accelerometer full scale for clipping detection, if known.

    Returns
    -------
    Recording
        ``left`` = the sensor (SI, sensor axes, ``mag`` in uT when the file has it); no truth.
    """
    tf = read_text(path)
    first = header_line(tf.lines)
    cells = split_header(tf.lines[first], sniff_delimiter(tf.lines[first])) if first is not None else []
    if not is_ximu_cal_header(cells):
        raise InvalidInputError(
            f"not an x-IMU CalInertialAndMag header: expected {', '.join(XIMU_CAL_HEADER)}; found {cells}",
            path=tf.path,
            line=(first or 0) + 1,
        )
    has_mag = tuple(cells[7:10]) == XIMU_CAL_HEADER[7:10]
    columns = {"counter": [0], "gyr": [1, 2, 3], "acc": [4, 5, 6], **({"mag": [7, 8, 9]} if has_mag else {})}
    rec = read_delimited(
        path,
        columns=columns,
        rate_hz=rate_hz,
        drop_duplicates=drop_duplicates,
        acc_full_scale_mps2=acc_full_scale_mps2,
        _format=FORMAT,
    )
    return rec
