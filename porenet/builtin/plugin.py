"""Registers porenet's built-in kinds through the public hooks, like any third-party plugin.

Only the light config modules (``porenet/builtin/*/config.py``, pydantic and porenet's light
modules) are imported here; every implementation is a ``"module:Class"`` string, imported only
when a scene builds the kind (docs/architecture.md, "Configs live apart from their
implementations").
"""

from __future__ import annotations

from porenet.builtin.classifiers import NoClassifierConfig
from porenet.builtin.classifiers.config import RulesClassifierConfig, TheoryClassifierConfig
from porenet.builtin.couplers.config import PressureApertureConfig
from porenet.builtin.fluids.config import InvasionPercolationConfig, ViscousConfig
from porenet.builtin.lattices.config import CubicLatticeConfig, SquareLatticeConfig
from porenet.builtin.lattices.network_config import NetworkLatticeConfig
from porenet.builtin.observers.config import ProgressConfig, SnapshotsConfig
from porenet.builtin.solids.config import HertzConfig, HertzMindlinConfig
from porenet.builtin.solids.rigid import RigidConfig
from porenet.hooks import Register, hookimpl


@hookimpl
def porenet_register_lattices(register: Register) -> None:
    register(SquareLatticeConfig, "porenet.builtin.lattices.square:SquareLattice")
    register(CubicLatticeConfig, "porenet.builtin.lattices.cubic:CubicLattice")
    register(NetworkLatticeConfig, "porenet.builtin.lattices.network:NetworkLattice")


@hookimpl
def porenet_register_fluid_models(register: Register) -> None:
    register(
        InvasionPercolationConfig,
        "porenet.builtin.fluids.invasion_percolation:InvasionPercolation",
    )
    register(ViscousConfig, "porenet.builtin.fluids.viscous:ViscousDrainage")


@hookimpl
def porenet_register_solid_models(register: Register) -> None:
    register(RigidConfig, None)
    register(HertzConfig, "porenet.builtin.solids.hertz:HertzSolid")
    register(HertzMindlinConfig, "porenet.builtin.solids.mindlin:HertzMindlinSolid")


@hookimpl
def porenet_register_couplers(register: Register) -> None:
    register(
        PressureApertureConfig,
        "porenet.builtin.couplers.pressure_aperture:PressureApertureCoupler",
    )


@hookimpl
def porenet_register_observers(register: Register) -> None:
    register(ProgressConfig, "porenet.builtin.observers.progress:Progress")
    register(SnapshotsConfig, "porenet.builtin.observers.snapshots:Snapshots")


@hookimpl
def porenet_register_classifiers(register: Register) -> None:
    register(NoClassifierConfig, None)
    register(RulesClassifierConfig, "porenet.builtin.classifiers.rules:RulesClassifier")
    register(TheoryClassifierConfig, "porenet.builtin.classifiers.theory:TheoryClassifier")
