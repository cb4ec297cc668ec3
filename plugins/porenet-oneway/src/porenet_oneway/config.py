"""Config of porenet-oneway's coupler, ``oneway.pressure``: pydantic and porenet's light config
base only.

porenet imports this module whenever it builds the scene schema (``porenet validate``,
``plan``, ``schema``, ``plugins``), so it imports no numerics; the coupler,
:mod:`porenet_oneway.model`, is imported only when a scene selects it.

A coupler has no section of its own in a scene: the solid's section names it (its config's
``coupler`` field, of type ``porenet.config.base.CouplerKind``: any registered coupler) and
carries its schedule (``coupling``, ``coupling_interval``, ``coupling_tolerance``), and the
Simulation hands the solid's config to the coupler. ``feeds_back = False`` tells porenet's
plan that the apertures the fluid sees never change (its effect ``aperture_feedback`` is off),
so the fluid models run as in a rigid medium.
"""

from __future__ import annotations

from typing import Any, ClassVar, Literal

from porenet.config.base import ModelConfig

#: The coupler's kind: ``[solid] coupler = "oneway.pressure"``.
KIND = "oneway.pressure"


class OneWayConfig(ModelConfig):
    """One-way coupling: the solid is loaded by the fluid's pore pressures on its schedule
    (the solid's ``coupling``, ``coupling_interval``, ``coupling_tolerance``), but the
    apertures the fluid sees never change."""

    kind: Literal["oneway.pressure"] = "oneway.pressure"
    feeds_back: ClassVar[bool] = False

    @classmethod
    def example_scene(cls) -> dict[str, Any]:
        """A small scene coupled by this coupler, for porenet's contract suite
        (docs/contract.md): porenet's Hertzian solid, soft, updated after every pore."""
        solid = {"kind": "hertz", "fracturing_number": 1.0, "coupling": "every-step",
                 "coupler": KIND}  # fmt: skip
        return {"seed": 1, "lattice": {"n": 12, "disorder": 0.3}, "fluid": {}, "solid": solid}
