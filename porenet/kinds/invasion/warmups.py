"""The scenes ``porenet compile`` runs to compile invasion percolation's kernels."""

from __future__ import annotations

from porenet.core.kinds import WarmUp
from porenet.kinds.scenes import INVASION, tiny_scene

WARM_UPS: tuple[WarmUp, ...] = (
    WarmUp("invasion percolation", tiny_scene(INVASION)),
    WarmUp(
        "invasion percolation without trapping",
        tiny_scene(INVASION | {"trapping": False}, stop={"at": "complete"}),
    ),
)
