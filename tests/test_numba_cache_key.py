"""The suite's numba cache folder changes with any change to footnav's sources (issue 17, item 7)."""

from __future__ import annotations

import os
import shutil
import time

import pytest
from numba_cache_key import PREFIX, STALE_AFTER_S, footnav_source_dir, numba_cache_dir, source_key


@pytest.fixture
def tree(tmp_path):
    """A copy of footnav's sources (no caches), to edit."""
    copy = tmp_path / "footnav"
    shutil.copytree(footnav_source_dir(), copy, ignore=shutil.ignore_patterns("__pycache__", "*.nb?", "*.pyc"))
    return copy


def test_one_changed_compiled_helper_gives_another_folder(tree, tmp_path):
    base = tmp_path / "tmp"
    base.mkdir()
    before = numba_cache_dir(tree, base)
    assert numba_cache_dir(tree, base) == before  # an unchanged tree reuses its folder
    helper = tree / "nav" / "quaternion.py"  # compiled helpers the filter kernels call
    assert "njit" in helper.read_text()
    helper.write_text(helper.read_text().replace("1.0", "1.00", 1))
    after = numba_cache_dir(tree, base)
    assert after != before
    assert os.path.dirname(after) == str(base) and os.path.basename(after).startswith(PREFIX)
    assert (os.stat(after).st_mode & 0o777) == 0o700


def test_the_key_ignores_timestamps_and_caches_but_not_renames(tree):
    key = source_key(tree)
    (tree / "nav" / "__pycache__").mkdir(exist_ok=True)
    (tree / "nav" / "__pycache__" / "x.nbi").write_bytes(b"cache")
    os.utime(tree / "nav" / "mechanization.py", (0, 0))
    assert source_key(tree) == key
    (tree / "nav" / "mechanization.py").rename(tree / "nav" / "mechanization2.py")
    assert source_key(tree) != key


def test_a_folder_others_can_write_is_not_used(tree, tmp_path):
    base = tmp_path / "tmp"
    base.mkdir()
    shared = base / f"{PREFIX}{os.getuid()}-{source_key(tree)}"
    shared.mkdir()
    shared.chmod(0o777)
    chosen = numba_cache_dir(tree, base)
    assert chosen != str(shared) and os.path.isdir(chosen)
    shutil.rmtree(chosen)


def test_folders_of_old_trees_are_pruned(tree, tmp_path):
    base = tmp_path / "tmp"
    base.mkdir()
    old = base / f"{PREFIX}{os.getuid()}-0123456789abcdef"
    recent = base / f"{PREFIX}{os.getuid()}-fedcba9876543210"
    for folder in (old, recent):
        folder.mkdir(mode=0o700)
    stale = time.time() - STALE_AFTER_S - 60
    os.utime(old, (stale, stale))
    numba_cache_dir(tree, base)
    assert not old.exists() and recent.exists()


def test_this_run_caches_where_the_conftest_said():
    """numba read NUMBA_CACHE_DIR after conftest set it (nothing imported numba earlier)."""
    from numba.core import config

    assert config.CACHE_DIR == os.environ["NUMBA_CACHE_DIR"]
    folder = config.CACHE_DIR  # one for every pytest -n worker (footnav/_cache_lock.py)
    if os.path.basename(folder).startswith(PREFIX):
        assert folder == numba_cache_dir()
