"""How a scene selects the coupler: the solid's ``coupler`` field names any registered coupler;
the plan names it and its package and turns the aperture feedback off; the Simulation builds
it from the solid's section; an unknown coupler is refused naming the field."""

from __future__ import annotations

import pytest
from porenet_oneway.config import KIND, OneWayConfig
from porenet_oneway.model import OneWayCoupler

from porenet.config.loading import load_scene
from porenet.core.errors import ConfigError
from porenet.core.plan import make_plan
from porenet.simulation import Simulation


def test_the_kind_is_registered_under_the_plugins_name(reg):
    coupler = reg.get("coupler", KIND)
    assert coupler.plugin == "oneway"
    assert coupler.implementation == "porenet_oneway.model:OneWayCoupler"


@pytest.mark.parametrize("coupler", [KIND, "pressure-aperture"])
def test_the_solid_names_its_coupler_and_the_plan_says_whether_apertures_change(reg, coupler):
    scene = OneWayConfig.example_scene()
    scene["solid"]["coupler"] = coupler
    config = load_scene(scene, registry=reg)
    plan = make_plan(config, reg)
    (row,) = [m for m in plan.models if m.family == "coupler"]
    assert row.built and row.kind == coupler
    assert row.package == ("porenet" if coupler != KIND else reg.get("coupler", KIND).package)
    assert plan.effects["deformation"] and plan.effects["aperture_feedback"] == (coupler != KIND)
    sim = Simulation(plan, reg)
    assert isinstance(sim.coupler, OneWayCoupler) == (coupler == KIND)
    assert sim.coupler.config is config.solid  # a coupler reads the solid's section
    assert sim.context.deformable == (coupler != KIND)  # fluids precompute when one way


def test_an_unknown_coupler_is_refused_naming_the_field(reg):
    scene = OneWayConfig.example_scene()
    scene["solid"]["coupler"] = "oneway.presure"
    with pytest.raises(ConfigError, match=r"solid\.coupler.*did you mean 'oneway.pressure'"):
        load_scene(scene, registry=reg)
