"""porenet's contract suite (docs/contract.md) on ``delaunay.random``: the lattice contract,
config errors naming the field, and runs on it that repeat under the seed, resume from a
checkpoint and read back from the run file; and the fluid checks of the viscous model on it
(a connected invaded cluster, the volume balance at every record)."""

from __future__ import annotations

import porenet_delaunay.plugin
from porenet_delaunay.config import KIND, DelaunayLatticeConfig

from porenet.testing.contract import contract_checks, contract_test, parametrized, plugin_registry

REGISTRY = plugin_registry({"delaunay": porenet_delaunay.plugin})
test_contract = contract_test("lattice", KIND, registry=REGISTRY)

#: The viscous model on this lattice, rate-controlled from the centre to breakthrough.
VISCOUS = DelaunayLatticeConfig.example_scene() | {
    "fluid": {"kind": "viscous", "capillary_number": 1e-2}
}
#: The checks of the viscous model that concern the lattice it runs on (its config's checks
#: are porenet's own tests').
ON_THIS_LATTICE = ("runs", "deterministic", "finite", "checkpoint", "invaded-cluster",
                   "volume-balance")  # fmt: skip
VISCOUS_CHECKS = contract_checks("fluid", "viscous", scene=VISCOUS, registry=REGISTRY)
test_viscous_contract = parametrized([c for c in VISCOUS_CHECKS if c.name in ON_THIS_LATTICE])
