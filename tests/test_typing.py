"""The package is typed (issue 38, item 4): it ships ``py.typed`` (PEP 561), and the public
verbs of the component bases, the Protocols and every registered component annotate each
parameter and the return. mypy checks the bodies (``[tool.mypy]`` in pyproject.toml, run by CI);
this test checks what mypy's ``disallow_untyped_defs`` does not reach: the components' public
methods, whatever module defines them, found through the registry as a user finds them."""

from __future__ import annotations

import inspect
import sys
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

import footnav
from footnav.core import component, online_contract
from footnav.plugins.manager import get_registry

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - exercised on 3.10 only
    import tomli as tomllib

ROOT = Path(__file__).resolve().parents[1]

#: The component bases and the Protocols of the contracts layer.
CONTRACTS = (
    component.Component,
    component.StanceDetector,
    component.FootEstimator,
    component.Fusion,
    component.HeadingAid,
    component.JointFilter,
    component.StepableEstimator,
    component.FusionSession,
    online_contract.OnlineFilter,
    online_contract.OnlineEstimator,
)


def public_methods(cls: type) -> Iterator[tuple[str, Any, bool]]:
    """``(qualified name, function, is a staticmethod)`` of every public method, classmethod,
    staticmethod and property getter ``cls`` has from a footnav class (not from object, dict,
    Protocol, ...), each name once (the one the class uses)."""
    seen: set[str] = set()
    for klass in cls.__mro__:
        if not klass.__module__.startswith("footnav"):
            continue
        for name, value in vars(klass).items():
            if name.startswith("_") or name in seen:
                continue
            seen.add(name)
            where = f"{klass.__module__}.{klass.__qualname__}.{name}"
            if isinstance(value, (classmethod, staticmethod)):
                yield where, value.__func__, isinstance(value, staticmethod)
            elif isinstance(value, property):
                yield where, value.fget, False
            elif inspect.isfunction(value):
                yield where, value, False


def unannotated(func: Any, static: bool) -> list[str]:
    """The parameters of ``func`` (self / cls aside) without an annotation, and ``return``."""
    sig = inspect.signature(func)
    params = list(sig.parameters.values())[(0 if static else 1) :]
    missing = [p.name for p in params if p.annotation is inspect.Parameter.empty]
    if sig.return_annotation is inspect.Signature.empty:
        missing.append("return")
    return missing


def registered_classes() -> list[type]:
    registry = get_registry()
    return [registry.get(kind, name).cls for kind, names in footnav.list_components().items() for name in names]


def test_every_kind_has_registered_components() -> None:
    # the walk below is not vacuous: each kind has its built-ins
    assert {kind: len(names) > 0 for kind, names in footnav.list_components().items()} == {
        "detector": True,
        "estimator": True,
        "fusion": True,
        "heading_aid": True,
    }


@pytest.mark.parametrize("cls", CONTRACTS, ids=lambda c: c.__qualname__)
def test_the_contracts_verbs_are_annotated(cls: type) -> None:
    gaps = {where: m for where, func, static in public_methods(cls) if (m := unannotated(func, static))}
    assert gaps == {}


def test_every_registered_components_public_methods_are_annotated() -> None:
    gaps = {
        where: m
        for cls in registered_classes()
        for where, func, static in public_methods(cls)
        if (m := unannotated(func, static))
    }
    assert gaps == {}


def test_the_verbs_are_found() -> None:
    # the walk sees each kind's verb, defined by the component or inherited from its base
    names = {where.rpartition(".")[2] for cls in registered_classes() for where, _, _ in public_methods(cls)}
    assert {"detect", "detect_pair", "estimate", "fuse", "correct", "get_params", "validate_params"} <= names


def test_the_package_ships_py_typed() -> None:
    assert (Path(footnav.__file__).parent / "py.typed").is_file()
    config = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))
    assert "py.typed" in config["tool"]["setuptools"]["package-data"]["footnav"]
