"""porenet-gravity: invasion percolation in a gravity field, as a porenet fluid model.

The plugin registers one fluid kind, ``gravity.invasion-percolation`` (fields in
:mod:`.config`, physics in :mod:`.model`, the front's position and width in :mod:`.front`),
through the ``porenet.plugins`` entry point ``gravity = "porenet_gravity.plugin"``. Importing
this package imports nothing heavy; porenet imports the model only when a scene selects the
kind.
"""

from __future__ import annotations

__version__ = "0.1.0"

__all__ = ["__version__"]
