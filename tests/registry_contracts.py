"""Contract test classes made from the plugin registry: one per registered component of a kind.

A test module of a kind's package (tests/detectors/test_detector_contracts.py, ...) puts them in
its namespace, so the contract runs with that package's tests (and with tools/mutate.py's subsets
for it); a component added to the registry is checked without a line of test code.
"""

from __future__ import annotations

import footnav
from footnav.plugins.manager import get_registry
from footnav.testing import DetectorContract, EstimatorContract, FusionContract, HeadingAidContract

#: The contract of each component kind (footnav.core.component.KINDS).
CONTRACTS = {
    "detector": DetectorContract,
    "estimator": EstimatorContract,
    "fusion": FusionContract,
    "heading_aid": HeadingAidContract,
}


def class_name(kind: str, name: str) -> str:
    return "Test" + "".join(part.capitalize() for part in f"{kind}-{name}".replace("_", "-").split("-")) + "Contract"


def contract_classes(kind: str) -> dict[str, type]:
    """``{class name: contract class}`` for every component of ``kind`` in the registry, with its
    default parameters."""
    registry = get_registry()
    return {
        class_name(kind, name): type(
            class_name(kind, name), (CONTRACTS[kind],), {"component": registry.get(kind, name).cls}
        )
        for name in footnav.list_components()[kind]
    }
