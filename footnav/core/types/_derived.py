"""Quantities derived from a recording's read-only arrays, computed once per pipeline run.

One :meth:`footnav.Pipeline.run` looks at the same arrays several times: the input checks take
|f| and |w|, the detector the windowed RMS of |w|^2 and of (|f| - g)^2 and the swing peaks, the
stance self-check the swing peaks and the RMS of (|f| - g)^2 again. :func:`shared` keeps each
such quantity while a :func:`sharing` block is open (the pipeline opens one around its run), so
the second user gets the first one's result instead of another pass over the samples.

Only quantities of read-only arrays are kept (every ImuData array is read-only): a writable
array could change between two uses. The cache holds the arrays it was keyed by, so their ids
cannot be reused by other arrays while it is open, and it is dropped when the block closes: a
later run on the same data computes everything again (nothing lives on in the ImuData).
Outside a block every call computes afresh.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from contextlib import contextmanager
from contextvars import ContextVar
from typing import Any, TypeVar

import numpy as np
from numpy.typing import NDArray

from footnav._numba import njit
from footnav.core.types._arrays import _readonly

__all__ = ["cumulative", "row_norms", "shared", "sharing"]

T = TypeVar("T")

#: The open block's cache, ``{key: (arrays, value)}``; a context variable, so that threads (and
#: asyncio tasks) running pipelines side by side each have their own.
_CACHE: ContextVar[dict[tuple, tuple[tuple, Any]] | None] = ContextVar("footnav_shared_derivations", default=None)


@contextmanager
def sharing() -> Iterator[None]:
    """Keep the results of :func:`shared` until the block ends (nested blocks share the outer one)."""
    if _CACHE.get() is not None:
        yield
        return
    token = _CACHE.set({})
    try:
        yield
    finally:
        _CACHE.reset(token)


def shared(name: str, arrays: tuple[NDArray, ...], params: tuple, compute: Callable[[], T]) -> T:
    """``compute()``, or the value it gave for the same ``name``, ``arrays`` and ``params`` earlier
    in the open :func:`sharing` block.

    Parameters
    ----------
    name
        What is computed (one name per function of the arrays).
    arrays
        The arrays it is computed from; the value is kept only when all are read-only.
    params
        The other (hashable) arguments it depends on.
    compute
        Computes the value; what it returns (arrays, or a tuple of them) is made read-only when
        kept, since it may be handed out again.

    Returns
    -------
    The value.
    """
    cache = _CACHE.get()
    if cache is None or any(a.flags.writeable for a in arrays):
        return compute()
    key = (name, tuple(id(a) for a in arrays), params)
    hit = cache.get(key)
    if hit is not None:
        return hit[1]
    value = compute()
    # handed out again: read-only, so that a user that changed it in place would fail loudly
    for v in value if isinstance(value, tuple) else (value,):
        if isinstance(v, np.ndarray):
            v.setflags(write=False)
    cache[key] = (arrays, value)  # the arrays stay alive: their ids are not reused in the block
    return value


@njit(cache=True)
def _row_norms(x: NDArray[np.float64]) -> NDArray[np.float64]:
    out = np.empty(x.shape[0])
    for i in range(x.shape[0]):
        # left to right, as numpy's add.reduce over a row of three: bit-identical to
        # np.linalg.norm(x, axis=1), in one pass and without its (N, 3) temporary
        s = x[i, 0] * x[i, 0] + x[i, 1] * x[i, 1]
        out[i] = np.sqrt(s + x[i, 2] * x[i, 2])
    return out


def row_norms(x: NDArray[np.float64]) -> NDArray[np.float64]:
    """Euclidean norm of every row of ``x`` (N, 3), (N,); shared within a :func:`sharing` block.

    Equals ``np.linalg.norm(x, axis=1)`` bit for bit.
    """
    # read-only always (a kept input is): one compiled signature, not one per writability
    return shared("row_norms", (x,), (), lambda: _row_norms(_readonly(np.asarray(x, dtype=np.float64))))


def cumulative(x: NDArray[np.float64]) -> NDArray[np.float64]:
    """``[0, x[0], x[0] + x[1], ...]`` (N + 1, ...): window sums are differences of two entries."""
    return np.concatenate([np.zeros((1,) + x.shape[1:]), np.cumsum(x, axis=0)])
