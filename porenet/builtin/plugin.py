"""Registers porenet's built-in kinds through the public hooks, like any third-party plugin."""

from __future__ import annotations

from porenet.builtin.classifiers import NoClassifierConfig
from porenet.builtin.classifiers.rules import RulesClassifierConfig
from porenet.builtin.classifiers.theory import TheoryClassifier, TheoryClassifierConfig
from porenet.builtin.couplers.pressure_aperture import (
    PressureApertureConfig,
    PressureApertureCoupler,
)
from porenet.builtin.fluids.invasion_percolation import (
    InvasionPercolation,
    InvasionPercolationConfig,
)
from porenet.builtin.fluids.viscous import ViscousConfig
from porenet.builtin.lattices.square import SquareLattice, SquareLatticeConfig
from porenet.builtin.observers.progress import Progress, ProgressConfig
from porenet.builtin.solids.hertz import HertzConfig
from porenet.builtin.solids.rigid import RigidConfig
from porenet.hooks import Register, hookimpl


@hookimpl
def porenet_register_lattices(register: Register) -> None:
    register(SquareLatticeConfig, SquareLattice)


@hookimpl
def porenet_register_fluid_models(register: Register) -> None:
    register(InvasionPercolationConfig, InvasionPercolation)
    register(ViscousConfig, "porenet.builtin.fluids.viscous:ViscousDrainage")


@hookimpl
def porenet_register_solid_models(register: Register) -> None:
    register(RigidConfig, None)
    register(HertzConfig, "porenet.builtin.solids.hertz:HertzSolid")


@hookimpl
def porenet_register_couplers(register: Register) -> None:
    register(PressureApertureConfig, PressureApertureCoupler)


@hookimpl
def porenet_register_observers(register: Register) -> None:
    register(ProgressConfig, Progress)


@hookimpl
def porenet_register_classifiers(register: Register) -> None:
    register(NoClassifierConfig, None)
    register(RulesClassifierConfig, "porenet.builtin.classifiers.rules:RulesClassifier")
    register(TheoryClassifierConfig, TheoryClassifier)
