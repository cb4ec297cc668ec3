"""porenet hook implementations of porenet-delaunay (entry point ``delaunay``)."""

from __future__ import annotations

from porenet.hooks import Register, hookimpl
from porenet_delaunay.config import DelaunayLatticeConfig


@hookimpl
def porenet_register_lattices(register: Register) -> None:
    """Register ``delaunay.random``; the lattice (and scipy) is imported only when a scene
    selects it."""
    register(DelaunayLatticeConfig, "porenet_delaunay.model:DelaunayLattice")
