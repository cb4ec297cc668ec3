"""Config of quasi-static invasion percolation, kind ``invasion-percolation``.

Pure Python (pydantic and porenet's light modules); the model,
:mod:`porenet.kinds.invasion.model`, is imported only when a scene builds it.
"""

from __future__ import annotations

from typing import Any, Literal

from pydantic import Field

from porenet.config.base import ModelConfig


class InvasionPercolationConfig(ModelConfig):
    """Both fluids inviscid: each step drains the pore behind the easiest throat."""

    kind: Literal["invasion-percolation"] = "invasion-percolation"
    trapping: bool = Field(
        True,
        description="A defending cluster cut off from the outlet can no longer be invaded "
        "(2D pattern D_f ~ 1.82); false gives D_f ~ 1.89.",
    )
    interfacial_tension: float = Field(
        0.07, gt=0, description="Interfacial tension gamma (N/m). Paper: 0.07 N/m."
    )

    def effects(self) -> dict[str, bool]:
        return {"capillarity": True, "viscous_dissipation": False, "trapping": self.trapping}

    @classmethod
    def example_scene(cls) -> dict[str, Any]:
        """A small scene of invasion percolation on the square lattice (the contract suite runs
        it)."""
        from porenet.kinds.scenes import INVASION, tiny_scene

        return tiny_scene(INVASION)
