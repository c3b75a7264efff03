"""Shared fixtures. Installed third-party plugins are kept out of the suite (autoload off)."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

os.environ["FOOTNAV_DISABLE_PLUGIN_AUTOLOAD"] = "1"

#: ../shared/data beside the repository, or $FOOTNAV_DATA.
SHARED_DATA = Path(os.environ.get("FOOTNAV_DATA", Path(__file__).resolve().parents[1].parent / "shared" / "data"))


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
