"""Registers this kind through the hook any plugin implements (docs/architecture.md, rule 1):
the config is imported here, the implementation only when a scene builds it."""

from __future__ import annotations

from porenet.hooks import Register, hookimpl
from porenet.kinds.pressure_aperture.config import PressureApertureConfig


@hookimpl
def porenet_register_couplers(register: Register) -> None:
    register(
        PressureApertureConfig, "porenet.kinds.pressure_aperture.model:PressureApertureCoupler"
    )
