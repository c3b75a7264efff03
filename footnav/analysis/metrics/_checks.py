"""Input checks shared by the metrics: positions, points, event indices and masks as finite float64
arrays (InvalidInputError naming the argument and the first bad index), and small helpers."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from footnav.core.errors import InvalidInputError, InvalidParameterError

# the one copy of the read-only, C-contiguous view, re-exported to the metrics
from footnav.core.types._arrays import _readonly  # noqa: F401

#: Percent per unit fraction.
_PERCENT = 100.0

_VALID_DIMS = (2, 3)


def _check_dims(dims: int) -> int:
    if dims not in _VALID_DIMS:
        raise InvalidParameterError(f"dims must be 2 (horizontal x, y) or 3 (x, y, z), got {dims!r}")
    return int(dims)


def _finite(arr: NDArray, name: str) -> None:
    bad = ~np.isfinite(arr)
    if bad.any():
        first = int(np.argmax(bad.reshape(len(arr), -1).any(axis=1)))
        raise InvalidInputError(f"non-finite value {arr[first]!r}; every value must be finite", field=name, index=first)


def _float64(value: ArrayLike, name: str) -> NDArray[np.float64]:
    """``value`` as a float64 array; InvalidInputError naming ``name`` if it is not numeric."""
    try:
        return np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise InvalidInputError(f"cannot convert to float64 ({exc})", field=name) from None


def _points(value: ArrayLike, name: str, dims: int, *, min_rows: int = 1) -> NDArray[np.float64]:
    """``value`` as a finite float64 (N, D) position array with D >= dims and N >= min_rows."""
    arr = _float64(value, name)
    if arr.ndim != 2 or arr.shape[1] < dims or arr.shape[1] > 3:
        raise InvalidInputError(
            f"expected positions in m of shape (N, {dims})"
            + (" or (N, 3)" if dims == 2 else "")
            + f", got {arr.shape}",
            field=name,
        )
    if len(arr) < min_rows:
        what = "is empty" if len(arr) == 0 else f"has {len(arr)} row(s)"
        raise InvalidInputError(f"{what}; need at least {min_rows} position(s)", field=name)
    _finite(arr, name)
    return arr


def _point(value: ArrayLike, name: str, dims: int) -> NDArray[np.float64]:
    """A single position (D,), or the last row of an (N, D) trajectory."""
    arr = _float64(value, name)
    if arr.ndim == 1:
        arr = arr[None, :]
    return _points(arr, name, dims)[-1]


def _same_length(a: NDArray, b: NDArray, name_a: str, name_b: str) -> None:
    if len(a) != len(b):
        raise InvalidInputError(
            f"has {len(b)} rows but {name_a!r} has {len(a)}; the rows must correspond one to one "
            "(same time stamps; resample with interpolate_positions)",
            field=name_b,
        )


def _events(value: ArrayLike, name: str) -> NDArray:
    """Event positions (samples) as a finite 1-D array; empty is allowed (no events)."""
    try:
        arr = np.asarray(value)
        if arr.dtype == bool or not np.issubdtype(arr.dtype, np.number):
            raise TypeError(f"dtype {arr.dtype} is not numeric (pass event indices, not a mask)")
    except (TypeError, ValueError) as exc:
        raise InvalidInputError(f"cannot read event indices ({exc})", field=name) from None
    if arr.ndim != 1:
        raise InvalidInputError(f"expected event indices of shape (K,), got {arr.shape}", field=name)
    if not np.issubdtype(arr.dtype, np.integer):
        arr = arr.astype(np.float64)
        _finite(arr, name)
    return arr


def _mask(value: ArrayLike, name: str) -> NDArray[np.bool_]:
    try:
        arr = np.asarray(value)
    except (TypeError, ValueError) as exc:  # pragma: no cover - numpy accepts almost anything
        raise InvalidInputError(f"cannot read mask ({exc})", field=name) from None
    if arr.ndim != 1:
        raise InvalidInputError(f"expected a per-sample mask of shape (N,), got {arr.shape}", field=name)
    if len(arr) == 0:
        raise InvalidInputError("is empty; need at least one sample", field=name)
    if arr.dtype != bool:
        if not np.issubdtype(arr.dtype, np.number):
            raise InvalidInputError(f"dtype {arr.dtype} is not boolean or numeric", field=name)
        _finite(arr.astype(np.float64), name)
        bad = (arr != 0) & (arr != 1)
        if bad.any():
            i = int(np.argmax(bad))
            raise InvalidInputError(f"value {arr[i]!r} is not 0/1 or boolean", field=name, index=i)
    return arr.astype(bool)


def _percent(num: float, den: float) -> float:
    # nan, not inf or an error, when the denominator is zero: the metric is undefined there
    return float(_PERCENT * num / den) if den > 0 else float("nan")
