"""The package's layers, read from the imports (issue 18): each folder imports only the layers
below it, nothing inside imports the package root, no module is over 600 lines, and every module
is imported by another (entry points aside)."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[1] / "footnav"

#: Rank of each top-level part of the package: a module may import its own rank or lower.
#: The contracts layer ``core`` is ranked by its own parts (``core.types``, ...): its data types
#: and errors below its component bases and Protocols, all of it below the numerics of ``nav``.
# fmt: off
LAYERS = {
    "_version": 0, "_cache_lock": 0, "_numba": 0, "_lazy": 0,
    "core.errors": 1, "core.warning_log": 1, "core.types": 1, "errors": 1,
    "core.parameters": 2, "core.component": 2, "core.online_contract": 2, "core": 2,
    "nav": 3,
    "detectors": 4, "estimators": 4, "fusion": 4, "heading_aids": 4,
    "pipeline": 5, "plugins": 5,
    "analysis": 6, "data": 6, "report": 6,
    "cli": 7, "demo": 7, "testing": 7, "__init__": 7,
}
# fmt: on
#: Modules nothing inside imports: the entry points (the console script, ``python -m``, the demo
#: the CLI runs by name, the contracts third parties import, the built-in registrations pluggy loads).
ENTRY_POINTS = {"footnav", "footnav.cli.__main__", "footnav.testing", "footnav.plugins.builtin"}
MAX_LINES = 600


def module_name(path: Path) -> str:
    parts = path.relative_to(PACKAGE.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def layer(module: str) -> int:
    parts = module.split(".")
    if len(parts) == 1:
        return LAYERS["__init__"]
    return LAYERS[".".join(parts[1:3])] if parts[1] == "core" and len(parts) > 2 else LAYERS[parts[1]]


def imports(path: Path) -> list[tuple[int, str]]:
    """(line, module) of every footnav import in ``path``, at any depth (lazy imports count)."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    here = module_name(path).split(".")
    if path.name != "__init__.py":
        here = here[:-1]
    out = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            out += [(node.lineno, a.name) for a in node.names if a.name.split(".")[0] == "footnav"]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = ".".join(here[: len(here) - node.level + 1] + ([node.module] if node.module else []))
            else:
                base = node.module or ""
            if base.split(".")[0] != "footnav":
                continue
            # `from footnav.x import y` may name a submodule y
            out += [
                (
                    node.lineno,
                    f"{base}.{a.name}"
                    if (PACKAGE.parent / f"{base}.{a.name}".replace(".", "/")).exists()
                    or (PACKAGE.parent / (f"{base}.{a.name}".replace(".", "/") + ".py")).exists()
                    else base,
                )
                for a in node.names
            ]
    return out


def violations(files: list[Path]) -> list[str]:
    bad = []
    for path in files:
        importer = module_name(path)
        for line, target in imports(path):
            where = f"{path.relative_to(PACKAGE.parent)}:{line}"
            if target == "footnav" and importer != "footnav":
                bad.append(f"{where}: imports the package root")
            elif target != "footnav" and layer(target) > layer(importer):
                bad.append(f"{where}: {importer} (layer {layer(importer)}) imports {target} (layer {layer(target)})")
    return bad


def _sources() -> list[Path]:
    return sorted(p for p in PACKAGE.rglob("*.py") if "__pycache__" not in p.parts)


def test_every_part_of_the_package_has_a_layer():
    parts = {module_name(p) for p in _sources()}
    unranked = []
    for module in sorted(parts):
        try:
            layer(module)
        except KeyError:
            unranked.append(module)
    assert unranked == []


def test_imports_run_only_downwards():
    assert violations(_sources()) == []


def test_the_check_catches_an_import_that_runs_back_up(tmp_path, monkeypatch):
    """A bottom-layer module importing the pipeline and a contract above it, and a module importing
    the package root."""
    fake = tmp_path / "footnav"
    (fake / "core" / "types").mkdir(parents=True)
    (fake / "nav").mkdir()
    (fake / "pipeline").mkdir()
    (fake / "pipeline" / "factory.py").write_text("X = 1\n")
    (fake / "core" / "component.py").write_text("X = 1\n")
    (fake / "core" / "types" / "imu.py").write_text(
        "def f():\n    from footnav.pipeline.factory import X\n    from footnav.core.component import X\n    return X\n"
    )
    (fake / "nav" / "quaternion.py").write_text("import footnav\n")
    monkeypatch.setattr(__import__(__name__), "PACKAGE", fake)
    found = violations([fake / "core" / "types" / "imu.py", fake / "nav" / "quaternion.py"])
    assert len(found) == 3
    assert "footnav.core.types.imu (layer 1) imports footnav.pipeline.factory (layer 5)" in found[0]
    assert "footnav.core.types.imu (layer 1) imports footnav.core.component (layer 2)" in found[1]
    assert "imports the package root" in found[2]


def test_the_pipeline_imports_nothing_of_the_ekf():
    """The pipeline runs any estimator through the contracts (footnav.core.component,
    footnav.core.online_contract), never through the EKF's own modules (issue 38)."""
    bad = [
        f"{p.relative_to(PACKAGE.parent)}:{line}: {target}"
        for p in _sources()
        if module_name(p).startswith("footnav.pipeline")
        for line, target in imports(p)
        if target.startswith("footnav.estimators.ekf")
    ]
    assert bad == []


@pytest.mark.parametrize("path", _sources(), ids=lambda p: str(p.relative_to(PACKAGE)))
def test_no_module_over_600_lines(path):
    n = len(path.read_text(encoding="utf-8").splitlines())
    assert n <= MAX_LINES, f"{path.relative_to(PACKAGE.parent)} has {n} lines"


def test_every_module_is_imported_by_another():
    names = {module_name(p) for p in _sources()}
    imported = {target for p in _sources() for _, target in imports(p)}
    # a package counts as imported when any of its modules is
    imported |= {".".join(t.split(".")[:k]) for t in imported for k in range(1, len(t.split(".")))}
    orphans = sorted(names - imported - ENTRY_POINTS)
    assert orphans == [], orphans
