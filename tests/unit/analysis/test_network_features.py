"""Pattern features without a grid (porenet.analysis.network_features): on the square lattice
they must equal the grid features exactly; on 3-D lattices and turned lattices they must
measure what the grid ones would."""

from __future__ import annotations

import numpy as np
import pytest

from porenet.analysis.features import LONG_RUN, _grid_features, pattern_features
from porenet.analysis.network_features import network_pattern_features, straight_runs_any
from porenet.kinds.rules.model import RulesClassifier
from porenet.simulation import Simulation

IP = {"kind": "invasion-percolation"}
SCENES = {
    "ip": {"fluid": IP},
    "ip-no-trapping": {"fluid": IP | {"trapping": False}},
    "viscous": {"fluid": {"kind": "viscous", "capillary_number": 1e-1}},
    "fractured": {"fluid": IP, "solid": {"kind": "hertz", "fracturing_number": 30.0}},
}


def run(seed: int, n: int = 40, **sections):
    sc = {"seed": seed, "lattice": {"n": n, "disorder": 0.5}, "classifier": {"kind": "none"}}
    return Simulation.from_scene(sc | sections).run().data


@pytest.mark.parametrize("seed", [0, 1, 2])
@pytest.mark.parametrize("name", list(SCENES))
def test_equal_to_the_grid_features_on_the_square_lattice(name, seed):
    data = run(seed, **SCENES[name])
    grid = _grid_features(data)
    any_lattice = network_pattern_features(data, LONG_RUN)
    assert grid.keys() == any_lattice.keys()
    for key, value in grid.items():
        assert any_lattice[key] == pytest.approx(value, rel=1e-12, abs=1e-12, nan_ok=True), key


def test_fractures_give_long_thin_runs():
    """The fractured pattern has thin straight runs (what the classifier calls FR)."""
    data = run(0, **SCENES["fractured"])
    runs = straight_runs_any(data, thin=True)
    assert runs.max() >= LONG_RUN


def _as_3d_layer(data):
    """The run's pattern lifted into a 3-D lattice of one layer (z = 1): the same network."""
    coords = np.column_stack([data.pore_coords, np.full(len(data.pore_coords), 1e-7)])
    return type(data)(**{**data.__dict__, "pore_coords": coords, "grid_shape": None})


def test_a_flat_3d_copy_has_the_same_features():
    data = run(1, **SCENES["viscous"])
    flat = _as_3d_layer(data)
    a, b = pattern_features(data), pattern_features(flat)
    for key in ("finger_width_mean", "longest_run", "longest_thin_run", "axis_bias"):
        assert b[key] == pytest.approx(a[key], rel=1e-12, abs=1e-12), key


def test_rules_classify_a_3d_pattern_with_a_note():
    sc = {"seed": 0, "lattice": {"kind": "cubic", "shape": [24, 24, 24], "disorder": 0.5},
          "fluid": IP, "classifier": {"kind": "none"}}  # fmt: skip
    data = Simulation.from_scene(sc).run().data
    verdict = RulesClassifier().classify(data)
    assert verdict.regime in ("CF", "VF", "CF/VF", "FR", "FR/CF", "FR/VF")
    assert "calibrated on the square lattice" in verdict.details["note"]
