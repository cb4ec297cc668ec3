"""Interfaces, State, registry, triggers: no numerics, no I/O.

The names below load on first use, so that importing :mod:`porenet.core.errors` (the command
line's checks do, for every command) does not import numpy with the interfaces.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:  # pragma: no cover
    from porenet.core.errors import (
        ConfigError,
        NumericalError,
        PluginError,
        PorenetError,
        RunFileError,
    )
    from porenet.core.interfaces import (
        Classification,
        Classifier,
        Coupler,
        FluidModel,
        Lattice,
        Observer,
        RunContext,
        SolidModel,
    )
    from porenet.core.state import DrainageRecord, State
    from porenet.core.units import Scales

_LAZY = {
    "ConfigError": "porenet.core.errors",
    "NumericalError": "porenet.core.errors",
    "PluginError": "porenet.core.errors",
    "PorenetError": "porenet.core.errors",
    "RunFileError": "porenet.core.errors",
    "Classification": "porenet.core.interfaces",
    "Classifier": "porenet.core.interfaces",
    "Coupler": "porenet.core.interfaces",
    "FluidModel": "porenet.core.interfaces",
    "Lattice": "porenet.core.interfaces",
    "Observer": "porenet.core.interfaces",
    "RunContext": "porenet.core.interfaces",
    "SolidModel": "porenet.core.interfaces",
    "DrainageRecord": "porenet.core.state",
    "State": "porenet.core.state",
    "Scales": "porenet.core.units",
}

__all__ = [
    "Classification",
    "Classifier",
    "ConfigError",
    "Coupler",
    "DrainageRecord",
    "FluidModel",
    "Lattice",
    "NumericalError",
    "Observer",
    "PluginError",
    "PorenetError",
    "RunContext",
    "RunFileError",
    "Scales",
    "SolidModel",
    "State",
]


def __getattr__(name: str) -> Any:
    if name in _LAZY:
        return getattr(importlib.import_module(_LAZY[name]), name)
    raise AttributeError(f"module 'porenet.core' has no attribute {name!r}")
