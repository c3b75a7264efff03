"""What the MATLAB readers share: reading a .mat file, its required variables and the (N, 6)
acc-then-gyro block with its per-sample vectors, each failure named by file and variable."""

from __future__ import annotations

from pathlib import Path as FilePath
from typing import Any

import numpy as np
from numpy.typing import NDArray

from footnav.core.errors import InvalidInputError
from footnav.data.io._text import check_file

__all__ = ["mat_imu", "mat_vector", "read_mat"]


def read_mat(path: Any, *, what: str, required: tuple[str, ...]) -> tuple[dict, FilePath]:
    """``scipy.io.loadmat`` of a checked file; InvalidInputError when it is not a MATLAB file or a
    ``required`` variable is missing (the message lists the variables found)."""
    from scipy.io import loadmat

    p = check_file(path, what=what)
    try:
        mat = loadmat(p)
    except Exception as exc:  # noqa: BLE001 -- scipy raises ValueError, TypeError, MatReadError... for bad files
        raise InvalidInputError(f"cannot read MATLAB file ({type(exc).__name__}: {exc})", path=str(p)) from None
    for name in required:
        if name not in mat:
            raise InvalidInputError(
                f"no variable {name!r}; found {sorted(k for k in mat if not k.startswith('__'))}",
                path=str(p),
                field=name,
            )
    return mat, p


def mat_imu(mat: dict, name: str, path: str) -> NDArray[np.float64]:
    """Variable ``name`` as an (N, 6) float array: acc (m/s^2) then gyro (rad/s)."""
    raw = np.asarray(mat[name], dtype=np.float64)
    if raw.ndim != 2 or raw.shape[1] != 6:
        raise InvalidInputError(f"expected shape (N, 6) = acc then gyro, got {raw.shape}", path=path, field=name)
    return raw


def mat_vector(mat: dict, name: str, n: int, path: str, *, rows_of: str = "imu") -> NDArray:
    """Variable ``name`` flattened, which must hold one value per row of ``rows_of`` (``n``)."""
    arr = np.asarray(mat[name]).reshape(-1)
    if len(arr) != n:
        raise InvalidInputError(f"has {len(arr)} values, {rows_of} has {n} rows", path=path, field=name)
    return arr
