"""Networks imported from files, kind ``network`` (docs/lattices.md, "Imported networks (kind
`network`)").

The file (:mod:`porenet.kinds.network.files`) gives, in SI units, the pore centres
and volumes, each throat's two pores, radius, length and, where it has one, shape factor G,
and named pore sets. This lattice scales them by the scene's ``pore_size`` a and maps them
onto the lattice contract:

* aperture ``r / a``: the throat radius (``throat.inscribed_diameter / 2``, else
  ``throat.diameter / 2``; Statoil: link1's radius);
* throat length ``l / a`` as the config's ``throat_length`` chooses (default the pore centre
  to pore centre length: porenet's pores are lumped volumes, so a throat conducts from centre
  to centre);
* cross-sections: with a shape factor, area ``A = r^2 / (4 G)`` (exact for any triangle, the
  square and the circle of inscribed radius r) and permeability ``k = k_G r^2 / 4``, so that
  ``A k = k_G G A^2`` is pnflow's conductance, with ``k_G`` 3/5 for a triangle (``G <=
  sqrt(3)/36``), 0.5623 for a square (``G <= 1/16``) and 1/2 for a circle: ``c_A = 1 / (4
  G)``, ``c_k = k_G / 4``; without one, circular cylinders ``c_A = pi``, ``c_k = 1/8``;
* entry pressure ``2 / r`` (a cylinder) or, with ``entry_pressure = "shape-factor"``, ``(1 +
  2 sqrt(pi G)) / r`` (Mayer-Stowe-Princen, zero contact angle; ``2 / r`` for a circle's
  ``G = 1 / (4 pi)``);
* pore volumes ``V / a^3``; labels as named in the file.

Isolated pores and clusters are kept (pore numbers stay the file's); they never drain.
"""

from __future__ import annotations

import math
from functools import cached_property
from typing import Any

import numpy as np

from porenet.core.interfaces import Lattice
from porenet.core.sites import FACES, OPPOSITE_FACE, face_of
from porenet.kinds.network.config import NetworkLatticeConfig
from porenet.kinds.network.files import NetworkData, read_network

#: pnflow's shape classes: the largest G of a triangle and of a square; circles above.
G_TRIANGLE = math.sqrt(3.0) / 36.0
G_SQUARE = 1.0 / 16.0
#: Conductance factors k_G of the three shapes (g = k_G G A^2 / mu per unit length).
K_TRIANGLE, K_SQUARE, K_CIRCLE = 0.6, 0.5623, 0.5
#: The label that marks the outer boundary when a file has one.
SURFACE_LABEL = "pore.surface"


def shape_factors(g: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``(c_A, c_k)`` per throat from the shape factors ``g``: area ``A = r^2 / (4 G)`` and
    permeability ``k = k_G r^2 / 4`` (module docstring)."""
    g = np.asarray(g, dtype=np.float64)
    k_g = np.where(g <= G_TRIANGLE, K_TRIANGLE, np.where(g <= G_SQUARE, K_SQUARE, K_CIRCLE))
    return 1.0 / (4.0 * g), k_g / 4.0


def shape_entry_pressures(r: np.ndarray, g: np.ndarray) -> np.ndarray:
    """Entry pressure ``(1 + 2 sqrt(pi G)) / r`` (units of gamma/a, ``r`` in a) of throats of
    shape factor ``g``: Mayer-Stowe-Princen for a zero contact angle."""
    return (1.0 + 2.0 * np.sqrt(np.pi * np.asarray(g))) / np.asarray(r, dtype=np.float64)


def _frozen(array: np.ndarray) -> np.ndarray:
    array = np.ascontiguousarray(array)
    array.setflags(write=False)
    return array


class NetworkLattice(Lattice):
    """A pore network read from an ``.npz`` (OpenPNM, PoreSpy) or Statoil files."""

    config: NetworkLatticeConfig

    def __init__(self, config: Any, rng: np.random.Generator) -> None:
        super().__init__(config, rng)
        data = read_network(config.file, config.throat_length)
        if config.entry_pressure == "shape-factor" and data.shape_factor is None:
            raise ValueError(
                f"{data.source}: entry_pressure = 'shape-factor' needs the shape factor "
                "'throat.shape_factor', which the file lacks"
            )
        a = float(config.pore_size)
        self.data: NetworkData = data
        self._coords = _frozen(data.coords / a)
        self._throats = _frozen(data.conns)
        self._apertures = _frozen(data.radius / a)
        self._lengths = _frozen(data.length / a)
        self._volumes = _frozen(data.volume / a**3)
        self._labels = {name: _frozen(mask) for name, mask in data.labels.items()}

    # -- pore network ---------------------------------------------------------------------
    @property
    def n_pores(self) -> int:
        return int(self._coords.shape[0])

    @property
    def throat_pores(self) -> np.ndarray:
        return self._throats

    @property
    def pore_coords(self) -> np.ndarray:
        return self._coords

    @property
    def initial_apertures(self) -> np.ndarray:
        return self._apertures

    @property
    def throat_lengths(self) -> np.ndarray:
        return self._lengths

    @property
    def pore_volumes(self) -> np.ndarray:
        return self._volumes

    @property
    def labels(self) -> dict[str, np.ndarray]:
        return dict(self._labels)

    @cached_property
    def throat_factors(self) -> tuple[float | np.ndarray, float | np.ndarray]:
        """``(c_A, c_k)``: from the shape factors (arrays) when the file has them and
        ``cross_sections = "auto"``, else circular cylinders ``(pi, 1/8)``."""
        g = self.data.shape_factor
        if g is None or self.config.cross_sections == "circle":
            return math.pi, 0.125
        c_area, c_perm = shape_factors(g)
        return _frozen(c_area), _frozen(c_perm)

    def entry_pressures(
        self, apertures: np.ndarray, throats: np.ndarray | None = None
    ) -> np.ndarray:
        """``2 / r``, or ``(1 + 2 sqrt(pi G)) / r`` with ``entry_pressure = "shape-factor"``,
        of the throats ``throats`` (default all) of apertures ``r / a``."""
        if self.config.entry_pressure == "cylinder":
            return super().entry_pressures(apertures, throats)
        g = self.data.shape_factor
        assert g is not None  # checked when the lattice was built
        return shape_entry_pressures(apertures, g if throats is None else g[throats])

    # -- sites and outlets ----------------------------------------------------------------
    @cached_property
    def face_tolerance(self) -> float:
        """Distance (units of a) from a face of the bounding box within which a pore lies on
        it: the config's ``face_tolerance``, else half the median distance between joined
        pore centres."""
        if self.config.face_tolerance is not None:
            return float(self.config.face_tolerance) / float(self.config.pore_size)
        if self.n_throats == 0:
            return 0.0
        tp = self._throats
        squared = np.sum((self._coords[tp[:, 1]] - self._coords[tp[:, 0]]) ** 2, axis=1)
        # the median distance (for an even count, the root mean square of the middle two)
        return 0.5 * math.sqrt(float(np.median(squared)))

    def _face(self, face: str) -> np.ndarray:
        axis, side = FACES[face]
        if axis >= self.dimension:
            raise ValueError(f"face {face!r} needs a 3-D network; this one is 2-D")
        x = self._coords[:, axis]
        tol = self.face_tolerance
        return x >= x.max() - tol if side > 0 else x <= x.min() + tol

    @cached_property
    def boundary_pores(self) -> np.ndarray:
        """The ``pore.surface`` label if the file has one, else the pores on any face of the
        bounding box (within :attr:`face_tolerance`)."""
        if SURFACE_LABEL in self._labels:
            return self._labels[SURFACE_LABEL]
        mask = np.zeros(self.n_pores, dtype=bool)
        for face in list(FACES)[: 2 * self.dimension]:
            mask |= self._face(face)
        return _frozen(mask)

    def sites(self, spec: str | list[int] | tuple[int, ...]) -> np.ndarray:
        """As :meth:`Lattice.sites`; a face is every pore within :attr:`face_tolerance` of
        it (an irregular network has few pores exactly on its bounding box)."""
        face = face_of(spec)
        if face is None:
            return super().sites(spec)
        return self._face(face)

    def outlet_mask(self, at: str | list[int]) -> np.ndarray:
        """The config's ``outlet`` (a label, a face, or ``"boundary"``: the boundary pores
        that are not inlets) if given; else the face opposite an injection face, or the
        boundary pores that are not inlets."""
        spec = self.config.outlet
        face = face_of(at)
        if spec is None and face is not None:
            return self.sites(OPPOSITE_FACE[face])
        if spec is None or spec == "boundary":
            return np.asarray(self.boundary_pores, dtype=bool) & ~self.sites(at)
        return self.sites(spec)

    # -- solid network ----------------------------------------------------------------------
    @property
    def particle_coords(self) -> np.ndarray:
        raise NotImplementedError(
            "an imported network has no particles: deformable solids need the square lattice"
        )

    @property
    def spring_particles(self) -> np.ndarray:
        raise NotImplementedError(
            "an imported network has no particles: deformable solids need the square lattice"
        )
