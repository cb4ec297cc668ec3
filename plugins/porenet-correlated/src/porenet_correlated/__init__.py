"""porenet-correlated: a porenet lattice with spatially correlated throat apertures.

The plugin registers one lattice kind, ``correlated.gaussian`` (see :mod:`.config` for its
fields and :mod:`.lattice` for the algorithm), through the ``porenet.plugins`` entry point
``correlated = "porenet_correlated.plugin"``. Importing this package imports nothing heavy; the
lattice implementation is imported by porenet only when a scene selects the kind.
"""

from __future__ import annotations

__version__ = "0.1.0"

__all__ = ["__version__"]
