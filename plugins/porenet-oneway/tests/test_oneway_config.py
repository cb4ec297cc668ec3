"""How a scene selects the coupler: a solid accepts the coupler kinds its ``coupler`` field
lists; the plan names the coupler and its package; the Simulation builds it from the
solid's section."""

from __future__ import annotations

import pytest
from porenet_oneway.config import KIND, SOLID_KIND, OneWayConfig
from porenet_oneway.model import OneWayCoupler

from porenet.config.loading import load_scene
from porenet.core.errors import ConfigError
from porenet.core.plan import make_plan
from porenet.simulation import Simulation


def test_the_kinds_are_registered_under_the_plugins_name(reg):
    coupler, solid = reg.get("coupler", KIND), reg.get("solid", SOLID_KIND)
    assert coupler.plugin == solid.plugin == "oneway"
    assert coupler.implementation == "porenet_oneway.model:OneWayCoupler"
    assert solid.implementation == "porenet_linear.solid:LinearSprings"


def test_the_solid_couples_one_way_by_default_and_two_way_when_asked(reg):
    scene = OneWayConfig.example_scene()
    for coupler in (None, "pressure-aperture"):
        if coupler is not None:
            scene["solid"]["coupler"] = coupler
        config = load_scene(scene, registry=reg)
        plan = make_plan(config, reg)
        (row,) = [m for m in plan.models if m.family == "coupler"]
        assert row.built and row.kind == (coupler or KIND)
        assert row.package == ("porenet" if coupler else reg.get("coupler", KIND).package)
        built = Simulation(plan, reg).coupler
        assert isinstance(built, OneWayCoupler) == (coupler is None)
        assert built.config is config.solid  # a coupler reads the solid's section


@pytest.mark.parametrize("solid", [{"kind": "hertz"}, {"kind": "linear.springs"}])
def test_a_solid_that_does_not_list_the_coupler_refuses_it(reg, solid):
    scene = OneWayConfig.example_scene()
    scene["solid"] = solid | {"fracturing_number": 1.0, "coupler": KIND}
    with pytest.raises(ConfigError, match=r"solid\.coupler"):
        load_scene(scene, registry=reg)
