"""footnav._cache_lock: a kernel's numba cache is saved under an exclusive file lock and loaded
under a shared one, so processes compiling one kernel at once cannot mix up its signatures; a
compilation holds the lock from its load to its save, so processes needing one signature at once
compile it once."""

from __future__ import annotations

import os
import pickle
import subprocess
import sys
import textwrap
import time

import pytest

from footnav import _numba
from footnav._cache_lock import lock_path

fcntl = pytest.importorskip("fcntl")

_KERNEL = textwrap.dedent(
    """
    from footnav._numba import njit

    @njit(cache=True)
    def scale(x):
        s = x * 0
        for i in range(3):
            s = s + x * (i + 1)
        return s
    """
)


def _holds(path: str, mode: int) -> bool:
    """Whether another open file could take ``mode`` on ``path`` now (False: someone holds it)."""
    fd = os.open(path, os.O_RDWR | os.O_CREAT)
    try:
        fcntl.flock(fd, mode | fcntl.LOCK_NB)
        return True
    except BlockingIOError:
        return False
    finally:
        os.close(fd)


def _kernel(x):
    return 3.0 * x


def test_a_save_is_exclusive_a_load_shared_and_a_first_call_exclusive_throughout(tmp_path, monkeypatch):
    from numba.core import caching, config

    monkeypatch.setattr(config, "CACHE_DIR", str(tmp_path))
    kernel = _numba.njit(cache=True)(_kernel)
    path = lock_path(kernel)
    seen = {}
    save_index, load_data = caching.IndexDataCacheFile._save_index, caching.IndexDataCacheFile._load_data

    def spy_save(self, overloads):  # inside save(): between loading the index and writing the data
        seen["save"] = (_holds(path, fcntl.LOCK_SH), _holds(path, fcntl.LOCK_EX))
        return save_index(self, overloads)

    def spy_load(self, name):  # inside load(): the index read, its data not yet
        seen["load"] = (_holds(path, fcntl.LOCK_SH), _holds(path, fcntl.LOCK_EX))
        return load_data(self, name)

    monkeypatch.setattr(caching.IndexDataCacheFile, "_save_index", spy_save)
    monkeypatch.setattr(caching.IndexDataCacheFile, "_load_data", spy_load)
    assert kernel(2.0) == 6.0  # compiles and saves
    assert seen.pop("save") == (False, False)  # no reader, no other writer during a save
    again = _numba.njit(cache=True)(_kernel)  # a new dispatcher, as in another process: loads
    assert again(2.0) == 6.0
    # a first call's load is its compilation's: another process needing the kernel waits for it
    assert seen.pop("load") == (False, False) and "save" not in seen
    third = _numba.njit(cache=True)(_kernel)
    assert third._cache.load_overload(again.signatures[0], third.targetctx) is not None
    assert seen.pop("load") == (True, False)  # a load alone: other readers, no writer
    assert _holds(path, fcntl.LOCK_EX)  # released after each


def test_a_kernel_without_a_cache_is_left_alone():
    kernel = _numba.njit(cache=False)(_kernel)
    assert kernel(1.0) == 3.0 and lock_path(kernel) is None


@pytest.mark.slow
def test_processes_needing_one_signature_at_once_compile_it_once(tmp_path):
    """Two processes call one kernel with one signature on an empty cache at once, numba's compiler
    made a second slower so that each needs it while the other could be compiling it: one
    compiles it and the other loads it (unlocked, both compiled it)."""
    (tmp_path / "kmod.py").write_text(_KERNEL, encoding="utf-8")
    worker = textwrap.dedent(
        """
        import sys, time
        import numpy as np
        from numba.core import dispatcher
        compile = dispatcher._FunctionCompiler.compile
        def slow(self, args, return_type):
            time.sleep(1.0)
            return compile(self, args, return_type)
        dispatcher._FunctionCompiler.compile = slow
        import kmod
        start = float(sys.argv[1])
        while time.time() < start:
            time.sleep(0.001)
        assert kmod.scale(np.float64(2.0)) == 12.0
        stats = kmod.scale.stats
        print(sum(stats.cache_misses.values()), sum(stats.cache_hits.values()))
        """
    )
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "cache")}
    env["PYTHONPATH"] = os.pathsep.join([str(tmp_path), env.get("PYTHONPATH", "")])
    start = str(time.time() + 3.0)  # both imported and waiting before either calls
    procs = [
        subprocess.Popen([sys.executable, "-c", worker, start], env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
        for _ in range(2)
    ]
    outs = []
    for proc in procs:
        out, err = proc.communicate(timeout=300)
        assert proc.returncode == 0, err.decode()[-2000:]
        outs.append(out.decode().split())
    # (cache misses, cache hits): one compiled, one loaded what it saved
    assert sorted(outs) == [["0", "1"], ["1", "0"]]


@pytest.mark.slow
def test_processes_compiling_one_kernel_at_once_leave_an_index_naming_each_signatures_own_code(tmp_path, monkeypatch):
    """Four processes compile six signatures of one kernel into one empty cache at once, each in
    another order; then every index entry's data is that signature's, and a fifth process loads
    all six and compiles nothing."""
    (tmp_path / "kmod.py").write_text(_KERNEL, encoding="utf-8")
    args = "[np.int64(3), np.float64(3.0), np.complex128(3 + 1j), np.float32(3.0), np.int32(3), np.uint8(3)]"
    worker = textwrap.dedent(
        f"""
        import sys, time
        import numpy as np
        import kmod
        args = {args}
        start = float(sys.argv[2])
        while time.time() < start:
            time.sleep(0.001)
        for i in np.random.default_rng(int(sys.argv[1])).permutation(len(args)):
            assert complex(kmod.scale(args[i])) == 6 * complex(args[i])
        """
    )
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "cache")}
    env["PYTHONPATH"] = os.pathsep.join([str(tmp_path), env.get("PYTHONPATH", "")])
    start = time.time() + 3.0  # every process imported and waiting before the first compiles
    procs = [
        subprocess.Popen([sys.executable, "-c", worker, str(seed), str(start)], env=env, stderr=subprocess.PIPE)
        for seed in range(4)
    ]
    for proc in procs:
        _, err = proc.communicate(timeout=300)
        assert proc.returncode == 0, err.decode()[-2000:]
    (index,) = (tmp_path / "cache").rglob("*.nbi")
    monkeypatch.syspath_prepend(str(tmp_path))  # the data's pickles name the module
    with open(index, "rb") as f:
        pickle.load(f)  # numba's version
        _, overloads = pickle.loads(f.read())
    assert len(overloads) == 6
    for key, name in overloads.items():
        data = pickle.loads((index.parent / name).read_bytes())
        # numba's reduced compile result: (library, fndesc, environment, signature, ...)
        assert tuple(data[3].args) == tuple(key[0]) == tuple(data[1].argtypes)
    check = textwrap.dedent(
        f"""
        import numpy as np
        import kmod
        for a in {args}:
            assert complex(kmod.scale(a)) == 6 * complex(a)
        print(sum(kmod.scale.stats.cache_misses.values()), sum(kmod.scale.stats.cache_hits.values()))
        """
    )
    out = subprocess.run([sys.executable, "-c", check], env=env, capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr[-2000:]
    assert out.stdout.split() == ["0", "6"]
