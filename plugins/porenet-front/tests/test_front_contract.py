"""porenet's contract suite (docs/contract.md) on the ``front.interface`` observer: config
errors naming the field, records that repeat under the seed, survive a checkpoint and reach
the run file with a unit each."""

from __future__ import annotations

import porenet_front.plugin
from porenet_front.config import KIND

from porenet.testing.contract import contract_test, plugin_registry

REGISTRY = plugin_registry({"front": porenet_front.plugin})
test_contract = contract_test("observer", KIND, registry=REGISTRY)
