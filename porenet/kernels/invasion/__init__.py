"""Invasion percolation: the precomputed sequence with and without trapping, the online variant
for deformable media, and the bitmap priority queue they share.

For plugin authors, the stable entry points are importable from here (they load with
:mod:`porenet.kernels.invasion.ip`, on first use): :func:`entry_pressures`,
:func:`invasion_sequence` and :func:`enclosed_defender` (docs/plugins.md, "Adding a fluid
model").
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:  # pragma: no cover
    from porenet.kernels.invasion.ip import enclosed_defender, entry_pressures, invasion_sequence

__all__ = ["enclosed_defender", "entry_pressures", "invasion_sequence"]


def __getattr__(name: str) -> Any:
    if name in __all__:
        return getattr(importlib.import_module("porenet.kernels.invasion.ip"), name)
    raise AttributeError(f"module 'porenet.kernels.invasion' has no attribute {name!r}")
