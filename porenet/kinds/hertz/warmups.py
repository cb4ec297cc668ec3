"""The scenes ``porenet compile`` runs to compile the Hertzian solid's kernels."""

from __future__ import annotations

from porenet.core.kinds import WarmUp
from porenet.kinds.scenes import HERTZ, INVASION, VISCOUS, tiny_scene
from porenet.kinds.viscous.warmups import warm_up

WARM_UPS: tuple[WarmUp, ...] = (
    WarmUp("invasion percolation in a Hertz solid", tiny_scene(INVASION, solid=HERTZ)),
    warm_up("viscous model in a Hertz solid", tiny_scene(VISCOUS, solid=HERTZ)),
    WarmUp(
        "Hertz solid, sparse direct solver",
        tiny_scene(INVASION, solid=HERTZ | {"solver": "sparse-direct"}),
    ),
)
