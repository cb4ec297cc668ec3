"""porenet-delaunay: a 2-D random pore network that is not a grid underneath.

The plugin registers one lattice kind, ``delaunay.random`` (fields in :mod:`.config`, the
network and the lattice in :mod:`.model`), through the ``porenet.plugins`` entry point
``delaunay = "porenet_delaunay.plugin"``. Importing this package imports nothing heavy;
porenet imports the lattice (and scipy) only when a scene selects the kind.
"""

from __future__ import annotations

__version__ = "0.1.0"

__all__ = ["__version__"]
