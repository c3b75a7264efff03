"""The numba cache folder of a test run, keyed by the contents of footnav's sources (issue 17).

numba's on-disk cache (``@njit(cache=True)``) checks only the timestamp and size of the file that
defines a kernel. A kernel that calls a compiled helper from another module keeps its cached
machine code when only the helper changes: the checkout then runs the old helper, and the tests
pass on code that no longer exists.

The suite therefore caches in ``<tmp>/footnav-test-numba-<uid>-<key>``, where ``<key>`` is a
SHA-256 over the relative path and the bytes of every ``footnav/**/*.py``: any change to any
source gives a fresh, empty folder (everything recompiles once, about ten seconds per process),
and an unchanged tree reuses its folder. ``tests/conftest.py`` sets ``NUMBA_CACHE_DIR`` to it
before numba is imported, unless ``NUMBA_CACHE_DIR`` is already set.

This module imports neither numba nor footnav: footnav's first kernel imports numba, and numba reads
``NUMBA_CACHE_DIR`` once, at its import.
"""

from __future__ import annotations

import hashlib
import importlib.util
import os
import stat
import tempfile
import time
from pathlib import Path

__all__ = ["footnav_source_dir", "source_key", "numba_cache_dir"]

PREFIX = "footnav-test-numba-"
#: Sibling folders of older trees unused for this long are removed when a new folder is made.
STALE_AFTER_S = 7 * 24 * 3600.0


def footnav_source_dir() -> Path:
    """The folder of the footnav package the tests will import, found without importing it."""
    spec = importlib.util.find_spec("footnav")
    if spec is not None and spec.submodule_search_locations:
        return Path(next(iter(spec.submodule_search_locations))).resolve()
    return Path(__file__).resolve().parents[1] / "footnav"


def source_key(package_dir: Path | str, length: int = 16) -> str:
    """Hex SHA-256 (first ``length`` digits) of every ``*.py`` under ``package_dir``.

    Each file contributes its path relative to ``package_dir`` and its bytes, in sorted order, so
    a renamed, added, removed or edited file changes the key; timestamps do not.
    """
    root = Path(package_dir)
    digest = hashlib.sha256()
    for path in sorted(root.rglob("*.py")):
        rel = path.relative_to(root).as_posix().encode()
        data = path.read_bytes()
        digest.update(len(rel).to_bytes(4, "little") + rel)
        digest.update(len(data).to_bytes(8, "little") + data)
    return digest.hexdigest()[:length]


def _private_dir(path: Path) -> bool:
    """Create ``path`` with mode 0700 if missing; True when it is a real folder only we can write.

    numba's cache files are pickles loaded as they are: a folder in the shared temporary
    directory that another user made or can write into must not be used.
    """
    try:
        path.mkdir(mode=0o700)
    except FileExistsError:
        pass
    except OSError:
        return False
    info = os.lstat(path)
    if not stat.S_ISDIR(info.st_mode):
        return False
    return not hasattr(os, "getuid") or (info.st_uid == os.getuid() and not info.st_mode & 0o022)


def _prune(base: Path, keep: Path, now: float) -> None:
    """Remove this user's folders of other source trees not used for :data:`STALE_AFTER_S`."""
    import shutil

    for old in base.glob(keep.name.rsplit("-", 1)[0] + "-*"):
        try:
            if old != keep and _private_dir(old) and now - old.stat().st_mtime > STALE_AFTER_S:
                shutil.rmtree(old, ignore_errors=True)
        except OSError:
            pass


def numba_cache_dir(package_dir: Path | str | None = None, base: Path | str | None = None) -> str:
    """The numba cache folder for the sources in ``package_dir`` (default: the footnav tests import).

    ``<base>/footnav-test-numba-<uid>-<key16>`` with ``base`` the system's temporary folder. When
    that folder is not private (see :func:`_private_dir`), a fresh ``mkdtemp`` folder instead
    (nothing reused, nothing unsafe loaded).
    """
    package_dir = footnav_source_dir() if package_dir is None else Path(package_dir)
    base = Path(tempfile.gettempdir() if base is None else base)
    uid = os.getuid() if hasattr(os, "getuid") else "user"
    path = base / f"{PREFIX}{uid}-{source_key(package_dir)}"
    fresh = not path.exists()
    if not _private_dir(path):
        return tempfile.mkdtemp(prefix=PREFIX)
    now = time.time()
    os.utime(path, (now, now))  # "last used", for the pruning of other trees' folders
    if fresh:
        _prune(base, path, now)
    return str(path)
