"""footnav's version, from the installed distribution's metadata (the bottom layer: anything may
import it; nothing inside the package imports the package root)."""

from __future__ import annotations

from importlib.metadata import PackageNotFoundError, version

try:
    __version__ = version("footnav")
except PackageNotFoundError:  # running from a source tree that is not installed
    __version__ = "0+unknown"
