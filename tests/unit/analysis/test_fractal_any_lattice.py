"""Fractal dimension on lattices without a grid layout and in 3-D (docs/fractal.md):
mass-radius in d dimensions, box counting over cells of one spacing; exact dimensions of
filled sets, and the same counts as the grid path on a square lattice."""

from __future__ import annotations

import numpy as np
import pytest

from porenet.analysis.fractal import _box_counting, mass_radius, occupancy, pattern_dimension
from porenet.simulation import Simulation


def cube(n: int, d: int) -> np.ndarray:
    """Pore centres of an n^d block, spacing 1."""
    axes = np.meshgrid(*[np.arange(n, dtype=float)] * d, indexing="ij")
    return np.stack([a.ravel() for a in axes], axis=1)


@pytest.mark.parametrize(("dims", "expected"), [((1, 1, 64), 1.0), ((1, 64, 64), 2.0),
                                                ((32, 32, 32), 3.0)])  # fmt: skip
def test_box_counting_of_filled_sets_in_3d(dims, expected):
    grid = np.ones(dims, dtype=bool)
    fit = _box_counting(grid, 2.0, 16.0)
    assert fit.dimension == pytest.approx(expected, abs=1e-12)


def test_mass_radius_of_a_filled_ball_is_3():
    xyz = cube(41, 3)
    centre = np.full(3, 20.0)
    ball = np.linalg.norm(xyz - centre, axis=1) <= 20
    fit = mass_radius(ball, xyz, centre, spacing=1.0, r_min=4, r_max=16)
    assert fit.dimension == pytest.approx(3.0, abs=0.05)


def test_mass_radius_refuses_mismatched_dimensions():
    with pytest.raises(ValueError, match="coords \\(N, d\\) and centre \\(d,\\)"):
        mass_radius(np.ones(8, bool), cube(2, 3), np.zeros(2))


def test_occupancy_box_counts_match_the_grid_on_a_square_lattice():
    sc = {"seed": 1, "lattice": {"n": 64, "disorder": 0.5},
          "fluid": {"kind": "invasion-percolation"}, "classifier": {"kind": "none"}}  # fmt: skip
    data = Simulation.from_scene(sc).run().data
    grid_fit = _box_counting(data.as_grid(data.drained), None, None)
    cells = occupancy(data.drained, data.pore_coords, 2.0 * data.pore_size)
    assert cells.T.shape == (64, 64)
    np.testing.assert_array_equal(cells.T, data.as_grid(data.drained))
    coord_fit = _box_counting(cells, None, None)
    np.testing.assert_array_equal(coord_fit.counts, grid_fit.counts)


def test_3d_pattern_dimension_by_both_methods():
    sc = {"seed": 0, "lattice": {"kind": "cubic", "shape": [48, 48, 48], "disorder": 0.5},
          "fluid": {"kind": "invasion-percolation", "trapping": False},
          "stop": {"at": "complete", "max_drained": 20000},
          "classifier": {"kind": "none"}}  # fmt: skip
    data = Simulation.from_scene(sc).run().data
    for method in ("mass-radius", "box-counting"):
        fit = pattern_dimension(data, method)
        # an invasion cluster in 3-D is between a line and a filled volume; the bias tables
        # are for 2-D lattices, so none is applied here
        assert 1.5 < fit.dimension < 3.0 and np.isnan(fit.bias), (method, fit.dimension)
