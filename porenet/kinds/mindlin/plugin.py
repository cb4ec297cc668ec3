"""Registers this kind through the hook any plugin implements (docs/architecture.md, rule 1):
the config is imported here; the implementation, and the cost estimate and compile warm-ups
where the kind has them, are named by ``"module:name"`` and imported only when used."""

from __future__ import annotations

from porenet.hooks import Register, hookimpl
from porenet.kinds.mindlin.config import HertzMindlinConfig


@hookimpl
def porenet_register_solid_models(register: Register) -> None:
    register(
        HertzMindlinConfig,
        "porenet.kinds.mindlin.model:HertzMindlinSolid",
        cost="porenet.kinds.mindlin.cost:estimate",
        warm_ups="porenet.kinds.mindlin.warmups:WARM_UPS",
    )
