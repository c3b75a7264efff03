"""Every registered fusion (the default included) through its kind's contract in footnav.testing
(classes made from the registry: tests/registry_contracts.py)."""

from registry_contracts import contract_classes  # tests/registry_contracts.py

globals().update(contract_classes("fusion"))
