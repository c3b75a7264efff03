"""Array checks the data types share: float64 conversion naming the bad field and index, read-only arrays."""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from footnav.core.errors import InvalidInputError


def _readonly(a: NDArray) -> NDArray:
    """``a`` as a C-contiguous array that cannot be written: a read-only view when it already is
    C-contiguous (no copy, and the caller's own array keeps its flags), else a read-only copy."""
    a = np.ascontiguousarray(a)
    if a.flags.writeable:
        a = a.view()
        a.setflags(write=False)
    return a


def _as_float_array(
    value: Any, name: str, ncols: int | None, path: str | None, *, offset: int = 0
) -> NDArray[np.float64]:
    """``value`` as float64 of shape (N,) (``ncols`` None) or (N, ncols), every value finite.

    The error names the field, the file and the first bad sample; ``offset`` is added to the
    index (a chunk of a stream: its first sample's index in the stream)."""
    try:
        arr = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise InvalidInputError(f"cannot convert to float64 ({exc})", field=name, path=path) from None
    if ncols is None:
        if arr.ndim != 1:
            raise InvalidInputError(f"expected shape (N,), got {arr.shape}", field=name, path=path)
    elif arr.ndim != 2 or arr.shape[1] != ncols:
        transposed = arr.ndim == 2 and arr.shape[0] == ncols and arr.shape[1] != ncols
        raise InvalidInputError(
            f"expected shape (N, {ncols}), got {arr.shape}"
            + ("; transposed? one row per sample" if transposed else ""),
            field=name,
            path=path,
        )
    if not np.isfinite(arr).all():  # one flat reduction first: the per-row one only to name the row
        bad = ~np.isfinite(arr)
        first = int(np.argmax(bad.reshape(len(arr), -1).any(axis=1)))
        raise InvalidInputError(
            f"non-finite value {arr[first]!r}; every sample must be finite", field=name, index=offset + first, path=path
        )
    return arr
