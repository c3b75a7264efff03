"""footnav imports and runs where it is installed read-only, without a writable HOME or numba cache.

numba's ``@njit(cache=True)`` raised "cannot cache function ...: no locator available" at import
time when neither the sources' ``__pycache__`` nor ``~/.cache`` was writable (issue 14).
:mod:`footnav._numba` falls back to a private folder in the temporary directory, or to no
cache; these tests run that for real in a subprocess and check the pieces in-process.
"""

from __future__ import annotations

import ctypes
import json
import logging
import os
import shutil
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest

import footnav
from footnav import _numba

#: Run in the subprocess: refuse to test anything if the sandbox is not what it claims (files we
#: must not be able to write are writable), then the acceptance run of issue 14.
_CHILD = textwrap.dedent(
    """
    import json, os, sys
    for folder in (os.environ["HOME"], os.getcwd(), sys.argv[1]):
        try:
            open(os.path.join(folder, "probe"), "w").close()
        except OSError:
            pass
        else:
            sys.exit(f"setup error: {folder} is writable")
    import numpy as np
    import footnav
    assert footnav.__file__.startswith(sys.argv[1]), footnav.__file__
    # threshold + madgwick: compiled kernels cached like any other, in 9 s cold against the
    # default pipeline's 20 s (the fallback folder is the same for every kernel)
    result = footnav.make_pipeline("threshold", "madgwick").run(footnav.simulate("straight", distance_m=10).left)
    position = np.asarray(result.left.position)
    print(json.dumps({"finite": bool(np.isfinite(position).all()), "end": position[-1].tolist()}))
    """
)

_PR_CAPBSET_DROP = 24  # linux/prctl.h


def _drop_capabilities() -> None:
    """preexec_fn: empty the capability bounding set, so the exec'd root process has no capability.

    Root bypasses file permissions through CAP_DAC_OVERRIDE / CAP_DAC_READ_SEARCH. Without them
    uid 0 is held to the permission bits like any user: a folder with mode 555 is read-only for
    it. (Switching to ``nobody`` instead is not possible when the interpreter lives under a
    0700 home, as it does in this sandbox.)
    """
    libc = ctypes.CDLL(None, use_errno=True)
    for cap in range(64):
        # EINVAL past the kernel's last capability: nothing left to drop
        if libc.prctl(_PR_CAPBSET_DROP, cap, 0, 0, 0) != 0 and ctypes.get_errno() != 22:
            raise OSError(ctypes.get_errno(), "prctl(PR_CAPBSET_DROP) failed")


def _read_only(*paths: Path) -> None:
    for path in paths:
        for folder, _dirs, files in os.walk(path):
            for name in files:
                os.chmod(os.path.join(folder, name), 0o444)
            os.chmod(folder, 0o555)


def _writable(*paths: Path) -> None:
    """Undo :func:`_read_only` so pytest can remove tmp_path."""
    for path in paths:
        for folder, _dirs, _files in os.walk(path):
            os.chmod(folder, 0o755)


@pytest.mark.slow
def test_import_and_run_from_a_read_only_copy_without_home_or_numba_cache(tmp_path):
    if sys.platform != "linux":
        pytest.skip("uses Linux file permissions and prctl")
    package = Path(footnav.__file__).resolve().parent
    site = tmp_path / "site"
    # the sources only: no numba cache (*.nbi / *.nbc) and no byte code from this checkout
    shutil.copytree(package, site / "footnav", ignore=shutil.ignore_patterns("__pycache__", "*.nbi", "*.nbc", "*.pyc"))
    home, cwd, tmp = tmp_path / "home", tmp_path / "cwd", tmp_path / "tmp"
    for folder in (home, cwd, tmp):
        folder.mkdir()
    _read_only(site, home, cwd)
    env = {k: v for k, v in os.environ.items() if k not in ("NUMBA_CACHE_DIR", "XDG_CACHE_HOME", "PYTHONPATH")}
    # TMPDIR: a fresh writable temporary folder, so the fallback cache starts empty and is found
    env.update(HOME=str(home), PYTHONPATH=str(site), TMPDIR=str(tmp), PYTHONDONTWRITEBYTECODE="")
    preexec = _drop_capabilities if os.geteuid() == 0 else None
    try:
        runs = [
            subprocess.run(
                [sys.executable, "-c", _CHILD, str(site)],
                check=False,
                cwd=cwd,
                env=env,
                preexec_fn=preexec,
                capture_output=True,
                text=True,
                timeout=600,
            )
            for _ in range(2)  # the second run loads what the first one cached
        ]
    finally:
        _writable(site, home, cwd)
    for run in runs:
        assert run.returncode == 0, run.stderr[-3000:]
        out = json.loads(run.stdout.strip().splitlines()[-1])
        assert out["finite"]
        assert abs(out["end"][0] - 10.0) < 1.0  # walked 10 m along x
        # the one notice: which folder, and how to choose another
        assert run.stderr.count("numba has no writable cache folder") == 1, run.stderr
        assert "NUMBA_CACHE_DIR" in run.stderr
    cache = tmp / f"footnav-numba-cache-{os.geteuid()}"
    assert cache.is_dir() and (cache.stat().st_mode & 0o777) == 0o700
    assert any(cache.rglob("*.nbi")), "the fallback folder holds no numba cache"
    assert not list(site.rglob("*.nbi")) and not list(home.iterdir())


# -- the pieces, in-process (fast) ------------------------------------------------------------


@pytest.fixture
def no_numba_locator(monkeypatch):
    """numba finds no cache folder for any function, as in a read-only install without HOME."""
    from numba.core import caching, config

    impl = getattr(caching, "CacheImpl", None) or caching._CacheImpl  # renamed in numba 0.60
    # only NUMBA_CACHE_DIR's locator, which finds nothing while it is unset
    monkeypatch.setattr(impl, "_locator_classes", [caching.UserProvidedCacheLocator])
    monkeypatch.setattr(config, "CACHE_LOCATOR_CLASSES", "", raising=False)
    monkeypatch.setattr(config, "CACHE_DIR", "")
    monkeypatch.setattr(_numba, "_fallback", None)  # the notice of this "process"


def _kernel(x):
    return 2.0 * x + 1.0


def test_unchanged_where_numba_can_cache(tmp_path, monkeypatch, caplog):
    from numba.core import config

    monkeypatch.setattr(config, "CACHE_DIR", str(tmp_path))
    with caplog.at_level(logging.WARNING, logger=_numba.__name__):
        kernel = _numba.njit(cache=True)(_kernel)
        assert kernel(1.0) == 3.0
    assert kernel._cache.cache_path.startswith(str(tmp_path))  # numba's own choice
    assert not caplog.records


def test_falls_back_to_a_private_folder_with_one_notice(tmp_path, monkeypatch, no_numba_locator, caplog):
    from numba.core import config

    monkeypatch.setenv("TMPDIR", str(tmp_path))
    monkeypatch.setattr("tempfile.tempdir", None)  # gettempdir() reads TMPDIR again
    with caplog.at_level(logging.WARNING, logger=_numba.__name__):
        first = _numba.njit(cache=True, error_model="numpy")(_kernel)
        second = _numba.njit(cache=True)(lambda x: x - 1.0)
        assert first(1.0) == 3.0 and second(1.0) == 0.0
    private = tmp_path / f"footnav-numba-cache-{os.getuid()}"
    assert first._cache.cache_path.startswith(str(private))
    assert (private.stat().st_mode & 0o777) == 0o700
    assert config.CACHE_DIR == ""  # restored: other numba users are untouched
    assert len(caplog.records) == 1 and str(private) in caplog.records[0].getMessage()


def test_no_cache_when_the_private_folder_is_not_safe(tmp_path, monkeypatch, no_numba_locator, caplog):
    """A fallback folder others can write into is refused: numba's cache files are pickles."""
    monkeypatch.setenv("TMPDIR", str(tmp_path))
    monkeypatch.setattr("tempfile.tempdir", None)
    planted = tmp_path / f"footnav-numba-cache-{os.getuid()}"
    planted.mkdir()
    planted.chmod(0o777)
    assert _numba.fallback_cache_dir() is None
    with caplog.at_level(logging.WARNING, logger=_numba.__name__):
        kernel = _numba.njit(cache=True)(_kernel)
        assert kernel(np.float64(2.0)) == 5.0
    assert kernel._cache.__class__.__name__ == "NullCache"
    assert len(caplog.records) == 1 and "without a cache" in caplog.records[0].getMessage()


def test_other_runtime_errors_are_not_swallowed(monkeypatch):
    import numba

    def broken(**options):
        raise RuntimeError("something else")

    monkeypatch.setattr(numba, "njit", broken)
    kernel = _numba.njit(cache=True)(_kernel)  # numba's dispatcher is made on first use
    with pytest.raises(RuntimeError, match="something else"):
        kernel(1.0)
