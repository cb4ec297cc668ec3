"""porenet's contract suite (docs/contract.md) on ``oneway.pressure`` (run on its example, a
deformable solid's scene: determinism, the run file, a checkpoint resumed to the bit) and on
``oneway.linear``, the solid it couples (config errors naming the field, force balance and
positive apertures at the end)."""

from __future__ import annotations

import porenet_linear.plugin
import porenet_oneway.plugin
from porenet_oneway.config import KIND, SOLID_KIND

from porenet.testing.contract import contract_test, plugin_registry

REGISTRY = plugin_registry({"linear": porenet_linear.plugin, "oneway": porenet_oneway.plugin})
test_contract = contract_test("coupler", KIND, registry=REGISTRY)
test_solid_contract = contract_test("solid", SOLID_KIND, registry=REGISTRY)
