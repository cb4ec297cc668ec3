"""porenet-front: an observer that records the invasion front over a porenet run.

The plugin registers one observer kind, ``front.interface`` (fields in :mod:`.config`, the
front's measures in :mod:`.front`, the observer in :mod:`.observer`), through the
``porenet.plugins`` entry point ``front = "porenet_front.plugin"``. Importing this package
imports nothing heavy; porenet imports the observer only when a scene asks for it.
"""

from __future__ import annotations

__version__ = "0.1.0"

__all__ = ["__version__"]
