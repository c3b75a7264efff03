"""Fixtures of the reader tests: where the shared data live, and small synthetic recordings."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest

from footnav.core.types import GRAVITY_MPS2

#: /work/shared/data seen from /work/main/tests/data/io/conftest.py; FOOTNAV_DATA overrides it.
DEFAULT_SHARED_DATA = Path(__file__).resolve().parents[3].parent / "shared" / "data"


def shared_data_dir() -> Path:
    return Path(os.environ.get("FOOTNAV_DATA", DEFAULT_SHARED_DATA))


@pytest.fixture
def shared_data() -> Path:
    """The shared data folder; the test is skipped when it is absent."""
    root = shared_data_dir()
    if not root.is_dir():
        pytest.skip(f"shared data not found at {root} (set FOOTNAV_DATA)")
    return root


@pytest.fixture
def shared_file(shared_data):
    """Path of one shared file; skip if that file is missing."""

    def get(*parts: str) -> Path:
        p = shared_data.joinpath(*parts)
        if not p.exists():
            pytest.skip(f"{p} not found")
        return p

    return get


def _rest_imu(n: int = 50, seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """(acc m/s^2, gyr rad/s) of a sensor at rest, z up, with a little noise; never repeats a value."""
    rng = np.random.default_rng(seed)
    acc = np.array([0.1, -0.2, GRAVITY_MPS2]) + 0.01 * rng.standard_normal((n, 3))
    gyr = 0.005 * rng.standard_normal((n, 3))
    return acc, gyr


@pytest.fixture
def rest_imu():
    """``rest_imu(n, seed) -> (acc, gyr)``: a sensor at rest, z up, SI units, with noise."""
    return _rest_imu


def messages(record) -> str:
    return "\n".join(str(w.message) for w in record)


@pytest.fixture
def warning_text():
    """``warning_text(record)``: all messages of a pytest.warns record, joined."""
    return messages
