"""Standard gravity and the units footnav converts inputs from.

Inside footnav everything is SI (m, s, rad, m/s^2, and uT for the magnetic field); readers and
:meth:`footnav.core.types.ImuData.from_arrays` convert at the edge with the scale factors here.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from footnav.core.errors import InvalidInputError

__all__ = ["GRAVITY_MPS2"]

#: Standard gravity in m/s^2 (CGPM 1901); the magnitude of the nav-frame gravity vector.
GRAVITY_MPS2 = 9.80665

_ACC_SCALE = {"m/s^2": 1.0, "g": GRAVITY_MPS2}
_GYR_SCALE = {"rad/s": 1.0, "deg/s": np.pi / 180.0}
_T_SCALE = {"s": 1.0, "ms": 1e-3, "us": 1e-6, "ns": 1e-9}
_MAG_SCALE = {"uT": 1.0, "T": 1e6, "gauss": 100.0, "a.u.": 1.0}


def _time_seconds(t: Any, t_unit: str, path: str | None) -> tuple[Any, dict[str, Any]]:
    """Time values as float seconds' input: datetime64 / timedelta64 (numpy or pandas, with or
    without a time zone) are converted here; anything else is returned for the unit scale.

    Returns ``(t, record)``: ``record`` is empty, or says what was converted (``meta["time_converted"]``).
    """
    if getattr(t, "dtype", None) is None:  # a list: see what numpy makes of it
        try:
            t = np.asarray(t)
        except (TypeError, ValueError):
            return t, {}  # ragged or odd: the float conversion names the problem
    dtype = t.dtype
    kind = getattr(dtype, "kind", None)
    if kind not in ("M", "m"):
        arr = np.asarray(t) if kind == "O" else None
        if arr is not None and arr.size and hasattr(arr.flat[0], "year"):
            raise InvalidInputError(
                "holds date/time objects; pass them as a datetime64 array (numpy.asarray(t, 'datetime64[ns]') "
                "or a pandas datetime column), which is converted to seconds since the first sample",
                field="t",
                path=path,
            )
        return t, {}
    if t_unit != "s":
        raise InvalidInputError(
            f"t is a {'datetime' if kind == 'M' else 'timedelta'} column, which carries its own unit; "
            f"t_unit={t_unit!r} contradicts it (leave t_unit at its default)",
            field="t_unit",
            path=path,
        )
    tz = getattr(getattr(t, "dt", t), "tz", None)
    if tz is not None:  # pandas, time zone aware: the same instants in UTC, without the zone
        t = t.dt.tz_convert("UTC").dt.tz_localize(None) if hasattr(t, "dt") else t.tz_convert("UTC").tz_localize(None)
    arr = np.asarray(t)
    if arr.dtype.kind not in ("M", "m"):  # a pandas extension type numpy did not keep
        arr = np.asarray(t, dtype="datetime64[ns]" if kind == "M" else "timedelta64[ns]")
    if arr.ndim != 1:
        raise InvalidInputError(f"expected shape (N,), got {arr.shape}", field="t", path=path)
    nat = np.isnat(arr)
    if nat.any():
        i = int(np.argmax(nat))
        raise InvalidInputError("missing time stamp (NaT); every sample needs a time", field="t", index=i, path=path)
    if kind == "M":
        # seconds since the first sample: absolute epoch seconds (~1.7e9) would lose the
        # microseconds in float64, and the nav solution only needs elapsed time
        secs = (arr - arr[0]) / np.timedelta64(1, "s")
        record = {
            "time_converted": f"datetime64 -> s since the first sample ({np.datetime_as_string(arr[0])}"
            + (f" {tz}" if tz is not None else "")
            + ")",
            "t0_datetime": str(np.datetime_as_string(arr[0])),
        }
    else:
        secs = arr / np.timedelta64(1, "s")
        record = {"time_converted": "timedelta64 -> s"}
    return np.asarray(secs, dtype=np.float64), record
