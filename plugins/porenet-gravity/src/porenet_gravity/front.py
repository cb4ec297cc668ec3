"""Heights along gravity and the invasion front: its position and width.

Definition of the front (Sapoval, Rosso & Gouyet 1985 [1]_, used for gravity invasion by
Birovljev et al. 1991 [2]_): the *front* is the set of invaded pores that have a neighbour
(through a throat) which is not invaded and is still connected to the outlet through
non-invaded pores. Invaded pores are all connected to the inlet (invasion percolation grows one
cluster), so this is the gradient-percolation front: sites of the cluster connected to the
source that touch the part of the empty phase connected to the sink. Trapped defender and
invaded pores bordering only trapped defender are not on it. Its *position* is the mean of
its pores' heights ``z`` (along gravity, from the injection edge) and its *width* ``w`` their
standard deviation,

    w^2 = <z^2>_front - <z>_front^2,

which in a gradient scales like the correlation length at the percolation threshold,
``w ~ g^(-nu / (1 + nu))`` for a threshold gradient ``g`` ([1]_, [3]_).

Lengths are in units of the pore size ``a`` (porenet's scaled length; the square lattice's
pore spacing is ``2a``).

References
----------
.. [1] B. Sapoval, M. Rosso and J.-F. Gouyet, J. Physique Lett. 46, L149-L156 (1985).
.. [2] A. Birovljev et al., Phys. Rev. Lett. 67, 584-587 (1991).
.. [3] D. Wilkinson, Phys. Rev. A 30, 520-531 (1984).
"""

from __future__ import annotations

import numba
import numpy as np

from porenet.core.interfaces import Lattice
from porenet.kinds.invasion.kernels import enclosed_defender

__all__ = [
    "INJECTION",
    "front_history",
    "front_moments",
    "front_pores",
    "front_statistics",
    "pore_heights",
    "steady_front_width",
    "throat_heights",
]

#: The injection site the model requires: gravity acts along x, from the inlet column (the
#: pores of smallest x) to the outlet column (largest x).
INJECTION = "left-edge"


def pore_heights(pore_coords: np.ndarray, inlets: np.ndarray) -> np.ndarray:
    """Height of each pore along gravity, from the injection edge, in units of ``a``.

    Parameters
    ----------
    pore_coords : numpy.ndarray, shape (N, 2)
        Pore centres ``(x, y) / a`` (:attr:`porenet.core.interfaces.Lattice.pore_coords`).
    inlets : numpy.ndarray of int
        The inlet pores; the injection edge is at their smallest x.

    Returns
    -------
    numpy.ndarray, shape (N,)
        ``z_p / a = (x_p - x_inlet) / a`` (0 on the inlet column).
    """
    x = np.asarray(pore_coords, dtype=np.float64)[:, 0]
    return x - x[np.asarray(inlets, dtype=np.int64)].min()


def throat_heights(
    pore_coords: np.ndarray, throat_pores: np.ndarray, inlets: np.ndarray
) -> np.ndarray:
    """Height of each throat's midpoint along gravity, from the injection edge (units of ``a``).

    Parameters
    ----------
    pore_coords : numpy.ndarray, shape (N, 2)
        Pore centres ``/ a``.
    throat_pores : numpy.ndarray of int, shape (M, 2)
        The two pores of each throat, in canonical throat order.
    inlets : numpy.ndarray of int
        The inlet pores.

    Returns
    -------
    numpy.ndarray, shape (M,)
        ``z_t / a``, the mean of the two pores' heights (:func:`pore_heights`). On the square
        lattice (pores at ``x = 2j + 1``) a horizontal throat between columns ``j`` and
        ``j + 1`` is at ``z = 2j + 1`` and a vertical throat in column ``j`` at ``z = 2j``.
    """
    z = pore_heights(pore_coords, inlets)
    tp = np.asarray(throat_pores, dtype=np.int64)
    return 0.5 * (z[tp[:, 0]] + z[tp[:, 1]])


def front_pores(
    adjacency: tuple[np.ndarray, np.ndarray, np.ndarray],
    throat_pores: np.ndarray,
    drained: np.ndarray,
    outlet: np.ndarray,
) -> np.ndarray:
    """The invasion front: invaded pores next to non-invaded pores connected to the outlet.

    Parameters
    ----------
    adjacency : (indptr, neighbours, throats)
        CSR adjacency (:attr:`porenet.core.interfaces.Lattice.adjacency`).
    throat_pores : numpy.ndarray of int, shape (M, 2)
        The two pores of each throat.
    drained : numpy.ndarray of bool, shape (N,)
        Invaded pores.
    outlet : numpy.ndarray of bool, shape (N,)
        Pores connected to the outlet reservoir.

    Returns
    -------
    numpy.ndarray of bool, shape (N,)
        True on the front (see the module docstring). O(N + M): one flood fill of the
        defender from the outlet (:func:`porenet.kinds.invasion.kernels.enclosed_defender`).
    """
    tp = np.asarray(throat_pores, dtype=np.int64)
    return _front(adjacency[0], adjacency[1], tp[:, 0], tp[:, 1], drained, outlet)


def _front(
    indptr: np.ndarray,
    neighbours: np.ndarray,
    a: np.ndarray,
    b: np.ndarray,
    drained: np.ndarray,
    outlet: np.ndarray,
) -> np.ndarray:
    """:func:`front_pores` with the throats' pores ``a``, ``b`` already split."""
    drained = np.ascontiguousarray(drained, dtype=bool)
    outlet = np.ascontiguousarray(outlet, dtype=bool)
    free = ~drained
    free &= ~enclosed_defender(indptr, neighbours, drained, outlet)
    front = np.zeros(drained.shape[0], dtype=bool)
    front[a[drained[a] & free[b]]] = True
    front[b[drained[b] & free[a]]] = True
    return front


@numba.njit(cache=True, nogil=True)
def _reach_from(
    p: int,
    indptr: np.ndarray,
    neighbours: np.ndarray,
    drained: np.ndarray,
    reach: np.ndarray,
    seen: np.ndarray,
    stack: np.ndarray,
    z: np.ndarray,
    c: int,
    s1: float,
    s2: float,
) -> tuple[int, float, float]:
    """Add ``p`` and the non-invaded pores it connects to ``reach`` (each pore once); count
    their drained neighbours in ``seen`` and add those that reach 1 to the front's sums
    ``c, s1, s2`` (of 1, z, z^2), which are returned."""
    reach[p] = True
    top = 1
    stack[0] = p
    while top > 0:
        top -= 1
        q = stack[top]
        for e in range(indptr[q], indptr[q + 1]):
            r = neighbours[e]
            if drained[r]:
                seen[r] += 1
                if seen[r] == 1:
                    c += 1
                    s1 += z[r]
                    s2 += z[r] * z[r]
            elif not reach[r]:
                reach[r] = True
                stack[top] = r
                top += 1
    return c, s1, s2


@numba.njit(cache=True, nogil=True)
def front_moments(
    indptr: np.ndarray,
    neighbours: np.ndarray,
    order: np.ndarray,
    outlet: np.ndarray,
    z: np.ndarray,
    counts: np.ndarray,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Front statistics after each of ``counts`` drained pores, in one reverse pass.

    The patterns ``order[:k]`` are visited from the last to the first. Going back one step
    un-drains a pore; the set of non-invaded pores connected to the outlet only grows on the
    way back, so each pore joins it once (a flood fill through non-invaded pores, as in the
    reverse trapping pass of Sheppard et al. 1999), and each drained pore counts its
    neighbours in that set: it is on the front while the count is positive. The sums of
    ``1, z, z^2`` over the front are updated as pores enter and leave it. Total cost
    O(N + M) for any number of snapshots, against O(N + M) per snapshot for
    :func:`front_pores`, which this kernel reproduces (the plugin's tests compare them).

    Parameters
    ----------
    indptr, neighbours : numpy.ndarray of int
        CSR adjacency (:attr:`porenet.core.interfaces.Lattice.adjacency`).
    order : numpy.ndarray of int, shape (K,)
        Drainage order, each pore at most once.
    outlet : numpy.ndarray of bool, shape (N,)
        Pores connected to the outlet reservoir.
    z : numpy.ndarray of float64, shape (N,)
        Pore heights (units of ``a``).
    counts : numpy.ndarray of int64
        Numbers of drained pores at which to measure, ascending, in ``[0, K]``.

    Returns
    -------
    count : numpy.ndarray of int64
        Number of front pores for each entry of ``counts``.
    position, width : numpy.ndarray of float64
        Mean and standard deviation of their heights (``nan`` where there is no front).
    """
    n = indptr.shape[0] - 1
    drained = np.zeros(n, dtype=np.bool_)
    for p in order:
        drained[p] = True
    reach = np.zeros(n, dtype=np.bool_)  # non-invaded and connected to the outlet
    seen = np.zeros(n, dtype=np.int64)  # of a drained pore: its neighbours in `reach`
    stack = np.empty(max(n, 1), dtype=np.int64)
    m = counts.shape[0]
    count = np.zeros(m, dtype=np.int64)
    position = np.full(m, np.nan)
    width = np.full(m, np.nan)
    c = 0
    s1 = 0.0
    s2 = 0.0
    for start in range(n):
        if outlet[start] and not drained[start] and not reach[start]:
            c, s1, s2 = _reach_from(
                start, indptr, neighbours, drained, reach, seen, stack, z, c, s1, s2
            )
    i = m - 1
    k = order.shape[0]
    while i >= 0:
        if counts[i] == k:
            count[i] = c
            if c > 0:
                mean = s1 / c
                position[i] = mean
                width[i] = np.sqrt(max(s2 / c - mean * mean, 0.0))
            i -= 1
            continue
        # go back one step: un-drain order[k - 1]
        k -= 1
        p = order[k]
        drained[p] = False
        if seen[p] > 0:  # it was on the front
            c -= 1
            s1 -= z[p]
            s2 -= z[p] * z[p]
        joins = outlet[p]
        for e in range(indptr[p], indptr[p + 1]):
            joins = joins or reach[neighbours[e]]
        if not joins:
            continue
        c, s1, s2 = _reach_from(p, indptr, neighbours, drained, reach, seen, stack, z, c, s1, s2)
    return count, position, width


def front_statistics(
    lattice: Lattice, drained: np.ndarray, outlet: np.ndarray | None = None
) -> tuple[float, float, int]:
    """Position and width of the front of a pattern on a lattice, in units of ``a``.

    Parameters
    ----------
    lattice : porenet.core.interfaces.Lattice
        The run's lattice (left-edge injection geometry).
    drained : numpy.ndarray of bool, shape (N,)
        Invaded pores.
    outlet : numpy.ndarray of bool, optional
        Pores connected to the outlet; default ``lattice.outlet_mask("left-edge")``.

    Returns
    -------
    position : float
        Mean height ``<z>`` of the front pores (``nan`` without a front).
    width : float
        Standard deviation ``w`` of their heights (``nan`` without a front).
    count : int
        Number of front pores.
    """
    if outlet is None:
        outlet = lattice.outlet_mask(INJECTION)
    front = front_pores(lattice.adjacency, lattice.throat_pores, drained, outlet)
    count = int(np.count_nonzero(front))
    if count == 0:
        return float("nan"), float("nan"), 0
    z = pore_heights(lattice.pore_coords, lattice.inlet_pores(INJECTION))[front]
    return float(z.mean()), float(z.std()), count


def front_history(
    lattice: Lattice, order: np.ndarray, counts: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Front position and width after each of ``counts`` drained pores of a drainage order.

    Parameters
    ----------
    lattice : porenet.core.interfaces.Lattice
        The run's lattice.
    order : numpy.ndarray of int
        Pores in order of drainage, inlets first (``RunData.order`` or ``state.record.order``).
    counts : numpy.ndarray of int
        Numbers of drained pores at which to measure, ascending, each ``<= len(order)``.

    Returns
    -------
    position, width : numpy.ndarray
        :func:`front_statistics` of the pattern ``order[:k]`` for each ``k`` in ``counts``
        (units of ``a``; ``nan`` without a front), computed by :func:`front_moments` in one
        pass.
    """
    counts = np.asarray(counts, dtype=np.int64)
    if np.any(np.diff(counts) < 0) or (
        counts.size and not 0 <= counts[0] <= counts[-1] <= len(order)
    ):
        raise ValueError("front_history: counts must be ascending, in [0, len(order)]")
    indptr, neighbours, _ = lattice.adjacency
    z = pore_heights(lattice.pore_coords, lattice.inlet_pores(INJECTION))
    _, position, width = front_moments(
        np.ascontiguousarray(indptr, dtype=np.int64),
        np.ascontiguousarray(neighbours, dtype=np.int64),
        np.ascontiguousarray(order, dtype=np.int64),
        np.ascontiguousarray(lattice.outlet_mask(INJECTION), dtype=np.bool_),
        np.ascontiguousarray(z, dtype=np.float64),
        counts,
    )
    return position, width


def steady_front_width(
    lattice: Lattice,
    order: np.ndarray,
    window: tuple[float, float] = (0.25, 0.6),
    snapshots: int = 60,
) -> tuple[float, int]:
    """Time-averaged front width while the front is far from the inlet and the outlet.

    The front is measured (:func:`front_history`) after ``snapshots`` numbers of drained
    pores evenly spaced over the whole ``order``; the snapshots whose front position lies in
    ``window`` (fractions of the lattice's extent along gravity, ``max z``) are kept and their
    widths averaged.

    Parameters
    ----------
    lattice : porenet.core.interfaces.Lattice
        The run's lattice.
    order : numpy.ndarray of int
        Drainage order of the run (a run to breakthrough crosses the whole window).
    window : (float, float)
        Fractions of the extent between which the front's mean position must lie.
    snapshots : int
        Number of evenly spaced measurements over the run.

    Returns
    -------
    width : float
        Mean of the kept widths (units of ``a``; ``nan`` if none was kept).
    kept : int
        Number of snapshots averaged.
    """
    z = pore_heights(lattice.pore_coords, lattice.inlet_pores(INJECTION))
    extent = float(z.max())
    counts = np.unique(np.linspace(1, len(order), snapshots).astype(np.int64))
    position, width = front_history(lattice, order, counts)
    keep = (position >= window[0] * extent) & (position <= window[1] * extent)
    if not keep.any():
        return float("nan"), 0
    return float(width[keep].mean()), int(keep.sum())
