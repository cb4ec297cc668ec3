"""The simple cubic lattice, kind ``cubic`` (docs/lattices.md, "The cubic lattice").

Pores sit at the cell centres of an ``nx x ny x nz`` grid: pore ``(k, i, j)`` (layer k along
z, row i along y, column j along x) has index ``(k ny + i) nx + j`` and centre
``(2j + 1, 2i + 1, 2k + 1)`` in units of ``a`` (node spacing 2a, throat length 2a, as on the
square lattice). Canonical throat order: the x throats ``(k,i,j)-(k,i,j+1)``, then the y throats
``(k,i,j)-(k,i+1,j)``, then the z throats ``(k,i,j)-(k+1,i,j)``, each in the order of their
first pore. With ``nz = 1`` the lattice is 2-D (coordinates ``(x, y)``) and, with ``nx = ny =
n``, the pores, throats, apertures and particles are the square lattice's
(:mod:`porenet.kinds.square.model`), so every run gives the square lattice's result to the
bit (``porenet/kinds/cubic/tests/test_cubic_lattice.py``).

Deformable solids need particles: only the 2-D square case (``nz = 1``, ``nx = ny``) has them
(a throat between two cubic pores passes a face bounded by four contacts, so the paper's one
spring per throat does not carry over to 3-D: docs/roadmap.md).
"""

from __future__ import annotations

from functools import cached_property
from typing import Any

import numpy as np

from porenet.core.interfaces import Lattice
from porenet.kinds.cubic.config import CubicLatticeConfig, load_cubic_apertures_file
from porenet.kinds.square.model import particle_coords, spring_particles


def cubic_throats(shape: tuple[int, int, int]) -> np.ndarray:
    """(M, 2) int64 pore pairs of an ``nx x ny x nz`` lattice in canonical order."""
    nx, ny, nz = shape
    idx = np.arange(nx * ny * nz, dtype=np.int64).reshape(nz, ny, nx)
    pairs = [
        (idx[:, :, :-1], idx[:, :, 1:]),  # x
        (idx[:, :-1, :], idx[:, 1:, :]),  # y
        (idx[:-1, :, :], idx[1:, :, :]),  # z
    ]
    return np.concatenate([np.stack([a.ravel(), b.ravel()], axis=1) for a, b in pairs])


class CubicLattice(Lattice):
    """Simple cubic lattice of ``nx x ny x nz`` pores with uniform apertures."""

    config: CubicLatticeConfig

    def __init__(self, config: Any, rng: np.random.Generator) -> None:
        super().__init__(config, rng)
        self.shape = tuple(int(s) for s in config.shape)
        if config.apertures_file is not None:
            r = load_cubic_apertures_file(config.apertures_file, self.shape) / config.pore_size
        else:
            lam = float(config.disorder)
            r0 = self.mean_aperture
            r = rng.uniform((1.0 - lam) * r0, (1.0 + lam) * r0, size=self.n_throats)
        r.setflags(write=False)
        self._apertures = r

    # -- pore network ---------------------------------------------------------------------
    @property
    def n_pores(self) -> int:
        nx, ny, nz = self.shape
        return nx * ny * nz

    @cached_property
    def throat_pores(self) -> np.ndarray:
        throats = cubic_throats(self.shape)
        throats.setflags(write=False)
        return throats

    @property
    def n_throats(self) -> int:
        nx, ny, nz = self.shape
        return (nx - 1) * ny * nz + nx * (ny - 1) * nz + nx * ny * (nz - 1)

    @cached_property
    def pore_coords(self) -> np.ndarray:
        nx, ny, nz = self.shape
        k, rest = np.divmod(np.arange(self.n_pores), nx * ny)
        i, j = np.divmod(rest, nx)
        columns = [2.0 * j + 1.0, 2.0 * i + 1.0] + ([2.0 * k + 1.0] if nz > 1 else [])
        coords = np.stack(columns, axis=1)
        coords.setflags(write=False)
        return coords

    @cached_property
    def _faces_touched(self) -> np.ndarray:
        """(n_pores,) float: how many faces of the box (edges in 2-D) each pore lies on."""
        count = np.zeros(self.shape[::-1])  # (nz, ny, nx)
        for axis, size in enumerate(self.shape[::-1]):
            if size == 1 and axis == 0:  # a single layer: a 2-D lattice has no z faces
                continue
            first = [slice(None)] * 3
            last = [slice(None)] * 3
            first[axis], last[axis] = 0, -1
            count[tuple(first)] += 1
            count[tuple(last)] += 1
        return count.ravel()

    @property
    def boundary_pores(self) -> np.ndarray:
        return self._faces_touched > 0

    @property
    def initial_apertures(self) -> np.ndarray:
        return self._apertures

    @property
    def grid_shape(self) -> tuple[int, int] | None:
        nx, ny, nz = self.shape
        return (ny, nx) if nz == 1 else None

    @property
    def canonical_grid(self) -> bool:
        nx, ny, nz = self.shape
        return nz == 1 and nx == ny

    @cached_property
    def pore_volumes(self) -> np.ndarray:
        return np.full(self.n_pores, float(self.config.volume_factor))

    @property
    def throat_factors(self) -> tuple[float, float]:
        return float(self.config.area_factor), float(self.config.permeability_factor)

    @property
    def mean_aperture(self) -> float:
        c = self.config
        return 1.0 if c.mean_aperture is None else c.mean_aperture / c.pore_size

    def outlet_links(self, at: str | list[int]) -> np.ndarray:
        """One half throat per face of the box (edge in 2-D) a pore lies on when the outlet is
        the whole boundary; one per pore of the opposite face for injection at a face."""
        if at != "centre":
            return super().outlet_links(at)
        return self._faces_touched.copy()

    def sites(self, spec: str | list[int] | tuple[int, ...]) -> np.ndarray:
        """As :meth:`Lattice.sites`; ``"centre"`` is the pore ``(nz//2, ny//2, nx//2)`` (the
        square lattice's ``(n//2, n//2)`` when ``nz = 1``)."""
        if spec != "centre":
            return super().sites(spec)
        nx, ny, nz = self.shape
        mask = np.zeros(self.n_pores, dtype=bool)
        mask[((nz // 2) * ny + ny // 2) * nx + nx // 2] = True
        return mask

    # -- solid network (the 2-D square case only) --------------------------------------------
    def _square_side(self) -> int:
        nx, ny, nz = self.shape
        if nz != 1 or nx != ny:
            raise NotImplementedError(
                f"the cubic lattice {list(self.shape)} has no particles: deformable solids need "
                "nz = 1 and nx = ny (the square lattice; 3-D packings: docs/roadmap.md)"
            )
        return nx

    @cached_property
    def particle_coords(self) -> np.ndarray:
        return particle_coords(self._square_side())

    @cached_property
    def spring_particles(self) -> np.ndarray:
        return spring_particles(self._square_side())
