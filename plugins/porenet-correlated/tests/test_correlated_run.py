"""The plugin through porenet's public API: registry, scene validation, a full run."""

from __future__ import annotations

import os
import subprocess
import sys

import numpy as np
import porenet_correlated.plugin
import pytest
from porenet_correlated.lattice import CorrelatedLattice

import porenet.hooks
from porenet.config.loading import load_scene
from porenet.core.errors import ConfigError
from porenet.core.plan import make_plan
from porenet.simulation import Simulation


@pytest.fixture
def reg(monkeypatch):
    monkeypatch.setenv("PORENET_PLUGINS", "")  # an installed copy must not clash with ours
    return porenet.hooks.build_registry(
        strict=True, extra_plugins={"correlated": porenet_correlated.plugin}
    )


def scene(**lattice):
    return {
        "seed": 3,
        "lattice": {
            "kind": "correlated.gaussian",
            "n": 31,
            "disorder": 0.3,
            "correlation_length": 4.0,
            **lattice,
        },
        "fluid": {"kind": "invasion-percolation", "trapping": True},
        "stop": {"at": "breakthrough"},
    }


def test_registered_lazily_under_a_namespaced_kind(reg):
    entry = reg.get("lattice", "correlated.gaussian")
    assert entry.implementation == "porenet_correlated.lattice:CorrelatedLattice"
    assert entry.plugin == "correlated"
    assert entry.load() is CorrelatedLattice


def test_plugin_import_does_not_import_the_implementation():
    code = (
        "import sys, porenet_correlated.plugin; "
        "assert 'porenet_correlated.lattice' not in sys.modules"
    )
    src = str(porenet_correlated.plugin.__file__).rsplit("porenet_correlated", 1)[0]
    env = {**os.environ, "PYTHONPATH": src}
    subprocess.run([sys.executable, "-c", code], check=True, env=env, cwd=src)


def test_full_run(reg):
    config = load_scene(scene(), registry=reg)
    assert config.lattice.kind == "correlated.gaussian"
    sim = Simulation(make_plan(config, reg), reg)
    assert isinstance(sim.lattice, CorrelatedLattice)
    result = sim.run()
    assert result.summary["stop_reason"] == "breakthrough"
    assert result.summary["n_drained"] > 1
    again = Simulation(make_plan(load_scene(scene(), registry=reg), reg), reg)
    np.testing.assert_array_equal(again.lattice.initial_apertures, sim.lattice.initial_apertures)


@pytest.mark.parametrize("value", [-1.0, 0.0, 1001.0])
def test_bad_correlation_length_is_a_config_error(reg, value):
    with pytest.raises(ConfigError, match=r"lattice\.correlation_length"):
        load_scene(scene(correlation_length=value), registry=reg)


def test_missing_correlation_length_is_a_config_error(reg):
    data = scene()
    del data["lattice"]["correlation_length"]
    with pytest.raises(ConfigError, match=r"lattice\.correlation_length: required"):
        load_scene(data, registry=reg)


def test_misspelt_field_is_named(reg):
    data = scene()
    data["lattice"]["correlation_lenght"] = data["lattice"].pop("correlation_length")
    with pytest.raises(ConfigError, match="did you mean 'correlation_length'"):
        load_scene(data, registry=reg)


def test_apertures_file_is_rejected(reg, tmp_path):
    path = tmp_path / "ap.npz"
    np.savez(path, apertures=np.full(2 * 31 * 30, 1e-7))
    with pytest.raises(ConfigError, match="apertures_file"):
        load_scene(scene(apertures_file=str(path)), registry=reg)
