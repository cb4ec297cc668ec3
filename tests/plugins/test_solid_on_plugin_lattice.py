"""A third-party lattice that describes its particles and springs gets the Hertzian solid
without any change to porenet: here the square lattice turned by 30 degrees, which has no
axis-aligned springs, so the solid assembles the general sparse system instead of chains."""

from __future__ import annotations

from functools import cached_property
from typing import Literal

import numpy as np

from porenet.hooks import build_registry, hookimpl
from porenet.kinds.square.model import SquareLattice, SquareLatticeConfig
from porenet.simulation import Simulation

ANGLE = np.pi / 6


class TurnedConfig(SquareLatticeConfig):
    kind: Literal["test.turned"] = "test.turned"  # type: ignore[assignment]


class TurnedLattice(SquareLattice):
    """Pores and particles of the square lattice, rotated about the origin."""

    def _turn(self, xy: np.ndarray) -> np.ndarray:
        c, s = np.cos(ANGLE), np.sin(ANGLE)
        return xy @ np.array([[c, -s], [s, c]]).T

    @property
    def canonical_grid(self) -> bool:
        return False  # the pores are not on an axis-aligned grid any more

    @property
    def pore_coords(self) -> np.ndarray:
        return self._turn(super().pore_coords)

    @cached_property
    def particle_coords(self) -> np.ndarray:
        return self._turn(super().particle_coords)

    @cached_property
    def fixed_particles(self) -> np.ndarray:
        # the outer ring, which the default (the bounding box) cannot see on a turned lattice
        ring = np.zeros((self.n + 1, self.n + 1), dtype=bool)
        ring[0, :] = ring[-1, :] = ring[:, 0] = ring[:, -1] = True
        return ring.ravel()


class TurnedPlugin:
    @staticmethod
    @hookimpl
    def porenet_register_lattices(register) -> None:
        register(TurnedConfig, TurnedLattice)


def run(kind: str, registry) -> Simulation:
    scene = {
        "seed": 2,
        "lattice": {"kind": kind, "n": 14, "disorder": 0.1},
        "fluid": {"kind": "invasion-percolation"},
        "solid": {"kind": "hertz", "fracturing_number": 3.0},
    }
    sim = Simulation.from_scene(scene, registry=registry)
    sim.run()
    return sim


def test_turned_lattice_runs_the_sparse_solver_and_matches_the_square_one():
    registry = build_registry(extra_plugins={"turned": TurnedPlugin})
    turned = run("test.turned", registry)
    square = run("square", registry)
    assert turned.solid.solver == "sparse-direct" and square.solid.solver == "chains"
    k = square.state.record.size
    assert turned.state.record.size == k
    np.testing.assert_array_equal(turned.state.record.order[:k], square.state.record.order[:k])
    assert square.solid.removed.sum() > 0
    np.testing.assert_array_equal(turned.solid.removed, square.solid.removed)
    np.testing.assert_allclose(turned.state.apertures, square.state.apertures, atol=1e-10)
