"""The resolved config of ``linear.springs`` and what its fields mean, through porenet's public
API (its registration and the config errors naming the field are checked with the rest of
porenet's contract in test_linear_contract.py)."""

from __future__ import annotations

from types import SimpleNamespace

import pytest
from porenet_linear.config import KIND
from porenet_linear.solid import scaled_stiffness

from porenet.config.loading import load_scene
from porenet.core.errors import ConfigError
from porenet.core.plan import make_plan
from porenet.simulation import Simulation


def scene(**solid) -> dict:
    fields = {"fracturing_number": 1.0, **solid}
    return {
        "seed": 3,
        "lattice": {"kind": "square", "n": 8, "disorder": 0.3, "pore_size": 1e-4},
        "fluid": {"kind": "invasion-percolation"},
        "solid": {"kind": KIND, **{k: v for k, v in fields.items() if v is not None}},
        "classifier": {"kind": "none"},
    }


def test_defaults_and_the_plan(reg):
    config = load_scene(scene(), registry=reg).solid
    assert (config.prestrain, config.cohesion, config.coupler) == (0.05, 1e-6, "pressure-aperture")
    plan = make_plan(load_scene(scene(), registry=reg), reg)
    built = {m.family: m for m in plan.models if m.built}
    assert built["solid"].kind == KIND and built["coupler"].kind == "pressure-aperture"
    assert plan.effects["deformation"] and plan.effects["contact_loss"]


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
