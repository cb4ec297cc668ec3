"""Registers this kind through the hook any plugin implements (docs/architecture.md, rule 1):
the config is imported here; the implementation, and the cost estimate and compile warm-ups
where the kind has them, are named by ``"module:name"`` and imported only when used."""

from __future__ import annotations

from porenet.hooks import Register, hookimpl
from porenet.kinds.invasion.config import InvasionPercolationConfig


@hookimpl
def porenet_register_fluid_models(register: Register) -> None:
    register(
        InvasionPercolationConfig,
        "porenet.kinds.invasion.model:InvasionPercolation",
        default=True,
        cost="porenet.kinds.invasion.cost:estimate",
        warm_ups="porenet.kinds.invasion.warmups:WARM_UPS",
    )
