"""Per-sample arrays laid out so that the compiled loops do not trip over 4K aliasing.

The filter's loops read and write row k of a dozen arrays per sample (inputs, outputs, the
smoother's record). Large numpy arrays each come from their own mmap, so they all start at the
same offset within a 4 KiB page; arrays with equal row strides (velocity and position, 24 bytes)
then keep the same low 12 address bits at every k. A load after a store to such an address is
held back by the CPU as if it depended on the store (4K aliasing), and the arrays compete for
the same L1 cache sets. Carving the arrays out of one buffer at staggered page offsets avoids
both: on a 10-minute walk the step-wise smoothed EKF went from 0.57-0.69 to 0.42-0.46 us/sample
(docs/performance.md).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import DTypeLike, NDArray

__all__ = ["staggered"]

_PAGE = 4096
_LINE = 64
#: Page offset between consecutive arrays: 7 cache lines, so 9 arrays fall on 9 distinct offsets
#: before the pattern wraps (64 distinct offsets in all).
_STAGGER = 7 * _LINE


def staggered(
    specs: Sequence[tuple[tuple[int, ...], DTypeLike]], *, zero: bool = False, first: int = 0
) -> list[NDArray]:
    """C-contiguous, writable arrays of the given (shape, dtype), each starting at a different
    offset within a memory page and aligned to a cache line, all views of one buffer.

    Parameters
    ----------
    specs
        (shape, dtype) of each array.
    zero
        Fill with zeros (else uninitialised, like :func:`numpy.empty`).
    first
        Place of the first array in the pattern of offsets: arrays of another call that the same
        loop touches (the filter's outputs and the smoother's) take places after this call's.

    Returns
    -------
    list of ndarray
        One array per spec; they share one buffer (kept alive by each array's ``base``).
    """
    starts, end = [], 0
    for i, (shape, dtype) in enumerate(specs):
        size = int(np.prod(shape, dtype=np.int64)) * np.dtype(dtype).itemsize
        start = -(-end // _PAGE) * _PAGE + ((first + i) * _STAGGER) % _PAGE
        starts.append((start, size))
        end = start + size
    buf = (np.zeros if zero else np.empty)(end + _PAGE, dtype=np.uint8)
    base = (-buf.ctypes.data) % _PAGE  # page-aligned origin: the offsets above are what they say
    return [
        buf[base + start : base + start + size].view(np.dtype(dtype)).reshape(shape)
        for (start, size), (shape, dtype) in zip(starts, specs)
    ]
