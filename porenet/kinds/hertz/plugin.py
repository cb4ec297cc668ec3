"""Registers this kind through the hook any plugin implements (docs/architecture.md, rule 1):
the config is imported here; the implementation, and the cost estimate and compile warm-ups
where the kind has them, are named by ``"module:name"`` and imported only when used."""

from __future__ import annotations

from porenet.hooks import Register, hookimpl
from porenet.kinds.hertz.config import HertzConfig


@hookimpl
def porenet_register_solid_models(register: Register) -> None:
    register(
        HertzConfig,
        "porenet.kinds.hertz.model:HertzSolid",
        cost="porenet.kinds.hertz.cost:estimate",
        warm_ups="porenet.kinds.hertz.warmups:WARM_UPS",
    )
