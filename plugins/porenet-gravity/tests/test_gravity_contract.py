"""porenet's contract suite (docs/contract.md) on ``gravity.invasion-percolation``: config
errors naming the field, a connected invaded cluster, determinism, the run file and a
checkpoint resumed to the bit."""

from __future__ import annotations

import porenet_gravity.plugin
from porenet_gravity.config import KIND

from porenet.testing.contract import contract_test, plugin_registry

REGISTRY = plugin_registry({"gravity": porenet_gravity.plugin})
test_contract = contract_test("fluid", KIND, registry=REGISTRY)
