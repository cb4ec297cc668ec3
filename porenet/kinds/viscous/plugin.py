"""Registers this kind through the hook any plugin implements (docs/architecture.md, rule 1):
the config is imported here; the implementation, and the cost estimate and compile warm-ups
where the kind has them, are named by ``"module:name"`` and imported only when used."""

from __future__ import annotations

from porenet.hooks import Register, hookimpl
from porenet.kinds.viscous.config import ViscousConfig


@hookimpl
def porenet_register_fluid_models(register: Register) -> None:
    register(
        ViscousConfig,
        "porenet.kinds.viscous.model:ViscousDrainage",
        cost="porenet.kinds.viscous.cost:estimate",
        warm_ups="porenet.kinds.viscous.warmups:WARM_UPS",
    )
