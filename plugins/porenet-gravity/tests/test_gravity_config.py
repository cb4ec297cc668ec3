"""The resolved config, the plan and the scenes the model refuses, through porenet's public API
(its registration and the config errors naming the field are checked with the rest of
porenet's contract in test_gravity_contract.py)."""

from __future__ import annotations

import pytest
from porenet_gravity.config import KIND, GravityInvasionConfig

from porenet.config.loading import load_scene
from porenet.core.errors import ConfigError
from porenet.core.plan import make_plan
from porenet.simulation import Simulation


def scene(**fluid):
    return {
        "seed": 3,
        "lattice": {"kind": "square", "n": 21, "disorder": 0.3},
        "injection": {"at": "left-edge"},
        "fluid": {"kind": KIND, "bond_number": 0.01, **fluid},
        "classifier": {"kind": "none"},
    }


def test_defaults_and_resolved_config(reg):
    config = load_scene(scene(), registry=reg).fluid
    assert isinstance(config, GravityInvasionConfig)
    assert (config.bond_number, config.gravity, config.trapping) == (0.01, "stabilising", True)
    assert config.interfacial_tension == 0.07
    assert config.sign == 1.0
    assert GravityInvasionConfig(bond_number=0.0, gravity="destabilising").sign == -1.0


def test_plan_lists_gravity_and_the_package(reg):
    plan = make_plan(load_scene(scene(), registry=reg), reg)
    assert plan.effects["gravity"] is True
    assert plan.effects["viscous_dissipation"] is False
    fluid = next(m for m in plan.models if m.family == "fluid")
    assert (fluid.kind, fluid.package) == (KIND, reg.get("fluid", KIND).package)
    assert (
        make_plan(load_scene(scene(bond_number=0), registry=reg), reg).effects["gravity"] is False
    )


def test_centre_injection_is_refused_before_the_run(reg):
    data = scene()
    data["injection"] = {"at": "centre"}
    with pytest.raises(ConfigError, match="left-edge"):
        Simulation.from_scene(data, registry=reg)


def test_deformable_solid_is_refused_before_the_run(reg):
    data = scene()
    data["solid"] = {"kind": "hertz", "fracturing_number": 0.5}
    with pytest.raises(ConfigError, match="rigid media only"):
        Simulation.from_scene(data, registry=reg)
