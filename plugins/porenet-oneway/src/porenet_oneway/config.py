"""Configs of porenet-oneway: the coupler ``oneway.pressure`` and a solid that a scene can
couple by it. pydantic, porenet's light config base and porenet-linear's config only.

porenet imports this module whenever it builds the scene schema (``porenet validate``,
``plan``, ``schema``, ``plugins``), so it imports no numerics; the coupler,
:mod:`porenet_oneway.model`, is imported only when a scene selects it.

A coupler has no section of its own in a scene: the solid's section names it (its config's
``coupler`` field) and carries its schedule (``coupling``, ``coupling_interval``,
``coupling_tolerance``), and the Simulation hands the solid's config to the coupler. A solid
accepts exactly the coupler kinds its ``coupler`` field lists; porenet's ``hertz`` and
``hertz-mindlin`` and porenet-linear's ``linear.springs`` list only ``pressure-aperture``, so
this plugin also registers ``oneway.linear``: ``linear.springs`` with a ``coupler`` field
that lists both.
"""

from __future__ import annotations

from typing import Any, Literal

from porenet_linear.config import LinearSpringsConfig
from pydantic import Field

from porenet.config.base import ModelConfig

#: The coupler's kind: ``[solid] coupler = "oneway.pressure"``.
KIND = "oneway.pressure"
#: The solid that accepts it: ``[solid] kind = "oneway.linear"``.
SOLID_KIND = "oneway.linear"


class OneWayConfig(ModelConfig):
    """One-way coupling: the solid is loaded by the fluid's pore pressures on its schedule
    (the solid's ``coupling``, ``coupling_interval``, ``coupling_tolerance``), but the
    apertures the fluid sees never change."""

    kind: Literal["oneway.pressure"] = "oneway.pressure"

    @classmethod
    def example_scene(cls) -> dict[str, Any]:
        """A small scene coupled by this coupler, for porenet's contract suite
        (docs/contract.md)."""
        solid = {"kind": SOLID_KIND, "fracturing_number": 1.0, "coupling": "every-step"}
        return {"seed": 1, "lattice": {"n": 12, "disorder": 0.3}, "fluid": {}, "solid": solid}


class OneWayLinearConfig(LinearSpringsConfig):
    """porenet-linear's solid (``linear.springs``: linear contacts, every field the same)
    whose ``coupler`` may be ``oneway.pressure`` (the default) or ``pressure-aperture``."""

    kind: Literal["oneway.linear"] = "oneway.linear"
    coupler: Literal["oneway.pressure", "pressure-aperture"] = Field(
        "oneway.pressure",
        description="Coupler kind: 'oneway.pressure', the solid feels the fluid's pore "
        "pressures but the fluid's apertures never change; 'pressure-aperture', porenet's "
        "two-way coupler.",
    )

    @classmethod
    def example_scene(cls) -> dict[str, Any]:
        """A small scene of invasion percolation in this solid, coupled one way."""
        return OneWayConfig.example_scene()
