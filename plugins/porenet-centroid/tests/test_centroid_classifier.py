"""The centroid classifier through porenet's public API: registry, scene, run, CLI path."""

from __future__ import annotations

import porenet_centroid.plugin
import pytest
from porenet_centroid.classifier import CentroidClassifier
from porenet_centroid.config import CentroidClassifierConfig

import porenet.hooks
from porenet.analysis.classify import classify_run
from porenet.config.loading import load_scene
from porenet.core.errors import ConfigError
from porenet.simulation import Simulation

KIND = "centroid.nearest"


@pytest.fixture
def reg(monkeypatch):
    monkeypatch.setenv("PORENET_PLUGINS", "")  # an installed copy must not clash with ours
    return porenet.hooks.build_registry(
        strict=True, extra_plugins={"centroid": porenet_centroid.plugin}
    )


def scene(**extra):
    return {
        "seed": 2,
        "lattice": {"n": 60, "disorder": 0.1},
        "fluid": {"trapping": True},
        "classifier": {"kind": KIND},
        **extra,
    }


def test_registered_lazily_under_its_package(reg):
    entry = reg.get("classifier", KIND)
    assert entry.package == "centroid" and isinstance(entry.implementation, str)


def test_a_run_is_labelled_by_the_plugin(reg):
    result = Simulation.from_scene(scene(), registry=reg).run()
    assert result.summary["classifier"] == KIND
    assert result.summary["regime"] == "CF"  # invasion percolation: capillary fingering


def test_a_fracture_is_labelled_fr(reg):
    solid = {"kind": "hertz", "fracturing_number": 10}
    result = Simulation.from_scene(scene(fluid={}, solid=solid), registry=reg).run()
    assert result.summary["regime"] == "FR"


def test_near_ties_give_the_intermediate_label(reg):
    data = Simulation.from_scene(scene(), registry=reg).run().data
    always_tied = CentroidClassifier(CentroidClassifierConfig(tie_ratio=1e-9))
    assert classify_run(data, always_tied, KIND)["regime"] in ("CF/VF", "FR/CF", "FR/VF")


def test_bad_centroids_name_the_field(reg):
    duplicate = [
        {"regime": "CF", "fractal_dimension": 1.8, "finger_width_mean": 2, "thin_run_fraction": 0},
        {"regime": "CF", "fractal_dimension": 1.6, "finger_width_mean": 1, "thin_run_fraction": 0},
    ]
    with pytest.raises(ConfigError, match=r"classifier\.centroids"):
        load_scene(scene(classifier={"kind": KIND, "centroids": duplicate}), registry=reg)
