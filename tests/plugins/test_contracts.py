"""Every registered component runs through its kind's contract (footnav.testing), the defaults
(``adaptive`` detector, ``ekf`` estimator, ``independent`` fusion, ``none`` heading aid) included.

The contract classes are made from the registry (tests/registry_contracts.py) in one test module
per kind, beside that kind's tests: tests/detectors/test_detector_contracts.py,
tests/estimators/test_estimator_contracts.py, tests/fusion/test_fusion_contracts.py and
tests/heading_aids/test_heading_aid_contracts.py. Here: that every kind has a contract and a
module, and that the defaults are among the classes made.
"""

from __future__ import annotations

from pathlib import Path

from registry_contracts import CONTRACTS, class_name, contract_classes  # tests/registry_contracts.py

import footnav
from footnav.core.component import KINDS

TESTS = Path(__file__).resolve().parents[1]
MODULES = {
    "detector": TESTS / "detectors" / "test_detector_contracts.py",
    "estimator": TESTS / "estimators" / "test_estimator_contracts.py",
    "fusion": TESTS / "fusion" / "test_fusion_contracts.py",
    "heading_aid": TESTS / "heading_aids" / "test_heading_aid_contracts.py",
}


def test_every_kind_has_a_contract_and_a_module_running_it():
    assert set(KINDS) <= set(CONTRACTS) and set(KINDS) <= set(MODULES)
    for kind, path in MODULES.items():
        assert f'contract_classes("{kind}")' in path.read_text(encoding="utf-8"), path


def test_every_registered_component_and_the_defaults_get_a_class():
    for kind, names in footnav.list_components().items():
        made = contract_classes(kind)
        assert sorted(made) == sorted(class_name(kind, n) for n in names)
        for cls in made.values():
            assert issubclass(cls, CONTRACTS[kind]) and cls.component.kind == kind
    pipe = footnav.make_pipeline()
    defaults = {c.kind: c.name for c in pipe.components}
    assert defaults["detector"] == "adaptive" and defaults["fusion"] == "independent"
    for kind, name in defaults.items():
        assert class_name(kind, name) in contract_classes(kind)
