"""Registration and scene validation of ``linear.springs`` through porenet's public API."""

from __future__ import annotations

import os
import subprocess
import sys
from types import SimpleNamespace

import porenet_linear.plugin
import pytest
from porenet_linear.config import KIND, LinearSpringsConfig
from porenet_linear.solid import LinearSprings, scaled_stiffness

import porenet.hooks
from porenet.config.loading import load_scene
from porenet.core.errors import ConfigError
from porenet.core.plan import make_plan
from porenet.simulation import Simulation


@pytest.fixture(scope="module")
def reg():
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("PORENET_PLUGINS", "")  # an installed copy must not clash with ours
        return porenet.hooks.build_registry(
            strict=True, extra_plugins={"linear": porenet_linear.plugin}
        )


def scene(**solid) -> dict:
    fields = {"fracturing_number": 1.0, **solid}
    return {
        "seed": 3,
        "lattice": {"kind": "square", "n": 8, "disorder": 0.3, "pore_size": 1e-4},
        "fluid": {"kind": "invasion-percolation"},
        "solid": {"kind": KIND, **{k: v for k, v in fields.items() if v is not None}},
        "classifier": {"kind": "none"},
    }


def test_registered_lazily_under_the_plugins_name(reg):
    entry = reg.get("solid", KIND)
    assert entry.config is LinearSpringsConfig
    assert entry.implementation == "porenet_linear.solid:LinearSprings"
    assert entry.plugin == "linear"
    assert entry.load() is LinearSprings


def test_plugin_import_does_not_import_the_solid_or_scipy():
    code = (
        "import sys, porenet_linear.plugin; "
        "assert 'porenet_linear.solid' not in sys.modules; "
        "assert 'scipy' not in sys.modules; "
        "assert 'numba' not in sys.modules"
    )
    src = str(porenet_linear.plugin.__file__).rsplit("porenet_linear", 1)[0]
    env = {**os.environ, "PYTHONPATH": src}
    subprocess.run([sys.executable, "-c", code], check=True, env=env, cwd=src)


def test_defaults_and_the_plan(reg):
    config = load_scene(scene(), registry=reg).solid
    assert (config.prestrain, config.cohesion, config.coupler) == (0.05, 1e-6, "pressure-aperture")
    plan = make_plan(load_scene(scene(), registry=reg), reg)
    built = {m.family: m for m in plan.models if m.built}
    assert built["solid"].kind == KIND and built["coupler"].kind == "pressure-aperture"
    assert plan.effects["deformation"] and plan.effects["contact_loss"]


@pytest.mark.parametrize(
    ("field", "value"),
    [
        ("stiffness", -1.0),
        ("fracturing_number", 0.0),
        ("fracturing_number", float("inf")),
        ("prestrain", 1.0),
        ("cohesion", 0.5),
        ("aperture_cap", 0.9),
        ("max_contact_iterations", 0),
        ("coupling", "sometimes"),
    ],
)
def test_bad_field_is_a_config_error_naming_it(reg, field, value):
    data = scene(**{field: value}, **({"fracturing_number": None} if field == "stiffness" else {}))
    with pytest.raises(ConfigError, match=rf"solid\.{field}"):
        load_scene(data, registry=reg)


def test_unknown_field_is_a_config_error_naming_it(reg):
    with pytest.raises(ConfigError, match=r"solid\.modulus: unknown field"):
        load_scene(scene(modulus=1e9), registry=reg)


@pytest.mark.parametrize("both", [True, False])
def test_exactly_one_stiffness(reg, both):
    data = scene(stiffness=10.0) if both else scene(fracturing_number=None)
    with pytest.raises(
        ConfigError, match=r"solid.*exactly one of 'stiffness'.*'fracturing_number'"
    ):
        load_scene(data, registry=reg)


def test_stiffness_in_si_is_scaled_by_gamma(reg):
    """k (N/m) / gamma (N/m): porenet's force unit is gamma a and its length a."""
    sim = Simulation.from_scene(scene(stiffness=7.0, fracturing_number=None), registry=reg)
    assert sim.solid.stiffness == pytest.approx(7.0 / 0.07, rel=1e-14)


def test_fracturing_number_needs_a_lattice_with_a_disorder(reg):
    sim = Simulation.from_scene(scene(), registry=reg)
    assert sim.solid.stiffness == pytest.approx(2 / (0.3 * 1.0), rel=1e-14)
    no_disorder = SimpleNamespace(config=SimpleNamespace())  # e.g. apertures from a file
    with pytest.raises(ConfigError, match=r"solid\.fracturing_number needs the lattice's"):
        scaled_stiffness(sim.solid.config, no_disorder, sim.context)
