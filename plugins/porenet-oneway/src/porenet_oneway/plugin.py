"""porenet hook implementations of porenet-oneway (entry point ``oneway``)."""

from __future__ import annotations

from porenet.hooks import Register, hookimpl
from porenet_oneway.config import OneWayConfig


@hookimpl
def porenet_register_couplers(register: Register) -> None:
    """Register ``oneway.pressure``; the coupler is imported only when a scene selects it."""
    register(OneWayConfig, "porenet_oneway.model:OneWayCoupler")
