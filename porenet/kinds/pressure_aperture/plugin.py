"""Registers this kind through the hook any plugin implements (docs/architecture.md, rule 1):
the config is imported here; the implementation, and the cost estimate and compile warm-ups
where the kind has them, are named by ``"module:name"`` and imported only when used."""

from __future__ import annotations

from porenet.hooks import Register, hookimpl
from porenet.kinds.pressure_aperture.config import PressureApertureConfig


@hookimpl
def porenet_register_couplers(register: Register) -> None:
    register(
        PressureApertureConfig, "porenet.kinds.pressure_aperture.model:PressureApertureCoupler"
    )
