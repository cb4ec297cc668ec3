"""porenet's contract suite (docs/contract.md) on the ``linear.springs`` solid: config errors
naming the field, force balance and positive apertures at the end, determinism, the run file
and a checkpoint resumed to the bit."""

from __future__ import annotations

import porenet_linear.plugin
from porenet_linear.config import KIND

from porenet.testing.contract import contract_test, plugin_registry

REGISTRY = plugin_registry({"linear": porenet_linear.plugin})
test_contract = contract_test("solid", KIND, registry=REGISTRY)
