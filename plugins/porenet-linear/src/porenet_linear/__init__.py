"""porenet-linear: a solid of linear (Hookean) contact springs between the particles.

The plugin registers one solid kind, ``linear.springs`` (fields in :mod:`.config`, the
mechanics as pure functions in :mod:`.springs`, the solid model in :mod:`.solid`), through the
``porenet.plugins`` entry point ``linear = "porenet_linear.plugin"``. Importing this package
imports nothing heavy; porenet imports the solid (and scipy) only when a scene selects it.
"""

from __future__ import annotations

__version__ = "0.1.0"

__all__ = ["__version__"]
