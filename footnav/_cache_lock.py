"""One process at a time in a kernel's numba cache: the index and its data saved under a file lock.

numba's on-disk cache keeps, per compiled function, an index (signature -> data file name) and
one data file per signature. Saving a new signature loads the index, picks the first free data
file name, saves the index, then the data, with no lock between processes. Two processes that
compile two signatures of one function at once (a process pool on a cold cache, a parallel
``footnav warmup``, the test suite's workers) can both pick the same name: the index then names
one signature's machine code for the other (numba/numba#4807, #10128), and a later process
loads and runs it.

:func:`serialise_cache` wraps the save and the load of one dispatcher's cache file: a save holds
an exclusive ``flock`` on ``<index>.lock`` from loading the index to writing the data, a load a
shared one, so no process reads an index whose data is not written yet. It also wraps the
dispatcher's ``compile`` (a first call with new argument types, or a caller's compilation
typing it), which holds the lock exclusively from its cache load to its save: of processes
that need one signature at once, one compiles it and the others wait and then load it, instead
of each compiling it (the suite's workers, a process pool and ``footnav warmup --jobs`` on a cold
cache). The lock is taken under numba's compiler lock, so one thread per process holds any, and
a compilation takes its callees' locks after its own: the calls between kernels have no cycle,
so neither do the waits. Where there is no ``fcntl`` (Windows) or the lock file cannot be
opened, numba's own unlocked behaviour is kept.
"""

from __future__ import annotations

import contextlib
import os
from collections.abc import Callable, Iterator
from typing import Any

try:
    import fcntl
except ImportError:  # Windows
    fcntl = None  # type: ignore[assignment]

__all__ = ["lock_path", "serialise_cache"]


def lock_path(dispatcher: Any) -> str | None:
    """The lock file of a dispatcher's cache (``<index>.lock``), or None without a cache file."""
    cache_file = getattr(getattr(dispatcher, "_cache", None), "_cache_file", None)
    index = getattr(cache_file, "_index_path", None)
    return None if index is None else index + ".lock"


#: The lock files this process holds exclusively: the load and save within a compilation take
#: no second lock (flock on another descriptor of the same file would wait for ourselves).
_held: set[str] = set()


@contextlib.contextmanager
def _flock(path: str, exclusive: bool) -> Iterator[None]:
    """Hold ``flock`` on ``path`` (created if missing); nothing held when it cannot be opened or
    when this process holds it exclusively already."""
    if path in _held:
        yield
        return
    try:
        # read-only is enough for flock, so users sharing a cache folder share its lock files
        fd = os.open(path, os.O_RDONLY | os.O_CREAT, 0o644)
    except OSError:  # no cache folder yet (a load before any save) or a read-only one
        yield
        return
    try:
        fcntl.flock(fd, fcntl.LOCK_EX if exclusive else fcntl.LOCK_SH)
        if exclusive:
            _held.add(path)
        try:
            yield
        finally:
            if exclusive:
                _held.discard(path)
    finally:
        os.close(fd)  # releases the lock


def _locked(method: Callable, path: str, exclusive: bool) -> Callable:
    def call(*args: Any) -> Any:
        with _flock(path, exclusive):
            return method(*args)

    call.__wrapped__ = method  # type: ignore[attr-defined]
    return call


def _compiling(method: Callable, path: str) -> Callable:
    from numba.core.compiler_lock import global_compiler_lock

    def compile(sig: Any) -> Any:
        with global_compiler_lock, _flock(path, exclusive=True):
            return method(sig)

    compile.__wrapped__ = method  # type: ignore[attr-defined]
    return compile


def serialise_cache(dispatcher: Any) -> Any:
    """Make ``dispatcher``'s compilations, and its cache file's saves and loads, hold the cache's
    file lock; return it.

    A dispatcher without an on-disk cache (``cache=False``), or numba's internals named otherwise
    than in the numba releases footnav supports, is returned unchanged.
    """
    path = lock_path(dispatcher)
    if fcntl is None or path is None:
        return dispatcher
    cache_file = dispatcher._cache._cache_file
    if not (callable(getattr(cache_file, "save", None)) and callable(getattr(cache_file, "load", None))):
        return dispatcher
    cache_file.save = _locked(cache_file.save, path, exclusive=True)
    cache_file.load = _locked(cache_file.load, path, exclusive=False)
    if callable(getattr(dispatcher, "compile", None)):
        dispatcher.compile = _compiling(dispatcher.compile, path)
    return dispatcher
