"""What ``import footnav`` loads (issue 33): the package root, the pipeline factory and the data
types, not the analysis layer or the heavy third-party modules it uses only on demand. A test
on which modules load, never on how long the import takes (speed: benchmarks/bench_startup.py)."""

from __future__ import annotations

import importlib
import json
import subprocess
import sys

import pytest

#: Modules (and their submodules) that ``import footnav`` must leave unloaded.
NOT_AT_IMPORT = [
    "sklearn",
    "hmmlearn",
    "scipy.signal",
    "scipy.optimize",
    "scipy.stats",
    "pandas",
    "matplotlib",
    "footnav.analysis",
    "footnav.analysis.comparison",
    "footnav.analysis.metrics",
    "footnav.analysis.evaluation",
]


def _loaded_after(code: str) -> set[str]:
    out = subprocess.run(
        [sys.executable, "-c", f"{code}; import json, sys; print(json.dumps(sorted(sys.modules)))"],
        capture_output=True, text=True, check=True,
    )
    return set(json.loads(out.stdout.strip().splitlines()[-1]))


def _offenders(loaded: set[str], names: list[str]) -> list[str]:
    return sorted(m for m in loaded for name in names if m == name or m.startswith(name + "."))


def test_import_footnav_leaves_the_heavy_modules_unloaded():
    loaded = _loaded_after("import footnav")
    assert "footnav.pipeline.factory" in loaded
    assert _offenders(loaded, NOT_AT_IMPORT) == []


def test_the_command_line_parser_leaves_the_heavy_modules_unloaded():
    """Building the parser (``footnav --help``, any command's set-up) imports no analysis."""
    loaded = _loaded_after("from footnav.cli import build_parser; build_parser()")
    assert _offenders(loaded, NOT_AT_IMPORT) == []


def test_every_public_name_is_importable_and_listed():
    import footnav

    listed = dir(footnav)
    for name in footnav.__all__:
        assert name in listed, name
        assert getattr(footnav, name) is not None, name


@pytest.mark.parametrize("name", ["evaluate", "evaluate_many", "EvaluationReport", "compare_detectors", "DetectorComparison"])
def test_a_lazy_name_is_the_analysis_object(name):
    import footnav

    module = {"evaluate_many": "footnav.analysis.batch", "compare_detectors": "footnav.analysis.comparison",
              "DetectorComparison": "footnav.analysis.comparison"}.get(name, "footnav.analysis.evaluation")
    assert getattr(footnav, name) is getattr(importlib.import_module(module), name)
    exec(f"from footnav import {name}", {})


def test_an_unknown_name_is_an_attribute_error():
    import footnav

    with pytest.raises(AttributeError, match="no attribute 'nothing_here'"):
        footnav.nothing_here  # noqa: B018
