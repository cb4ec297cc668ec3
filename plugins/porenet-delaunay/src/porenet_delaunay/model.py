"""The ``delaunay.random`` lattice: a 2-D random pore network, not a grid underneath.

The network, in units of the pore size ``a``:

1. **Pores**: ``N`` points drawn uniformly in the square ``[0, L]^2``, ``L = 2 sqrt(N)`` (one
   pore per ``4 a^2``, the square lattice's density); every point closer than
   ``min_distance`` to a point drawn before it is drawn again, until none is (a hard-core
   point set: no throat is shorter than ``min_distance``).
2. **Throats**: the edges of the Delaunay triangulation of the points, taken from the
   Voronoi tessellation of the points and their mirror images across the four sides
   (``scipy.spatial.Voronoi``): two pores are joined where their cells share an edge. The
   mirrors bound every pore's cell by the square, so the cells tile it exactly and the
   triangulation has no long, thin triangles along its hull, which a triangulation of the
   points alone has.
3. **Apertures** ``r / a``: uniform in ``[1 - lambda, 1 + lambda]`` (``r_mean = a``), drawn
   after the points, in the canonical throat order (pairs ``(i, j)``, ``i < j``, sorted).
4. **Throat lengths**: the distances between the two pores' centres.
5. **Pore volumes** ``V / a^3 = A / 4``, ``A`` the area of the pore's cell in ``a^2``: a pore
   of the square lattice owns ``4 a^2`` and holds ``a^3``; the volumes add up to ``N``.
6. **Faces**: the pores whose cells touch a side of the square (each shares a cell edge
   with its own mirror across that side); the boundary is the four faces.

Everything comes from the run's generator: the same seed gives the same network.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy.spatial import Voronoi, cKDTree

from porenet.core.interfaces import Lattice
from porenet.core.sites import face_of
from porenet_delaunay.config import KIND, DelaunayLatticeConfig

#: The sides of the square, in the order of the mirror images: name -> (axis, side).
SIDES = {"x-": (0, -1), "x+": (0, 1), "y-": (1, -1), "y+": (1, 1)}
#: Width (a) of the band of points mirrored across each side; wide enough that a wider one
#: never changes a cell (checked: :func:`tessellate` mirrors every point when it would).
MIRROR_BAND = 8.0
#: Most rounds of drawing again the points that are too close to an earlier one.
MAX_ROUNDS = 10_000


def hard_core_points(
    n: int, side: float, min_distance: float, rng: np.random.Generator
) -> np.ndarray:
    """``(n, 2)`` points uniform in ``[0, side]^2``, no two closer than ``min_distance``.

    All points are drawn at once; then, round by round, the later point of every pair closer
    than ``min_distance`` is drawn again, until no pair is. Deterministic for a generator's
    state.

    Raises
    ------
    ValueError
        If the points could not be placed in :data:`MAX_ROUNDS` rounds (far denser than the
        config allows).
    """
    xy = rng.uniform(0.0, side, size=(n, 2))
    if min_distance <= 0:
        return xy
    for _ in range(MAX_ROUNDS):
        pairs = cKDTree(xy).query_pairs(min_distance, output_type="ndarray")
        if len(pairs) == 0:
            return xy
        later = np.unique(pairs.max(axis=1))
        xy[later] = rng.uniform(0.0, side, size=(len(later), 2))
    raise ValueError(
        f"could not place {n} pores at least {min_distance} a apart in {MAX_ROUNDS} rounds"
    )


@dataclass(frozen=True)
class Tessellation:
    """The network of a point set in a square (module docstring).

    Attributes
    ----------
    throat_pores : ndarray of int64, shape (M, 2)
        Pairs ``(i, j)``, ``i < j``, sorted: pores whose cells share an edge.
    cell_areas : ndarray of float64, shape (N,)
        Area of each pore's cell (units of the points' coordinates, squared).
    faces : dict
        ``{"x-": mask, "x+": ..., "y-": ..., "y+": ...}``, ``(N,)`` bool: the pores whose cells
        touch that side.
    """

    throat_pores: np.ndarray
    cell_areas: np.ndarray
    faces: dict[str, np.ndarray]


def mirrored(xy: np.ndarray, side: float, band: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The points followed by their mirror images across each side of ``[0, side]^2`` (in the
    order of :data:`SIDES`) of the points within ``band`` of that side; for each, the point it
    is an image of (itself for the originals) and the side it was mirrored across (-1 for the
    originals)."""
    points, source, across = [xy], [np.arange(len(xy))], [np.full(len(xy), -1)]
    for k, (axis, sign) in enumerate(SIDES.values()):
        edge = side if sign > 0 else 0.0
        near = np.flatnonzero(np.abs(xy[:, axis] - edge) <= band)
        image = xy[near].copy()
        image[:, axis] = 2.0 * edge - image[:, axis]
        points.append(image)
        source.append(near)
        across.append(np.full(len(near), k))
    return np.concatenate(points), np.concatenate(source), np.concatenate(across)


def tessellate(xy: np.ndarray, side: float, band: float = MIRROR_BAND) -> Tessellation:
    """The throats, cells and faces of the points ``xy`` in ``[0, side]^2`` (module docstring).

    Mirrors the points within ``band`` of each side; if the cells then do not tile the square
    exactly (their areas add up to more than ``side^2``: a mirror that matters was left out),
    mirrors every point.
    """
    n = len(xy)
    points, source, across = mirrored(xy, side, band)
    vor = Voronoi(points)
    pairs = np.asarray(vor.ridge_points, dtype=np.int64)
    ends = np.asarray(vor.ridge_vertices, dtype=np.int64)
    own = (pairs < n).any(axis=1)
    pairs, ends = pairs[own], ends[own]
    width = np.linalg.norm(vor.vertices[ends[:, 0]] - vor.vertices[ends[:, 1]], axis=1)
    distance = np.linalg.norm(points[pairs[:, 0]] - points[pairs[:, 1]], axis=1)
    # a cell's area: over its edges, triangles of base `width` and height `distance / 2`
    areas = np.zeros(n)
    for k in (0, 1):
        mine = pairs[:, k] < n
        np.add.at(areas, pairs[mine, k], 0.25 * width[mine] * distance[mine])
    bounded = bool(np.all(ends >= 0))
    if not (bounded and abs(areas.sum() - side * side) <= 1e-9 * side * side):
        if band >= side:
            raise ValueError("the Voronoi cells of the pores do not tile their square")
        return tessellate(xy, side, band=side)
    inner = (pairs < n).all(axis=1)
    throats = np.sort(pairs[inner], axis=1)
    throats = throats[np.lexsort((throats[:, 1], throats[:, 0]))]
    # a pore touches a side where its cell shares an edge with its own image across it
    pore, image = np.where(pairs[:, :1] < n, pairs, pairs[:, ::-1]).T
    touches = (image >= n) & (source[image] == pore)
    faces = {}
    for k, name in enumerate(SIDES):
        mask = np.zeros(n, dtype=bool)
        mask[pore[touches & (across[image] == k)]] = True
        faces[name] = mask
    return Tessellation(throats, areas, faces)


def _frozen(array: np.ndarray) -> np.ndarray:
    array = np.ascontiguousarray(array)
    array.setflags(write=False)
    return array


class DelaunayLattice(Lattice):
    """A 2-D random pore network (module docstring): pores at hard-core random points of a
    square, throats along their Delaunay triangulation, faces where the cells touch the
    square's sides."""

    config: DelaunayLatticeConfig

    def __init__(self, config: Any, rng: np.random.Generator) -> None:
        super().__init__(config, rng)
        side = config.side()
        xy = hard_core_points(config.n_pores, side, config.min_distance, rng)
        cells = tessellate(xy, side)
        lam = float(config.disorder)
        tp = cells.throat_pores
        self._coords = _frozen(xy)
        self._throats = _frozen(tp)
        self._apertures = _frozen(rng.uniform(1.0 - lam, 1.0 + lam, size=len(tp)))
        self._lengths = _frozen(np.linalg.norm(xy[tp[:, 1]] - xy[tp[:, 0]], axis=1))
        self._volumes = _frozen(cells.cell_areas / 4.0)
        self._faces = {name: _frozen(mask) for name, mask in cells.faces.items()}
        self._boundary = _frozen(np.logical_or.reduce(list(self._faces.values())))

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
    def boundary_pores(self) -> np.ndarray:
        return self._boundary

    @property
    def mean_aperture(self) -> float:
        """``r_mean / a = 1``: the apertures are drawn about the pore size."""
        return 1.0

    # -- sites ----------------------------------------------------------------------------
    @property
    def labels(self) -> dict[str, np.ndarray]:
        """The four faces, ``"x-"``, ``"x+"``, ``"y-"``, ``"y+"``: the pores whose cells touch
        that side of the square."""
        return dict(self._faces)

    def sites(self, spec: str | list[int] | tuple[int, ...]) -> np.ndarray:
        """As :meth:`Lattice.sites`, a face being the pores whose cells touch that side (few
        pores of a random network lie exactly on its bounding box)."""
        face = face_of(spec)
        if face is None:
            return super().sites(spec)
        if face not in self._faces:
            raise ValueError(f"face {spec!r} needs a 3-D lattice; the {KIND!r} lattice is 2-D")
        return self._faces[face].copy()

    # -- solid network --------------------------------------------------------------------
    @property
    def particle_coords(self) -> np.ndarray:
        raise NotImplementedError(self._no_particles())

    @property
    def spring_particles(self) -> np.ndarray:
        raise NotImplementedError(self._no_particles())

    def _no_particles(self) -> str:
        return (
            f"the {KIND!r} lattice describes no solid particles (no particle_coords or "
            "spring_particles): deformable solids need a lattice that does, such as 'square'"
        )
