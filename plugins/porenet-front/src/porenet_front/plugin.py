"""porenet hook implementations of porenet-front (entry point ``front``)."""

from __future__ import annotations

from porenet.hooks import Register, hookimpl
from porenet_front.config import FrontConfig


@hookimpl
def porenet_register_observers(register: Register) -> None:
    """Register ``front.interface``; the observer is imported only when a scene asks for it."""
    register(FrontConfig, "porenet_front.observer:FrontObserver")
