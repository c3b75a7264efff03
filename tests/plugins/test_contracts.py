"""Every registered component runs through its kind's contract (footnav.testing), the defaults
(``adaptive`` detector, ``ekf`` estimator, ``independent`` fusion, ``none`` heading aid) included.

The contract classes are made here from the registry, one per (kind, name): a component added to
the registry is checked without a line of test code, and a kind without a contract fails below.
"""

from __future__ import annotations

import footnav
from footnav.component import KINDS
from footnav.plugins.manager import get_registry
from footnav.testing import DetectorContract, EstimatorContract, FusionContract, HeadingAidContract

CONTRACTS = {
    "detector": DetectorContract,
    "estimator": EstimatorContract,
    "fusion": FusionContract,
    "heading_aid": HeadingAidContract,
}


def _class_name(kind: str, name: str) -> str:
    return "Test" + "".join(part.capitalize() for part in f"{kind}-{name}".replace("_", "-").split("-")) + "Contract"


_REGISTRY = get_registry()
for _kind, _names in footnav.list_components().items():
    for _name in _names:
        _cls = _REGISTRY.get(_kind, _name).cls
        globals()[_class_name(_kind, _name)] = type(_class_name(_kind, _name), (CONTRACTS[_kind],), {"component": _cls})


def test_every_kind_has_a_contract():
    assert set(KINDS) <= set(CONTRACTS)


def test_the_defaults_are_among_the_contracted():
    pipe = footnav.make_pipeline()
    for comp in pipe.components:
        assert _class_name(comp.kind, comp.name) in globals(), comp
    assert {"adaptive", "independent"} <= {c.name for c in pipe.components}
