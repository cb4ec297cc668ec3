"""porenet hook implementations of porenet-correlated (entry point ``correlated``)."""

from __future__ import annotations

from porenet.hooks import Register, hookimpl
from porenet_correlated.config import CorrelatedLatticeConfig


@hookimpl
def porenet_register_lattices(register: Register) -> None:
    """Register ``correlated.gaussian``; its implementation is imported only when selected."""
    register(CorrelatedLatticeConfig, "porenet_correlated.lattice:CorrelatedLattice")
