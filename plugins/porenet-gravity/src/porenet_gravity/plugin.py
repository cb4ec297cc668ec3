"""porenet hook implementations of porenet-gravity (entry point ``gravity``)."""

from __future__ import annotations

from porenet.hooks import Register, hookimpl
from porenet_gravity.config import GravityInvasionConfig


@hookimpl
def porenet_register_fluid_models(register: Register) -> None:
    """Register ``gravity.invasion-percolation`` with its cost estimate (``porenet plan``)
    and its compile warm-ups (``porenet compile``); each is imported only when used."""
    register(
        GravityInvasionConfig,
        "porenet_gravity.model:GravityInvasionPercolation",
        cost="porenet_gravity.cost:estimate",
        warm_ups="porenet_gravity.warmups:WARM_UPS",
    )
