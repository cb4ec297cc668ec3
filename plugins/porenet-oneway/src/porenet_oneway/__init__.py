"""porenet-oneway: one-way fluid-solid coupling.

The plugin registers the coupler kind ``oneway.pressure`` (:mod:`.model`): the solid is
loaded by the fluid's pore pressures on its own schedule, but the apertures the fluid sees
never change. With it, the solid kind ``oneway.linear``, porenet-linear's solid with a config
whose ``coupler`` field accepts this coupler (:mod:`.config`). Entry point ``oneway =
"porenet_oneway.plugin"``. Importing this package imports nothing heavy; porenet imports the
coupler and the solid only when a scene selects them.
"""

from __future__ import annotations

__version__ = "0.1.0"

__all__ = ["__version__"]
