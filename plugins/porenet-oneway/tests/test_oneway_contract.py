"""porenet's contract suite (docs/contract.md) on ``oneway.pressure``, run on its example, a
deformable solid's scene: determinism, the run file, a checkpoint resumed to the bit."""

from __future__ import annotations

import porenet_oneway.plugin
from porenet_oneway.config import KIND

from porenet.testing.contract import contract_test, plugin_registry

REGISTRY = plugin_registry({"oneway": porenet_oneway.plugin})
test_contract = contract_test("coupler", KIND, registry=REGISTRY)
