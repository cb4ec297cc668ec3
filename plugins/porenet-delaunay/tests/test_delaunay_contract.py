"""porenet's contract suite (docs/contract.md) on ``delaunay.random``: the lattice contract,
config errors naming the field, and runs on it that repeat under the seed, resume from a
checkpoint and read back from the run file; and the fluid checks of both fluid models on it
(a connected invaded cluster; for the viscous model the volume balance at every record)."""

from __future__ import annotations

import porenet_delaunay.plugin
from porenet_delaunay.config import KIND, DelaunayLatticeConfig

from porenet.testing.contract import contract_checks, contract_test, parametrized, plugin_registry

REGISTRY = plugin_registry({"delaunay": porenet_delaunay.plugin})
test_contract = contract_test("lattice", KIND, registry=REGISTRY)

#: The example scene (invasion percolation from the centre) and the viscous model on it.
INVASION = DelaunayLatticeConfig.example_scene()
VISCOUS = INVASION | {"fluid": {"kind": "viscous", "capillary_number": 1e-2}}
#: The checks of each fluid model that concern the lattice it runs on (the rest are
#: porenet's own tests'; the lattice's contract above already runs invasion percolation).
ON_THIS_LATTICE = {
    "invasion-percolation": (INVASION, ("invaded-cluster",)),
    "viscous": (VISCOUS, ("runs", "deterministic", "finite", "checkpoint", "invaded-cluster",
                          "volume-balance")),
}  # fmt: skip
test_fluids_on_this_lattice = parametrized(
    [
        check
        for fluid, (scene, names) in ON_THIS_LATTICE.items()
        for check in contract_checks("fluid", fluid, scene=scene, registry=REGISTRY)
        if check.name in names
    ]
)
