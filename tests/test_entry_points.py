"""footnav._numba.EntryPoints: a kernel called through its compiled entry point gives the
dispatcher's result, and a call whose other arguments differ in type is not sent to an entry
point compiled for other types."""

from __future__ import annotations

from collections import namedtuple

import numpy as np

from footnav._numba import EntryPoints, njit, type_key


@njit(cache=False)
def _scaled_sum(x, scale):
    total = 0.0
    for v in x:
        total += v * scale
    return total


def test_entry_point_gives_the_dispatchers_result_and_is_reused():
    x = np.arange(5.0)
    calls = EntryPoints(_scaled_sum)
    assert calls((x, 2.0), held=(x,), fresh=(2.0,)) == _scaled_sum(x, 2.0)
    assert len(calls) == 1
    x[:] = [1.0, 2.0, 3.0, 4.0, 5.0]  # the held array's contents change, not its type
    assert calls((x, 0.5), held=(x,), fresh=(0.5,)) == _scaled_sum(x, 0.5) == 7.5
    assert len(calls) == 1  # the same key: the entry point was used


def test_other_types_of_the_fresh_arguments_get_their_own_compilation():
    x = np.arange(4.0)
    calls = EntryPoints(_scaled_sum)
    calls((x, 2.0), held=(x,), fresh=(2.0,))
    # an integer scale: another type, hence another key (an entry point for float64 would read
    # the integer's bits as a float)
    assert calls((x, 3), held=(x,), fresh=(3,)) == _scaled_sum(x, 3) == 18.0
    assert len(calls) == 2


def test_an_array_no_longer_held_is_never_confused_with_a_new_one_at_its_address():
    calls = EntryPoints(_scaled_sum, size=2)
    for n in range(1, 6):
        x = np.ones(n, dtype=np.float32) if n % 2 else np.ones(n)  # float32 / float64 alternately
        assert calls((x, 1.0), held=(x,), fresh=(1.0,)) == float(n)
    assert len(calls) <= 2


def test_the_fresh_arguments_key_tells_apart_what_numba_types_apart():
    """type_key stands in for numba's typeof on the fresh arguments: values numba types
    differently get different keys, values it types alike the same key."""
    dispatcher = getattr(_scaled_sum, "dispatcher", lambda: _scaled_sum)()
    pair = namedtuple("pair", "a b")
    x = np.zeros((3, 4))
    readonly = x.copy()
    readonly.flags.writeable = False
    values = [
        x,
        x.T,
        x[:, ::2],
        x.astype(np.float32),
        readonly,
        np.zeros(3),
        1.0,
        1,
        2**63,
        True,
        None,
        np.float32(1.0),
        (x, 1.0),
        pair(x, 1.0),
        (x.T, 1.0),
        pair(x, None),
    ]
    for i, a in enumerate(values):
        for b in values[i + 1 :]:
            same_numba = (
                dispatcher.typeof_pyval(a) == dispatcher.typeof_pyval(b) if not (a is None or b is None) else a is b
            )
            if not same_numba:
                assert type_key(a, dispatcher) != type_key(b, dispatcher), (a, b)
    for a, b in [(x, np.ones((3, 4))), (2.0, 3.5), (1, -7), (pair(x, 1.0), pair(np.ones((5, 2)), 2.0))]:
        assert dispatcher.typeof_pyval(a) == dispatcher.typeof_pyval(b)
        assert type_key(a, dispatcher) == type_key(b, dispatcher)
