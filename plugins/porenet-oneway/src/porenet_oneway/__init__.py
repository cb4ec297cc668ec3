"""porenet-oneway: one-way fluid-solid coupling.

The plugin registers the coupler kind ``oneway.pressure`` (:mod:`.model`): the solid is
loaded by the fluid's pore pressures on its own schedule, but the apertures the fluid sees
never change (:mod:`.config`: ``feeds_back = False``). A scene selects it in its solid's
section, ``coupler = "oneway.pressure"``. Entry point ``oneway = "porenet_oneway.plugin"``.
Importing this package imports nothing heavy; porenet imports the coupler only when a scene
selects it.
"""

from __future__ import annotations

__version__ = "0.1.0"

__all__ = ["__version__"]
