"""Staggered per-sample arrays: distinct page offsets, no overlap, usable as ordinary arrays."""

import numpy as np
import pytest

from footnav.estimators.ekf._buffers import staggered


def _span(a):
    return a.ctypes.data, a.ctypes.data + a.nbytes


@pytest.mark.parametrize("first", [0, 8])
def test_arrays_start_at_distinct_page_offsets_and_do_not_overlap(first):
    specs = [
        ((5000, 3), np.float64),
        ((5000, 3), np.float64),
        ((5000,), np.bool_),
        ((7, 9, 6), np.float64),
        ((3,), np.int64),
    ]
    arrays = staggered(specs, first=first, zero=True)
    offsets = [a.ctypes.data % 4096 for a in arrays]
    assert len(set(offsets)) == len(arrays)
    assert all(o % 64 == 0 for o in offsets)  # cache-line aligned
    spans = sorted(_span(a) for a in arrays)
    assert all(end <= start for (_, end), (start, _) in zip(spans, spans[1:]))
    for a, (shape, dtype) in zip(arrays, specs):
        assert a.shape == shape and a.dtype == dtype
        assert a.flags.c_contiguous and a.flags.writeable
        assert not a.any()
    # writing one array leaves the others alone
    arrays[0][:] = 1.0
    assert not arrays[1].any() and not arrays[3].any()


def test_a_later_call_continues_the_pattern():
    a = staggered([((1000,), np.float64)] * 3)
    b = staggered([((1000,), np.float64)] * 2, first=3)
    offsets = [x.ctypes.data % 4096 for x in a + b]
    assert len(set(offsets)) == 5


def test_empty_arrays_are_allowed():
    (a,) = staggered([((0, 3), np.float64)])
    assert a.shape == (0, 3)
