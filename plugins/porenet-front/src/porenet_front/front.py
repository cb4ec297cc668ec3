"""The invasion front of a drainage pattern: its menisci, their mean distance from the
injection site and the spread of that distance.

Definitions
-----------
A *meniscus* sits in every throat that joins a drained pore to an undrained one (docs/model.md
section 2): the interface between the two fluids, one meniscus per throat. The *front* is the
set of menisci that face defending fluid still connected to the outlet, the ones that can
still advance; menisci that face defender cut off from the outlet (trapped) are part of the
interface but not of the front (the external perimeter of the invaded cluster, as in
gradient percolation: Sapoval, Rosso & Gouyet 1985 [1]_).

The *distance* of a meniscus from the injection site is that of its throat's midpoint: along x
from the inlet column for injection at the left edge (a penetration depth), from the inlet
pore's centre for injection at the centre (a radius). The front's *position* is the mean of
its menisci's distances and its *width* their standard deviation,

    position = <d>_front,     width^2 = <(d - position)^2>_front,

and the *extent* of the invasion is the largest distance of a drained pore (the tip of the
longest finger). Lengths are in units of the pore size ``a`` (porenet's scaled length; the
square lattice's pore spacing is ``2a``).

References
----------
.. [1] B. Sapoval, M. Rosso and J.-F. Gouyet, J. Physique Lett. 46, L149-L156 (1985).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from porenet.core.interfaces import Lattice
from porenet.kinds.invasion.kernels import enclosed_defender

__all__ = ["FrontGeometry", "FrontMeasures", "front_geometry", "injection_distance", "measure"]


def injection_distance(points: np.ndarray, inlet_coords: np.ndarray, at: str) -> np.ndarray:
    """Distance of each point from the injection site, in the units of the coordinates.

    Parameters
    ----------
    points : numpy.ndarray, shape (K, 2)
        Coordinates ``(x, y)``.
    inlet_coords : numpy.ndarray, shape (I, 2)
        Centres of the inlet pores (:meth:`porenet.core.interfaces.Lattice.inlet_pores`).
    at : {"left-edge", "centre"}
        The injection site (the scene's ``[injection] at``).

    Returns
    -------
    numpy.ndarray, shape (K,)
        ``x - min(x_inlet)`` for ``"left-edge"``, the distance to the (single) inlet pore's
        centre for ``"centre"``.
    """
    points = np.asarray(points, dtype=np.float64)
    inlet_coords = np.asarray(inlet_coords, dtype=np.float64)
    if at == "left-edge":
        return points[:, 0] - inlet_coords[:, 0].min()
    if at == "centre":
        return np.hypot(points[:, 0] - inlet_coords[0, 0], points[:, 1] - inlet_coords[0, 1])
    raise ValueError(f"unknown injection site {at!r}")


class FrontGeometry(NamedTuple):
    """What :func:`measure` needs of a lattice and an injection site (units of ``a``)."""

    #: (M, 2) int64: the two pores of each throat.
    throat_pores: np.ndarray
    #: CSR adjacency of the pores (:attr:`porenet.core.interfaces.Lattice.adjacency`).
    indptr: np.ndarray
    neighbours: np.ndarray
    #: (N,) bool: pores connected to the outlet reservoir.
    outlet: np.ndarray
    #: (N,) distance of each pore centre from the injection site.
    pore_distance: np.ndarray
    #: (M,) distance of each throat's midpoint from the injection site.
    throat_distance: np.ndarray


def front_geometry(lattice: Lattice, at: str) -> FrontGeometry:
    """The :class:`FrontGeometry` of ``lattice`` for injection ``at`` (``"left-edge"`` or
    ``"centre"``), from the lattice's public description only."""
    xy = np.asarray(lattice.pore_coords, dtype=np.float64)
    tp = np.ascontiguousarray(lattice.throat_pores, dtype=np.int64)
    inlet_coords = xy[lattice.inlet_pores(at)]
    midpoints = 0.5 * (xy[tp[:, 0]] + xy[tp[:, 1]])
    indptr, neighbours, _ = lattice.adjacency
    return FrontGeometry(
        throat_pores=tp,
        indptr=np.ascontiguousarray(indptr, dtype=np.int64),
        neighbours=np.ascontiguousarray(neighbours, dtype=np.int64),
        outlet=np.ascontiguousarray(lattice.outlet_mask(at), dtype=np.bool_),
        pore_distance=injection_distance(xy, inlet_coords, at),
        throat_distance=injection_distance(midpoints, inlet_coords, at),
    )


class FrontMeasures(NamedTuple):
    """The front of one pattern (:func:`measure`); lengths in units of ``a``."""

    #: Menisci: throats between a drained and an undrained pore.
    menisci: int
    #: Of those, the ones facing defender connected to the outlet (the front).
    front_menisci: int
    #: Mean distance of the front's menisci from the injection site (nan without a front).
    position: float
    #: Standard deviation of that distance (nan without a front).
    width: float
    #: Largest distance of a drained pore from the injection site (nan if none is drained).
    extent: float


def measure(geometry: FrontGeometry, drained: np.ndarray) -> FrontMeasures:
    """The front of the pattern ``drained`` ((N,) bool), in O(N + M): one flood fill of the
    defender from the outlet (:func:`porenet.kinds.invasion.kernels.enclosed_defender`)."""
    drained = np.ascontiguousarray(drained, dtype=np.bool_)
    a, b = geometry.throat_pores[:, 0], geometry.throat_pores[:, 1]
    meniscus = drained[a] != drained[b]
    free = ~drained & ~enclosed_defender(
        geometry.indptr, geometry.neighbours, drained, geometry.outlet
    )
    front = meniscus & (free[a] | free[b])
    d = geometry.throat_distance[front]
    nan = float("nan")
    return FrontMeasures(
        menisci=int(np.count_nonzero(meniscus)),
        front_menisci=int(d.size),
        position=float(d.mean()) if d.size else nan,
        width=float(d.std()) if d.size else nan,
        extent=float(geometry.pore_distance[drained].max()) if drained.any() else nan,
    )
