"""The scene ``porenet compile`` runs to compile this plugin's kernels (the front's statistics
in :mod:`porenet_gravity.front`) and porenet's invasion kernels it calls, once per machine."""

from __future__ import annotations

from porenet.core.kinds import WarmUp

WARM_UPS: tuple[WarmUp, ...] = (
    WarmUp(
        "gravity invasion percolation",
        {
            "seed": 1,
            "lattice": {"kind": "square", "n": 12, "disorder": 0.3, "pore_size": 5e-4},
            "injection": {"at": "left-edge"},
            "fluid": {"kind": "gravity.invasion-percolation", "bond_number": 0.01},
        },
    ),
)
