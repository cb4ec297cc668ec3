"""porenet hook implementations of porenet-linear (entry point ``linear``)."""

from __future__ import annotations

from porenet.hooks import Register, hookimpl
from porenet_linear.config import LinearSpringsConfig


@hookimpl
def porenet_register_solid_models(register: Register) -> None:
    """Register ``linear.springs``; the solid is imported only when a scene selects it."""
    register(LinearSpringsConfig, "porenet_linear.solid:LinearSprings")
