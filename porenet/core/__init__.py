"""Interfaces, State, registry, triggers: no numerics, no I/O."""

from porenet.core.errors import ConfigError, NumericalError, PluginError, PorenetError, RunFileError
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
