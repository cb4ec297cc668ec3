"""Invasion percolation: the precomputed sequence with and without trapping, the online variant
for deformable media, and the bitmap priority queue they share.

For plugin authors, the stable entry points are importable from here (they load on first use,
from :mod:`porenet.kinds.invasion.kernels.ip` and :mod:`porenet.kinds.invasion.kernels.trapping`):
:func:`entry_pressures`, :func:`invasion_sequence` and :func:`enclosed_defender`
(docs/plugins.md, "Adding a fluid model").
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:  # pragma: no cover
    from porenet.kinds.invasion.kernels.ip import entry_pressures, invasion_sequence
    from porenet.kinds.invasion.kernels.trapping import enclosed_defender

__all__ = ["enclosed_defender", "entry_pressures", "invasion_sequence"]


_HOME = {
    "enclosed_defender": "porenet.kinds.invasion.kernels.trapping",
    "entry_pressures": "porenet.kinds.invasion.kernels.ip",
    "invasion_sequence": "porenet.kinds.invasion.kernels.ip",
}


def __getattr__(name: str) -> Any:
    if name in _HOME:
        return getattr(importlib.import_module(_HOME[name]), name)
    raise AttributeError(f"module 'porenet.kinds.invasion.kernels' has no attribute {name!r}")
