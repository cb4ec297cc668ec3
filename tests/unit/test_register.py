"""``porenet.register``: a kind defined in a script or notebook joins the registry under a
plugin's rules, is replaced when registered again, and keeps the interfaces' promises
(the contract suite)."""

from __future__ import annotations

from typing import Literal

import numpy as np
import pytest

import porenet
from porenet.core.errors import PluginError
from porenet.hooks import SCRIPT_PLUGIN, build_registry
from porenet.kinds.square.config import SquareLatticeConfig
from porenet.kinds.square.model import SquareLattice
from porenet.simulation import Simulation
from porenet.testing.contract import check_kind


class WideConfig(SquareLatticeConfig):
    """The square lattice with every throat twice as wide."""

    kind: Literal["mine.wide"] = "mine.wide"  # type: ignore[assignment]


class Wide(SquareLattice):
    def draw_apertures(self, rng: np.random.Generator) -> np.ndarray:
        return 2.0 * super().draw_apertures(rng)


class Wider(SquareLattice):
    def draw_apertures(self, rng: np.random.Generator) -> np.ndarray:
        return 3.0 * super().draw_apertures(rng)


SCENE = {"seed": 3, "lattice": {"kind": "mine.wide", "n": 12, "disorder": 0.3}, "fluid": {}}
SQUARE = {**SCENE, "lattice": {**SCENE["lattice"], "kind": "square"}}


@pytest.fixture
def process_registry(monkeypatch):
    """A fresh process-wide registry, so that the kinds a test registers go with it."""
    import porenet.hooks

    registry = build_registry(strict=True)
    monkeypatch.setattr(porenet.hooks, "_REGISTRY", registry)
    return registry


def test_a_registered_kind_runs_through_porenet_run(process_registry):
    entry = porenet.register(WideConfig, Wide)
    assert (entry.family, entry.kind, entry.plugin) == ("lattice", "mine.wide", SCRIPT_PLUGIN)
    assert entry.package == __name__  # the module that defined the config
    wide = porenet.run(SCENE).data
    square = porenet.run(SQUARE).data
    # the same random draw, twice as wide: invasion percolation's order is unchanged
    assert np.allclose(wide.apertures, 2.0 * square.apertures)
    assert np.array_equal(wide.order, square.order)


def test_registering_again_replaces_the_kind(process_registry):
    porenet.register(WideConfig, Wide)
    porenet.register(WideConfig, Wider)  # the notebook cell, edited and run again
    assert process_registry.get("lattice", "mine.wide").load() is Wider
    wider = porenet.run(SCENE).data
    square = porenet.run(SQUARE).data
    assert np.allclose(wider.apertures, 3.0 * square.apertures)


def test_a_plugins_kind_is_never_replaced():
    registry = build_registry(strict=True)
    registry.add("lattice", WideConfig, Wide, package="mine", plugin="mine")
    with pytest.raises(PluginError, match=r"registered twice.*'mine'"):
        porenet.register(WideConfig, Wider, registry=registry)


def test_the_family_is_told_from_the_implementation_or_asked_for():
    registry = build_registry(strict=True)
    with pytest.raises(PluginError, match="give family="):
        porenet.register(WideConfig, None, registry=registry)
    with pytest.raises(PluginError, match="give family="):
        porenet.register(WideConfig, "mine:Wide", registry=registry)
    entry = porenet.register(WideConfig, f"{__name__}:Wide", family="lattice",
                             registry=registry)  # fmt: skip
    assert entry.load() is Wide


def test_the_plugin_rules_hold():
    registry = build_registry(strict=True)

    class Bare(SquareLatticeConfig):
        kind: Literal["bare"] = "bare"  # type: ignore[assignment]

    with pytest.raises(PluginError, match="must be namespaced"):
        porenet.register(Bare, Wide, registry=registry)
    with pytest.raises(PluginError, match="unknown family"):
        porenet.register(WideConfig, Wide, family="lattices", registry=registry)


def test_the_registered_kind_keeps_the_lattice_contract():
    registry = build_registry(strict=True)
    porenet.register(WideConfig, Wide, registry=registry)
    check_kind("lattice", "mine.wide", scene=SCENE, registry=registry)


def test_simulation_takes_the_registry_given():
    registry = build_registry(strict=True)
    porenet.register(WideConfig, Wide, registry=registry)
    result = Simulation.from_scene(SCENE, registry=registry).run()
    assert result.summary["n_drained"] > 0
