"""Registers this kind through the hook any plugin implements (docs/architecture.md, rule 1):
the config is imported here; the implementation, and the cost estimate and compile warm-ups
where the kind has them, are named by ``"module:name"`` and imported only when used."""

from __future__ import annotations

from porenet.hooks import Register, hookimpl
from porenet.kinds.network.config import NetworkLatticeConfig


@hookimpl
def porenet_register_lattices(register: Register) -> None:
    register(NetworkLatticeConfig, "porenet.kinds.network.model:NetworkLattice")
