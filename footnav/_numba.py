"""numba's ``njit`` for footnav's kernels, so that importing footnav never needs a writable cache.

footnav's kernels are compiled with ``@njit(cache=True)``: numba saves the machine code and the
next process loads it instead of compiling again (about ten seconds for the whole package).
numba looks for a writable cache folder in ``NUMBA_CACHE_DIR``, then ``__pycache__`` next to the
sources, then the user's cache folder under ``HOME``, and when none of them is writable (a
read-only installation run by a user without a writable home: containers, shared servers,
CI sandboxes) it raises ``RuntimeError: cannot cache function ...: no locator available`` while
the module is being imported, so ``import footnav`` failed.

:func:`njit` makes each kernel with ``numba.njit`` unchanged wherever numba finds a cache folder. Only where it
finds none does it compile the kernel with a private cache folder in the system's temporary
directory (``footnav-numba-cache-<uid>``, created mode 0700 and used only when it is a real
folder owned by this user that nobody else can write), or, when there is no such folder, without
a cache. Then it says so once per process with a ``logging`` WARNING on ``footnav._numba``.

Why logging and not a :class:`~footnav.FootnavWarning`: the notice is about the installation,
not about the data or the call. Components are imported lazily, so a warning could be raised
inside ``Pipeline.run`` and land in that run's ``meta["warnings"]`` and ``summary.json``, making
the provenance of the same data depend on the machine. A logging WARNING reaches stderr even when
the application configured no logging (Python's last-resort handler) and stays out of results.

The private folder is checked because numba's cache files are pickles that are loaded as they
are: a folder another user could write into would let that user run code in this process.

Each kernel's cache is saved and loaded under a file lock (:mod:`footnav._cache_lock`), so that
processes compiling at once cannot mix up its signatures.

Each kernel is created on first use (:class:`LazyKernel`): ``import footnav`` imports no numba
(0.12-0.15 s) and a process pays numba's per-function set-up only for the kernels it calls.
"""

from __future__ import annotations

import functools
import logging
import os
import stat
import tempfile
import threading
import types
from collections.abc import Callable
from typing import Any

import numpy as np

from footnav._cache_lock import serialise_cache

__all__ = ["LazyKernel", "fallback_cache_dir", "njit"]

log = logging.getLogger(__name__)

_NO_LOCATOR = "no locator available"
_lock = threading.RLock()  # re-entered: a kernel creates the kernels it calls
#: ``None`` until the first fallback; then ``(path or None,)`` so the folder is checked only once.
_fallback: tuple[str | None] | None = None


def fallback_cache_dir() -> str | None:
    """The private cache folder used when numba has no writable cache folder, or None.

    ``<tempdir>/footnav-numba-cache-<uid>``, created with mode 0700. It is returned only when it
    is a folder (not a symbolic link) owned by the current user, not writable by group or others,
    and writable by us; otherwise None (footnav then compiles without a cache).

    Returns
    -------
    str or None
        The folder, or None when no safe writable folder exists.
    """
    try:
        base = tempfile.gettempdir()  # FileNotFoundError when no temporary folder is writable
        uid = os.getuid() if hasattr(os, "getuid") else None
        path = os.path.join(base, f"footnav-numba-cache-{uid if uid is not None else 'user'}")
        try:
            os.mkdir(path, 0o700)
        except FileExistsError:
            pass
        info = os.lstat(path)
        if not stat.S_ISDIR(info.st_mode):
            return None
        # On POSIX the temporary directory is shared between users: refuse a folder someone else
        # made or can write into (see the module docstring). Windows has a per-user temp folder.
        if uid is not None and (info.st_uid != uid or info.st_mode & 0o022):
            return None
        tempfile.TemporaryFile(dir=path).close()  # the check numba itself makes
        return path
    except OSError:
        return None


def _fallback_dir_once(func: Callable) -> str | None:
    """Find the fallback folder on the first call and log the one notice of the process.

    Called with ``_lock`` held, so two threads making kernels log one notice.
    """
    global _fallback
    if _fallback is None:
        path = fallback_cache_dir()
        _fallback = (path,)
        where = (
            f"caching compiled code in {path} instead"
            if path is not None
            else "compiling without a cache (every process compiles again, about 10 s)"
        )
        log.warning(
            "numba has no writable cache folder for %s (read-only installation, no writable HOME "
            "and NUMBA_CACHE_DIR not set); %s. Set NUMBA_CACHE_DIR to a writable folder to choose one.",
            os.path.dirname(func.__code__.co_filename),
            where,
        )
    return _fallback[0]


def njit(*args: Any, **options: Any) -> Any:
    """``numba.njit`` that falls back to a private or no cache when numba has no cache folder.

    Used exactly like ``numba.njit`` (``@njit`` or ``@njit(cache=True, ...)``); returns a
    :class:`LazyKernel` that creates numba's dispatcher on first use. With ``cache=True`` and no
    writable cache folder, the function is compiled with
    the cache in :func:`fallback_cache_dir`, or without a cache when that is None, and one
    ``logging`` WARNING per process says which.

    Parameters
    ----------
    *args
        The function (``@njit`` without parentheses), or numba's signatures.
    **options
        numba.njit's options, passed on unchanged.

    Returns
    -------
    LazyKernel or decorator
        Stands for what ``numba.njit`` returns for the same arguments.
    """
    if len(args) == 1 and callable(args[0]) and not isinstance(args[0], str) and not options:
        return LazyKernel(args[0], (), {})

    def decorate(func: Callable) -> Any:
        return LazyKernel(func, args, options)

    return decorate


class LazyKernel:
    """A compiled kernel whose numba dispatcher is made on first use (call or attribute).

    Before the dispatcher is made, every kernel the function names (its globals, attributes of
    modules it names, its closure) is made too and put in place of its LazyKernel, so that numba
    compiling the function sees dispatchers, as it would with ``numba.njit`` (inlining
    ``inline="always"`` callees included). Attributes (``signatures``, ``py_func``, ...) are the
    dispatcher's; numba types a LazyKernel passed as an argument as its dispatcher.
    """

    def __init__(self, func: Callable, signatures: tuple, options: dict[str, Any]) -> None:
        functools.update_wrapper(self, func)
        self._func = func
        self._signatures = signatures
        self._options = options
        self._dispatcher: Any = None
        self._busy = False

    def dispatcher(self) -> Any:
        """numba's dispatcher for this kernel, made on the first call."""
        if self._dispatcher is None:
            with _lock:
                if self._dispatcher is None and not self._busy:
                    self._busy = True  # a kernel naming itself (recursion) is made once
                    try:
                        _resolve_kernels(self._func)
                        made = _compile(self._func, self._signatures, self._options)
                        if self._func.__globals__.get(self._func.__name__) is self:
                            self._func.__globals__[self._func.__name__] = made
                        self._dispatcher = made
                    finally:
                        self._busy = False
        return self._dispatcher

    def __call__(self, *args: Any, **kwargs: Any) -> Any:
        return self.dispatcher()(*args, **kwargs)

    def __getattr__(self, name: str) -> Any:
        if name.startswith("__") or name in ("_func", "_signatures", "_options", "_dispatcher", "_busy"):
            raise AttributeError(name)  # not set yet (copy, pickle): never make the dispatcher for these
        return getattr(self.dispatcher(), name)

    def __get__(self, obj: Any, objtype: Any = None) -> Any:
        # as numba's dispatcher: a kernel stored on a class binds like a method
        return self if obj is None else types.MethodType(self, obj)

    def __reduce__(self) -> Any:
        return self.dispatcher().__reduce__()

    @property
    def _numba_type_(self) -> Any:  # numba's typeof() of any object reads this
        return self.dispatcher()._numba_type_

    def __repr__(self) -> str:
        state = "made" if self._dispatcher is not None else "not made yet"
        return f"<footnav kernel {self.__module__}.{self.__qualname__} ({state})>"


class EntryPoints:
    """A kernel called through numba's compiled entry point for arguments it has seen before.

    numba's dispatcher types every argument at every call (the EKF's loop: some 60 arrays,
    38 us a call against 12 us for the entry point). A caller that calls a kernel many times with
    the same long-lived arguments names them ``held`` (objects it owns and never changes the type
    of: arrays, tuples of arrays); they are keyed by identity and kept here, so their ids cannot
    be reused. Every other argument (``fresh``) is keyed by its type as numba would see it
    (:func:`type_key`), so a call whose types differ goes through the dispatcher, and compiles,
    as usual.
    """

    def __init__(self, kernel: Any, size: int = 8) -> None:
        self._kernel = kernel
        self._size = size
        self._calls: dict[tuple, tuple] = {}

    def __len__(self) -> int:
        return len(self._calls)

    def __call__(self, args: tuple, held: tuple, fresh: tuple) -> Any:
        """``kernel(*args)``; ``held`` and ``fresh`` together are everything ``args`` holds."""
        kernel = self._kernel
        dispatcher = kernel.dispatcher() if isinstance(kernel, LazyKernel) else kernel
        key = (*map(id, held), *(type_key(a, dispatcher) for a in fresh))
        hit = self._calls.get(key)
        if hit is not None:
            return hit[0](*args)
        result = kernel(*args)
        compiled = dispatcher.overloads.get(tuple(dispatcher.typeof_pyval(a) for a in args))
        if compiled is not None:
            if len(self._calls) >= self._size:  # buffers replaced: the old keys are dead
                self._calls.clear()
            self._calls[key] = (compiled.entry_point, held)
        return result


_MAX_INT64 = 2**63


def type_key(x: Any, dispatcher: Any) -> Any:
    """What tells apart the numba types of ``x``, without numba's typing for the common kinds:
    an ndarray by its dtype, dimensions, layout, writeable and aligned flags (numba's Array type);
    a tuple (a namedtuple too) by its class and items; None, bool, float and numpy scalars by their
    type; an int by whether int64 holds it. Anything else: ``dispatcher.typeof_pyval`` (numba's
    typeof of a tuple of arrays took 30 us, as long as the EKF's compiled loop on a chunk).
    """
    kind = type(x)
    if kind is np.ndarray:
        flags = x.flags
        return (kind, x.dtype.str, x.ndim, flags.c_contiguous, flags.f_contiguous, flags.writeable, flags.aligned)
    if isinstance(x, tuple):
        return (kind, *(type_key(item, dispatcher) for item in x))
    if x is None or kind is bool or kind is float or isinstance(x, np.generic):
        return kind
    if kind is int:
        return (kind, -_MAX_INT64 <= x < _MAX_INT64)
    return dispatcher.typeof_pyval(x)


def _names(code: types.CodeType) -> set[str]:
    """Every name ``code`` and the functions defined inside it look up (globals, attributes)."""
    names = set(code.co_names)
    for const in code.co_consts:
        if isinstance(const, types.CodeType):
            names |= _names(const)
    return names


def _resolve_kernels(func: Callable) -> None:
    """Make the kernels ``func`` names and put their dispatchers in place of the LazyKernels."""
    names = _names(func.__code__)
    scope = func.__globals__
    for name in names:
        value = scope.get(name)
        if isinstance(value, LazyKernel) and not value._busy:
            scope[name] = value.dispatcher()
        elif isinstance(value, types.ModuleType):  # ``quat.quat_mul(...)``
            for attr in names:
                member = value.__dict__.get(attr)
                if isinstance(member, LazyKernel) and not member._busy:
                    setattr(value, attr, member.dispatcher())
    for cell in func.__closure__ or ():
        try:
            value = cell.cell_contents
        except ValueError:  # an empty cell
            continue
        if isinstance(value, LazyKernel) and not value._busy:
            cell.cell_contents = value.dispatcher()


def _compile(func: Callable, signatures: tuple, options: dict[str, Any]) -> Any:
    """Apply numba.njit; on "no locator available", retry with the fallback folder or no cache."""
    import numba  # here: importing numba takes 0.12-0.15 s, which ``import footnav`` does without
    from numba.core import config as _numba_config

    try:
        return serialise_cache(numba.njit(*signatures, **options)(func))
    except RuntimeError as exc:
        if not options.get("cache") or _NO_LOCATOR not in str(exc):
            raise
    # numba reads config.CACHE_DIR (NUMBA_CACHE_DIR) when the dispatcher picks its cache folder,
    # i.e. here, and keeps that folder for the function. Setting it only around this call keeps
    # every other numba user of the process (and NUMBA_CACHE_DIR in os.environ) untouched; the
    # lock keeps two threads making kernels from restoring each other's value.
    # Without a safe folder: compile without a cache rather than fail the import.
    with _lock:
        path = _fallback_dir_once(func)
        if path is None:
            return numba.njit(*signatures, **{**options, "cache": False})(func)
        saved = _numba_config.CACHE_DIR
        _numba_config.CACHE_DIR = path
        try:
            return serialise_cache(numba.njit(*signatures, **options)(func))
        finally:
            _numba_config.CACHE_DIR = saved
