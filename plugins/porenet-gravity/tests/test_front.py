"""The front and its width on patterns drawn by hand (porenet_gravity.front)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from porenet_gravity.front import (
    front_history,
    front_pores,
    front_statistics,
    pore_heights,
    steady_front_width,
    throat_heights,
)

from porenet.simulation import Simulation

N = 5


@pytest.fixture(scope="module")
def lattice(reg):
    data = {
        "lattice": {"n": N, "disorder": 0.3},
        "injection": {"at": "left-edge"},
        "fluid": {"kind": "gravity.invasion-percolation", "bond_number": 0.1},
    }
    return Simulation.from_scene(data, registry=reg).lattice


def mask(cells: list[tuple[int, int]]) -> np.ndarray:
    """Drained mask of the N x N lattice from (row, column) cells."""
    out = np.zeros(N * N, dtype=bool)
    for i, j in cells:
        out[i * N + j] = True
    return out


def columns(*cols: int) -> list[tuple[int, int]]:
    return [(i, j) for j in cols for i in range(N)]


def test_heights_are_measured_in_a_from_the_inlet_column(lattice):
    z = pore_heights(lattice.pore_coords, lattice.inlet_pores("left-edge"))
    np.testing.assert_array_equal(z.reshape(N, N)[0], [0.0, 2.0, 4.0, 6.0, 8.0])
    zt = throat_heights(lattice.pore_coords, lattice.throat_pores, lattice.inlet_pores("left-edge"))
    assert zt[0] == 1.0  # horizontal throat (0, 0)-(0, 1)
    assert zt[N * (N - 1) + 1] == 2.0  # vertical throat (0, 1)-(1, 1)


def test_flat_front_has_zero_width(lattice):
    position, width, count = front_statistics(lattice, mask(columns(0, 1)))
    assert (position, width, count) == (2.0, 0.0, N)


def test_a_bump_widens_the_front(lattice):
    drained = mask([*columns(0, 1), (2, 2)])
    front = front_pores(
        lattice.adjacency, lattice.throat_pores, drained, lattice.outlet_mask("left-edge")
    )
    assert sorted(np.flatnonzero(front).tolist()) == [1, 6, 12, 16, 21]  # (2, 1) is buried
    position, width, count = front_statistics(lattice, drained)
    assert count == 5
    assert position == pytest.approx(2.4)  # heights 2, 2, 4, 2, 2
    assert width == pytest.approx(0.8)


def test_trapped_defender_is_not_part_of_the_front(lattice):
    drained = mask([c for c in columns(0, 1, 2) if c != (2, 1)])  # (2, 1) enclosed
    position, width, count = front_statistics(lattice, drained)
    assert (position, width, count) == (4.0, 0.0, N)


def test_no_front_once_everything_is_drained(lattice):
    position, width, count = front_statistics(lattice, np.ones(N * N, dtype=bool))
    assert count == 0 and math.isnan(position) and math.isnan(width)


def test_history_and_steady_width(lattice):
    cells = [*columns(0, 1), (2, 2), *(c for c in columns(2, 3) if c != (2, 2))]
    order = np.array([i * N + j for i, j in cells])
    position, width = front_history(lattice, order, np.array([N, 2 * N, 2 * N + 1]))
    np.testing.assert_allclose(position, [0.0, 2.0, 2.4])
    np.testing.assert_allclose(width, [0.0, 0.0, 0.8])
    with pytest.raises(ValueError, match="ascending"):
        front_history(lattice, order, np.array([3, 2]))
    w, kept = steady_front_width(lattice, order, window=(0.2, 0.3), snapshots=len(order))
    assert kept > 0 and 0.0 <= w <= 0.8
    assert steady_front_width(lattice, order, window=(0.9, 1.0))[1] == 0


@pytest.mark.parametrize(
    ("bond_number", "gravity", "trapping"),
    [(0.0, "stabilising", True), (0.02, "stabilising", True), (0.02, "destabilising", False)],
)
def test_one_pass_kernel_matches_the_flood_fill_of_every_snapshot(
    reg, bond_number, gravity, trapping
):
    """front_history (the reverse-pass kernel front_moments) against front_pores, which
    flood-fills the defender afresh for each pattern, after every drained pore of a run."""
    data = {
        "seed": 4,
        "lattice": {"n": 24, "disorder": 0.3},
        "injection": {"at": "left-edge"},
        "fluid": {
            "kind": "gravity.invasion-percolation",
            "bond_number": bond_number,
            "gravity": gravity,
            "trapping": trapping,
        },
        "stop": {"at": "complete"},
        "classifier": {"kind": "none"},
    }
    sim = Simulation.from_scene(data, registry=reg)
    order = sim.run().data.order
    lat = sim.lattice
    counts = np.arange(len(order) + 1)
    position, width = front_history(lat, order, counts)
    drained = np.zeros(lat.n_pores, dtype=bool)
    for k in counts:
        drained[order[:k]] = True
        expected = front_statistics(lat, drained)
        np.testing.assert_allclose([position[k], width[k]], expected[:2], rtol=1e-9, atol=1e-9)
