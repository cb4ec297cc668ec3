"""Registers this kind through the hook any plugin implements (docs/architecture.md, rule 1):
the config is imported here, the implementation only when a scene builds it."""

from __future__ import annotations

from porenet.hooks import Register, hookimpl
from porenet.kinds.cubic.config import CubicLatticeConfig


@hookimpl
def porenet_register_lattices(register: Register) -> None:
    register(CubicLatticeConfig, "porenet.kinds.cubic.model:CubicLattice")
