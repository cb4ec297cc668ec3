"""The paper's square lattice of dented blocks (docs/model.md section 1).

Pores sit at cell centres of an ``n x n`` grid, pore ``(i, j)`` (row i, column j) has index
``i*n + j`` and centre ``(x, y) = (2j + 1, 2i + 1)`` in units of ``a`` (the node spacing is 2a).
Particles sit at the ``(n+1) x (n+1)`` nodes, particle ``(I, J)`` has index ``I*(n+1) + J`` and
centre ``(2J, 2I)``.

Canonical throat order: first the horizontal throats ``(i,j)-(i,j+1)``, row-major, index
``i*(n-1) + j``; then the vertical throats ``(i,j)-(i+1,j)``, row-major, index
``n*(n-1) + i*n + j``. The spring crossing a horizontal throat joins particles ``(i, j+1)`` and
``(i+1, j+1)`` (a vertical spring); the spring crossing a vertical throat joins ``(i+1, j)`` and
``(i+1, j+1)`` (a horizontal spring). Springs share the throat index.
"""

from __future__ import annotations

from functools import cached_property, lru_cache
from typing import Any

import numpy as np

from porenet.core.interfaces import Lattice
from porenet.kinds.square.config import SquareLatticeConfig, load_apertures_file


def canonical_throats(n: int) -> np.ndarray:
    """(2 n (n-1), 2) int64 pore pairs of an n x n square lattice, in canonical order."""
    idx = np.arange(n * n, dtype=np.int64).reshape(n, n)
    horizontal = np.stack([idx[:, :-1].ravel(), idx[:, 1:].ravel()], axis=1)
    vertical = np.stack([idx[:-1, :].ravel(), idx[1:, :].ravel()], axis=1)
    return np.concatenate([horizontal, vertical])


@lru_cache(maxsize=4)
def _topology(n: int) -> tuple[np.ndarray, tuple[np.ndarray, np.ndarray, np.ndarray]]:
    """Read-only throat pairs and CSR adjacency of an n x n lattice, shared by all lattices of
    that size in a process (sweeps and replicates rebuild only the apertures)."""
    from porenet.kernels.graph import csr_adjacency

    throats = canonical_throats(n)
    adjacency = csr_adjacency(throats, n * n)
    for array in (throats, *adjacency):
        array.setflags(write=False)
    return throats, adjacency


@lru_cache(maxsize=4)
def _pore_coords(n: int) -> np.ndarray:
    """Read-only pore centres (x = 2j + 1, y = 2i + 1, in units of a) of an n x n lattice."""
    i, j = np.divmod(np.arange(n * n), n)
    coords = np.stack([2.0 * j + 1.0, 2.0 * i + 1.0], axis=1)
    coords.setflags(write=False)
    return coords


class SquareLattice(Lattice):
    """Square lattice of ``n x n`` pores and ``(n+1) x (n+1)`` particles.

    Subclasses that only change how apertures are drawn override :meth:`draw_apertures`.
    """

    config: SquareLatticeConfig

    def __init__(self, config: Any, rng: np.random.Generator) -> None:
        super().__init__(config, rng)
        self.n = int(config.n)
        if config.apertures_file is not None:
            r = load_apertures_file(config.apertures_file, self.n) / config.pore_size
        else:
            r = self.draw_apertures(rng)
        if r.shape != (self.n_throats_expected,) or not np.all(np.isfinite(r) & (r > 0)):
            raise ValueError(f"{type(self).__name__}: apertures must be positive, finite, (M,)")
        self._apertures = r
        self._apertures.setflags(write=False)

    @property
    def n_throats_expected(self) -> int:
        return 2 * self.n * (self.n - 1)

    @property
    def mean_aperture_scaled(self) -> float:
        """r_mean / a."""
        c = self.config
        return 1.0 if c.mean_aperture is None else c.mean_aperture / c.pore_size

    def draw_apertures(self, rng: np.random.Generator) -> np.ndarray:
        """Uncorrelated apertures ``r / a`` uniform in [(1-lambda), (1+lambda)] r_mean / a."""
        lam = float(self.config.disorder)
        r0 = self.mean_aperture_scaled
        return rng.uniform((1.0 - lam) * r0, (1.0 + lam) * r0, size=self.n_throats_expected)

    # -- Lattice interface ----------------------------------------------------------------
    @property
    def n_pores(self) -> int:
        return self.n * self.n

    @property
    def throat_pores(self) -> np.ndarray:
        return _topology(self.n)[0]

    @property
    def adjacency(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        return _topology(self.n)[1]

    @property
    def pore_coords(self) -> np.ndarray:
        return _pore_coords(self.n)

    @cached_property
    def boundary_pores(self) -> np.ndarray:
        mask = np.zeros((self.n, self.n), dtype=bool)
        mask[0, :] = mask[-1, :] = mask[:, 0] = mask[:, -1] = True
        return mask.ravel()

    @property
    def initial_apertures(self) -> np.ndarray:
        return self._apertures

    @property
    def grid_shape(self) -> tuple[int, int]:
        return (self.n, self.n)

    @cached_property
    def pore_volumes(self) -> np.ndarray:
        return np.full(self.n_pores, float(self.config.volume_factor))

    @property
    def canonical_grid(self) -> bool:
        return True

    @property
    def throat_factors(self) -> tuple[float, float]:
        return float(self.config.area_factor), float(self.config.permeability_factor)

    @property
    def mean_aperture(self) -> float:
        return self.mean_aperture_scaled

    def outlet_links(self, at: str) -> np.ndarray:
        """One half throat per outer side a pore touches (two for the corners) when the outlet
        is the whole edge; one per pore of the right column for ``left-edge``."""
        if at != "centre":
            return super().outlet_links(at)
        links = np.zeros((self.n, self.n))
        links[0, :] += 1
        links[-1, :] += 1
        links[:, 0] += 1
        links[:, -1] += 1
        return links.ravel()

    def inlet_pores(self, at: str) -> np.ndarray:
        if at == "centre":
            return np.array([(self.n // 2) * self.n + self.n // 2], dtype=np.int64)
        return super().inlet_pores(at)

    # -- solid network ----------------------------------------------------------------------
    @cached_property
    def particle_coords(self) -> np.ndarray:
        return particle_coords(self.n)

    @cached_property
    def spring_particles(self) -> np.ndarray:
        return spring_particles(self.n)


def particle_coords(n: int) -> np.ndarray:
    """((n+1)^2, 2) float: the particle centres (2J, 2I) of an n x n lattice, in units of a."""
    big_i, big_j = np.divmod(np.arange((n + 1) ** 2), n + 1)
    return np.stack([2.0 * big_j, 2.0 * big_i], axis=1)


def spring_particles(n: int) -> np.ndarray:
    """(2 n (n-1), 2) int64: the particles each throat's spring joins (module docstring)."""
    n1 = n + 1
    i, j = np.divmod(np.arange(n * (n - 1)), n - 1)
    vertical_springs = np.stack([i * n1 + j + 1, (i + 1) * n1 + j + 1], axis=1)
    i, j = np.divmod(np.arange((n - 1) * n), n)
    horizontal_springs = np.stack([(i + 1) * n1 + j, (i + 1) * n1 + j + 1], axis=1)
    return np.concatenate([vertical_springs, horizontal_springs]).astype(np.int64)
