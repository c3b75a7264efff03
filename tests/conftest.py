"""Shared fixtures. Installed third-party plugins are kept out of the suite (autoload off).

numba caches compiled kernels in a folder keyed by the contents of footnav's sources
(``tests/numba_cache_key.py``), so a changed helper in one module can never leave a stale
caller cached in another. Set ``NUMBA_CACHE_DIR`` yourself to choose the folder instead.
"""

from __future__ import annotations

import os
from pathlib import Path

# Before anything imports numba (footnav's first kernel does): numba reads NUMBA_CACHE_DIR once, at its import.
# Subprocesses the tests start (the CLI, follow) inherit it.
if not os.environ.get("NUMBA_CACHE_DIR"):
    from numba_cache_key import numba_cache_dir

    os.environ["NUMBA_CACHE_DIR"] = numba_cache_dir()
# Under pytest-xdist (`pytest -n 2`) the workers share the folder: a kernel one of them compiled
# the other loads. footnav saves and loads each kernel's cache under a file lock
# (footnav/_cache_lock.py), so two workers compiling one kernel at once cannot mix up its signatures.

import pytest  # noqa: E402

os.environ["FOOTNAV_DISABLE_PLUGIN_AUTOLOAD"] = "1"

#: ../shared/data beside the repository, or $FOOTNAV_DATA.
SHARED_DATA = Path(os.environ.get("FOOTNAV_DATA", Path(__file__).resolve().parents[1].parent / "shared" / "data"))


def pytest_configure(config):
    """Under pytest-xdist the controller collects nothing, so it never loads tests/faults/conftest.py
    as a conftest; it is registered there as a plugin instead, to count the workers' fault-injection
    reports and print their summary (and write FOOTNAV_FAULT_REPORT) once, as a serial run does."""
    if hasattr(config, "workerinput") or getattr(config.option, "dist", "no") == "no" or config.option.collectonly:
        return
    import importlib.util

    spec = importlib.util.spec_from_file_location(
        "footnav_tests_faults_conftest", Path(__file__).parent / "faults" / "conftest.py"
    )
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    config.pluginmanager.register(module, "footnav-faults-summary")


def pytest_collection_modifyitems(items):
    """The tests marked slow (long subprocess runs, cold numba compiles) run first, in their order,
    so that with several workers (pytest -n) none of them is left running alone at the end."""
    items.sort(key=lambda item: item.get_closest_marker("slow") is None)  # stable: the rest keep their order


@pytest.fixture
def shared_data() -> Path:
    """The shared real recordings; the test is skipped when they are absent."""
    if not SHARED_DATA.is_dir():
        pytest.skip(f"shared data not found at {SHARED_DATA} (set FOOTNAV_DATA)")
    return SHARED_DATA


@pytest.fixture(autouse=True)
def _fresh_registry():
    """Each test starts from the built-in registry and leaves no plugin behind."""
    from footnav.plugins.manager import reset_registry

    reset_registry()
    yield
    reset_registry()


def _never_still_gait(floor_radps: float, rate_hz: float = 200.0, strides: int = 12, stride_s: float = 0.7):
    """A foot that never stops turning: ``strides`` strides of a swing (angular rate up to 9 rad/s,
    the foot lifted and lowered at up to 8 m/s^2) then a 0.2 s stance at ``floor_radps``, one more
    swing, and 1 s standstills at both ends. Returns the ImuData and the true stance mask; the
    stances at the floor all lie between two swings."""
    import numpy as np

    from footnav.core.types import GRAVITY_MPS2, ImuData

    n_stride = int(stride_s * rate_hz)
    n_stance = int(0.2 * rate_hz)
    u = np.arange(n_stride - n_stance) / (n_stride - n_stance)
    swing = floor_radps + (9.0 - floor_radps) * np.sin(np.pi * u) ** 2
    still = np.zeros(int(rate_hz))
    rate = np.concatenate([still, *[np.r_[swing, np.full(n_stance, floor_radps)]] * strides, swing, still])
    stride_truth = np.r_[np.zeros(len(swing), bool), np.ones(n_stance, bool)]
    truth = np.concatenate([still == 0, *[stride_truth] * strides, np.zeros(len(swing), bool), still == 0])
    n = len(rate)
    gyr = np.zeros((n, 3))
    gyr[:, 1] = rate
    acc = np.tile([0.0, 0.0, GRAVITY_MPS2], (n, 1))
    # the swing lifts and lowers the foot, 8 m/s^2 at most (a swing's |f| - g)
    u_all = np.concatenate([np.zeros(len(still)), *[np.r_[u, np.zeros(n_stance)]] * strides, u, np.zeros(len(still))])
    acc[:, 2] += np.where(truth, 0.0, 8.0 * np.sin(2.0 * np.pi * u_all))
    return ImuData(t=np.arange(n) / rate_hz, acc=acc, gyr=gyr), truth


@pytest.fixture
def never_still_gait():
    """``never_still_gait(floor_radps, rate_hz=200, strides=12, stride_s=0.7) -> (imu, truth)``."""
    return _never_still_gait
