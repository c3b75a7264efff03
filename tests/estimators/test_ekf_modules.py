"""The EKF sub-package's shape: imports run one way through its modules, none over 600 lines."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

from footnav.estimators import ekf

#: The order of footnav/estimators/ekf/__init__.py: each module may import only those before it.
ORDER = [
    "_buffers",
    "_records",
    "_kernels",
    "_backward",
    "_loop",
    "_measurements",
    "filter",
    "smoother",
    "online",
    "estimator",
]
PACKAGE = Path(ekf.__file__).parent


def _ekf_imports(source: str) -> set[str]:
    """The ekf sub-modules a module's source imports (``from footnav.estimators.ekf import filter``
    included)."""
    found = set()
    for node in ast.walk(ast.parse(source)):
        names = []
        if isinstance(node, ast.ImportFrom) and node.module:
            names = [node.module] + [f"{node.module}.{a.name}" for a in node.names]
        elif isinstance(node, ast.Import):
            names = [a.name for a in node.names]
        for name in names:
            parts = name.split(".")
            if parts[:3] == ["footnav", "estimators", "ekf"] and len(parts) > 3 and parts[3] in ORDER:
                found.add(parts[3])
    return found


def test_every_module_is_listed():
    assert {p.stem for p in PACKAGE.glob("*.py")} - {"__init__"} == set(ORDER)


@pytest.mark.parametrize("name", ORDER)
def test_imports_run_one_way(name):
    source = (PACKAGE / f"{name}.py").read_text(encoding="utf-8")
    later = {m for m in _ekf_imports(source) if ORDER.index(m) >= ORDER.index(name)}
    assert not later, f"ekf/{name}.py imports {sorted(later)}, which come after it in {ORDER}"
    assert len(source.splitlines()) <= 600


def test_the_check_sees_an_import_back():
    """The rule fails when a lower module imports a higher one (here: records -> filter)."""
    bad = "from footnav.estimators.ekf import filter as f\nfrom footnav.estimators.ekf._loop import run\n"
    assert _ekf_imports(bad) == {"filter", "_loop"}


def test_public_names_and_registration():
    import footnav

    assert type(footnav.make_estimator("ekf")) is ekf.EkfEstimator  # the registration's class
    assert ekf.InsFilter.__module__ == "footnav.estimators.ekf.filter"
    assert ekf.smooth.__module__ == "footnav.estimators.ekf.smoother"
    assert ekf.OnlineInsFilter.__module__ == "footnav.estimators.ekf.online"
    # the internals are private: no public module of that name
    for name in ("loop", "backward", "records", "kernels", "buffers"):
        assert not (PACKAGE / f"{name}.py").exists()
        assert hasattr(ekf, "__all__") and name not in ekf.__all__
