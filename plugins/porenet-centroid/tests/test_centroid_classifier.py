"""The centroid classifier's verdicts on real runs (its contract: test_centroid_contract.py)."""

from __future__ import annotations

import pytest
from porenet_centroid.classifier import CentroidClassifier
from porenet_centroid.config import CentroidClassifierConfig

from porenet.analysis.classify import classify_run
from porenet.config.loading import load_scene
from porenet.core.errors import ConfigError
from porenet.simulation import Simulation

KIND = "centroid.nearest"


def scene(**extra):
    return {
        "seed": 2,
        "lattice": {"n": 60, "disorder": 0.1},
        "fluid": {"trapping": True},
        "classifier": {"kind": KIND},
        **extra,
    }


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
