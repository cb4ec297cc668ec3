"""Registration, scene validation and the scenes the model refuses, through porenet's public API."""

from __future__ import annotations

import os
import subprocess
import sys

import porenet_gravity.plugin
import pytest
from porenet_gravity.config import KIND, GravityInvasionConfig
from porenet_gravity.model import GravityInvasionPercolation

import porenet.hooks
from porenet.config.loading import load_scene
from porenet.core.errors import ConfigError
from porenet.core.plan import make_plan
from porenet.simulation import Simulation


@pytest.fixture
def reg(monkeypatch):
    monkeypatch.setenv("PORENET_PLUGINS", "")  # an installed copy must not clash with ours
    return porenet.hooks.build_registry(
        strict=True, extra_plugins={"gravity": porenet_gravity.plugin}
    )


def scene(**fluid):
    return {
        "seed": 3,
        "lattice": {"kind": "square", "n": 21, "disorder": 0.3},
        "injection": {"at": "left-edge"},
        "fluid": {"kind": KIND, "bond_number": 0.01, **fluid},
        "classifier": {"kind": "none"},
    }


def test_registered_lazily_under_a_namespaced_kind(reg):
    entry = reg.get("fluid", "gravity.invasion-percolation")
    assert entry.config is GravityInvasionConfig
    assert entry.implementation == "porenet_gravity.model:GravityInvasionPercolation"
    assert entry.plugin == "gravity"
    assert entry.load() is GravityInvasionPercolation


def test_plugin_import_does_not_import_the_model():
    code = (
        "import sys, porenet_gravity.plugin; "
        "assert 'porenet_gravity.model' not in sys.modules; "
        "assert 'porenet.kinds.invasion.kernels.ip' not in sys.modules; "
        "assert 'numba' not in sys.modules"
    )
    src = str(porenet_gravity.plugin.__file__).rsplit("porenet_gravity", 1)[0]
    env = {**os.environ, "PYTHONPATH": src}
    subprocess.run([sys.executable, "-c", code], check=True, env=env, cwd=src)


def test_defaults_and_resolved_config(reg):
    config = load_scene(scene(), registry=reg).fluid
    assert isinstance(config, GravityInvasionConfig)
    assert (config.bond_number, config.gravity, config.trapping) == (0.01, "stabilising", True)
    assert config.interfacial_tension == 0.07
    assert config.sign == 1.0
    assert GravityInvasionConfig(bond_number=0.0, gravity="destabilising").sign == -1.0


@pytest.mark.parametrize("value", [-1e-3, float("nan"), float("inf"), "much"])
def test_bad_bond_number_is_a_config_error_naming_the_field(reg, value):
    with pytest.raises(ConfigError, match=r"fluid\.bond_number"):
        load_scene(scene(bond_number=value), registry=reg)


def test_missing_bond_number_is_a_config_error_naming_the_field(reg):
    data = scene()
    del data["fluid"]["bond_number"]
    with pytest.raises(ConfigError, match=r"fluid\.bond_number: required"):
        load_scene(data, registry=reg)


@pytest.mark.parametrize(
    ("field", "value"),
    [("gravity", "sideways"), ("interfacial_tension", 0.0), ("trapping", "maybe")],
)
def test_other_bad_fields_are_named(reg, field, value):
    with pytest.raises(ConfigError, match=rf"fluid\.{field}"):
        load_scene(scene(**{field: value}), registry=reg)


def test_misspelt_field_is_named(reg):
    data = scene()
    data["fluid"]["bond_numbr"] = data["fluid"].pop("bond_number")
    with pytest.raises(ConfigError, match="did you mean 'bond_number'"):
        load_scene(data, registry=reg)


def test_config_is_frozen():
    config = GravityInvasionConfig(bond_number=0.01)
    with pytest.raises(ValueError, match="frozen"):
        config.bond_number = 0.02  # type: ignore[misc]


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
