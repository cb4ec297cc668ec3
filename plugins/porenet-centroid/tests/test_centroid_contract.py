"""porenet's contract suite (docs/contract.md) on ``centroid.nearest``: config errors naming
the field, a verdict in porenet's regimes with a confidence in [0, 1], the same run after run,
from a checkpoint and in the run file."""

from __future__ import annotations

import porenet_centroid.plugin

from porenet.testing.contract import contract_test, plugin_registry

REGISTRY = plugin_registry({"centroid": porenet_centroid.plugin})
test_contract = contract_test("classifier", "centroid.nearest", registry=REGISTRY)
