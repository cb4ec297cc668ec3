"""The scenes ``porenet compile`` runs to compile the frictional solid's kernels."""

from __future__ import annotations

from porenet.core.kinds import WarmUp
from porenet.kinds.scenes import INVASION, VISCOUS, tiny_scene
from porenet.kinds.viscous.warmups import warm_up

MINDLIN = {"kind": "hertz-mindlin", "fracturing_number": 10.0, "shear_stiffness_ratio": 0.5}

WARM_UPS: tuple[WarmUp, ...] = (
    warm_up(
        "viscous model in a frictional solid (multigrid)",
        tiny_scene(VISCOUS, n=40, solid=MINDLIN, stop={"max_drained": 40}),
    ),
    WarmUp(
        "frictional solid with sliding",
        tiny_scene(INVASION, n=40, solid=MINDLIN | {"friction": 0.3}, stop={"max_drained": 40}),
    ),
    WarmUp(
        "frictional solid with free rotations (sparse direct)",
        tiny_scene(INVASION, solid=MINDLIN | {"rotation": "free"}),
    ),
)
