"""porenet's contract suite (docs/contract.md) on ``correlated.gaussian``: the lattice
contract, config errors naming the field, and runs on it that repeat under the seed, resume
from a checkpoint and read back from the run file."""

from __future__ import annotations

import porenet_correlated.plugin
from porenet_correlated.config import KIND

from porenet.testing.contract import contract_test, plugin_registry

REGISTRY = plugin_registry({"correlated": porenet_correlated.plugin})
test_contract = contract_test("lattice", KIND, registry=REGISTRY)
