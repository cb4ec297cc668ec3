"""porenet hook implementations of porenet-oneway (entry point ``oneway``)."""

from __future__ import annotations

from porenet.hooks import Register, hookimpl
from porenet_oneway.config import OneWayConfig, OneWayLinearConfig


@hookimpl
def porenet_register_couplers(register: Register) -> None:
    """Register ``oneway.pressure``; the coupler is imported only when a scene selects it."""
    register(OneWayConfig, "porenet_oneway.model:OneWayCoupler")


@hookimpl
def porenet_register_solid_models(register: Register) -> None:
    """Register ``oneway.linear``: porenet-linear's solid, which this config lets a scene
    couple one way; the solid is imported only when a scene selects it."""
    register(OneWayLinearConfig, "porenet_linear.solid:LinearSprings")
