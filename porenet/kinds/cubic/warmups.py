"""The scenes ``porenet compile`` runs to compile the viscous model's kernels on the lists of
a lattice other than the square grid (the 3-D cubic lattice; imported networks share them)."""

from __future__ import annotations

from porenet.core.kinds import WarmUp
from porenet.kinds.scenes import VISCOUS, tiny_scene
from porenet.kinds.viscous.warmups import warm_up

CUBIC = {"kind": "cubic", "shape": [6, 6, 6], "disorder": 0.3, "pore_size": 1e-7}

WARM_UPS: tuple[WarmUp, ...] = (
    warm_up(
        "viscous model on a 3-D lattice, explicit integrator",
        tiny_scene(VISCOUS | {"integrator": "explicit"}) | {"lattice": CUBIC},
    ),
    warm_up(
        "viscous model on a 3-D lattice, rkc integrator",
        tiny_scene(VISCOUS | {"integrator": "rkc"}) | {"lattice": CUBIC},
    ),
)
