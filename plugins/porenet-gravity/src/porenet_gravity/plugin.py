"""porenet hook implementations of porenet-gravity (entry point ``gravity``)."""

from __future__ import annotations

from porenet.hooks import Register, hookimpl
from porenet_gravity.config import GravityInvasionConfig


@hookimpl
def porenet_register_fluid_models(register: Register) -> None:
    """Register ``gravity.invasion-percolation``; the model is imported only when selected."""
    register(GravityInvasionConfig, "porenet_gravity.model:GravityInvasionPercolation")
