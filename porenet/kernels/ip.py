"""Invasion percolation kernels (MODEL.md section 3).

Pure functions on arrays. Pressures are scaled by ``gamma / a`` and apertures by ``a``, so the
entry pressure of a throat of aperture ``r`` is ``2 / r``.

The whole invasion costs O(M log M) for M throats:

* :func:`invade` runs classical invasion percolation *without* trapping (Wilkinson & Willemsen
  1983) with a priority queue of the frontier throats' ranks (:mod:`porenet.kernels.bitqueue`);
  each throat enters and leaves the queue at most once.
* :func:`trapped_steps` then finds which of those steps would have entered a trapped defending
  cluster, by adding the invaded pores back in reverse order into a union-find structure that
  also holds the outlet (Sheppard, Knackstedt, Pinczewski & Sahimi 1999; Masson 2016). Removing
  those steps gives exactly the invasion *with* trapping: an enclosed cluster is surrounded by
  invaded pores for ever, so invading it never changes the frontier elsewhere.

Ties in entry pressure are broken by the lower throat index (canonical order).
"""

from __future__ import annotations

import numpy as np

from porenet.kernels._jit import njit
from porenet.kernels.bitqueue import queue_insert, queue_min, queue_new, queue_remove
from porenet.kernels.sorting import stable_argsort
from porenet.kernels.unionfind import uf_find, uf_link, uf_union


def entry_pressures(apertures: np.ndarray) -> np.ndarray:
    """Capillary entry pressure ``p_e = 2 gamma / r`` in units of ``gamma / a``.

    Parameters
    ----------
    apertures : ndarray, shape (M,)
        Throat apertures ``r / a`` (positive).
    """
    return 2.0 / np.asarray(apertures, dtype=np.float64)


def throat_ranks(entry: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Order throats by ascending entry pressure, ties by throat index.

    Returns
    -------
    by_rank : ndarray of int64, shape (M,)
        Throat index at each rank (rank 0 is invaded first).
    rank : ndarray of int64, shape (M,)
        Rank of each throat (the inverse permutation).
    """
    m = entry.shape[0]
    by_rank = stable_argsort(entry)
    rank = np.empty(m, dtype=np.int64)
    rank[by_rank] = np.arange(m, dtype=np.int64)
    return by_rank, rank


@njit
def invade(
    indptr: np.ndarray,
    neighbours: np.ndarray,
    neighbour_rank: np.ndarray,
    inlets: np.ndarray,
    outlet: np.ndarray,
    stop_at_outlet: bool,
    max_steps: int,
) -> tuple[np.ndarray, np.ndarray]:
    """Invasion percolation without trapping, on throats relabelled by rank.

    Throats are addressed by their rank (see :func:`throat_ranks`), so the queue holds the keys
    themselves. The queue holds exactly the throats between drained and undrained pores (a
    throat whose second pore drains is removed at once), so the throat it yields always leads
    to an undrained pore, recorded when the throat was queued.

    Parameters
    ----------
    indptr : ndarray of int, shape (N+1,)
        CSR row pointer of the pore adjacency.
    neighbours : ndarray of int, shape (2M,)
        Neighbouring pore of each CSR entry.
    neighbour_rank : ndarray of int, shape (2M,)
        Rank of the throat behind each CSR entry (``rank[throats]``).
    inlets : ndarray of int64
        Pores drained at the start, recorded first in the given order.
    outlet : ndarray of bool, shape (N,)
        Pores connected to the outlet; breakthrough is the first drained outlet pore.
    stop_at_outlet : bool
        Stop right after the breakthrough step.
    max_steps : int
        Stop after this many recorded steps (inlets included).

    Returns
    -------
    order : ndarray of int64, shape (K,)
        Drained pores in order.
    via_rank : ndarray of int64, shape (K,)
        Rank of the throat through which each pore was entered, -1 for inlets.
    """
    n = indptr.shape[0] - 1
    m = neighbour_rank.shape[0] // 2
    drained = np.zeros(n, dtype=np.bool_)
    order = np.empty(n, dtype=np.int64)
    via = np.empty(n, dtype=np.int64)
    target = np.empty(max(m, 1), dtype=neighbours.dtype)
    words, offsets = queue_new(m)
    k = 0
    done = False
    for p in inlets:
        if drained[p] or k >= max_steps:
            continue
        drained[p] = True
        order[k] = p
        via[k] = -1
        k += 1
        if stop_at_outlet and outlet[p]:
            done = True
    for i in range(k):
        p = order[i]
        for e in range(indptr[p], indptr[p + 1]):
            q = neighbours[e]
            if not drained[q]:
                r = neighbour_rank[e]
                target[r] = q
                queue_insert(words, offsets, r)
    while k < max_steps and not done:
        r = queue_min(words, offsets)
        if r < 0:
            break
        q = target[r]
        drained[q] = True
        order[k] = q
        via[k] = r
        k += 1
        if stop_at_outlet and outlet[q]:
            break
        for e in range(indptr[q], indptr[q + 1]):
            nb = neighbours[e]
            r2 = neighbour_rank[e]
            if drained[nb]:
                queue_remove(words, offsets, r2)  # now internal to the invader
            else:
                target[r2] = nb
                queue_insert(words, offsets, r2)
    return order[:k].copy(), via[:k].copy()


def invasion_sequence(
    adjacency: tuple[np.ndarray, np.ndarray, np.ndarray],
    entry: np.ndarray,
    inlets: np.ndarray,
    outlet: np.ndarray,
    *,
    trapping: bool,
    stop_at_outlet: bool,
    max_steps: int,
) -> tuple[np.ndarray, np.ndarray]:
    """Invasion percolation from ``inlets``, with or without trapping.

    Parameters
    ----------
    adjacency : (indptr, neighbours, throats)
        CSR adjacency of the pores (:attr:`porenet.core.interfaces.Lattice.adjacency`).
    entry : ndarray of float64, shape (M,)
        Entry pressures (any consistent unit).
    inlets : ndarray of int64
    outlet : ndarray of bool, shape (N,)
    trapping : bool
        Leave out the steps that enter defending clusters cut off from the outlet.
    stop_at_outlet : bool
        End at breakthrough.
    max_steps : int
        Steps to record at most (inlets included), counted after trapping is applied.

    Returns
    -------
    order : ndarray of int64, shape (K,)
        Pores in order of drainage, inlets first.
    via : ndarray of int64, shape (K,)
        Throat through which each was entered (-1 for inlets).
    """
    indptr, neighbours, throats = adjacency
    by_rank, rank = throat_ranks(entry)
    small = np.int32 if len(entry) < 2**31 - 1 else np.int64
    limit = indptr.shape[0] - 1 if trapping else max_steps
    order, via_rank = invade(
        indptr, neighbours, rank.astype(small)[throats], inlets, outlet, stop_at_outlet, limit
    )
    if trapping:
        keep = ~trapped_steps(indptr, neighbours, order, outlet, len(inlets))
        order, via_rank = order[keep][:max_steps], via_rank[keep][:max_steps]
    via = np.where(via_rank >= 0, by_rank[np.maximum(via_rank, 0)], -1)
    return order, via


@njit
def trapped_steps(
    indptr: np.ndarray,
    neighbours: np.ndarray,
    order: np.ndarray,
    outlet: np.ndarray,
    n_inlets: int,
) -> np.ndarray:
    """Which steps of a no-trapping invasion enter a defending cluster cut off from the outlet.

    At step t the defending fluid occupies every pore not in ``order[:t]``. Pore ``order[t]``
    may be invaded under the trapping rule only if its defending cluster at that moment still
    contains an outlet pore. Adding the pores back in reverse order into a union-find that also
    holds a virtual outlet node answers this for every step in O(N alpha(N)).

    Parameters
    ----------
    indptr, neighbours : ndarray of int64
        CSR adjacency.
    order : ndarray of int64, shape (K,)
        Pores in order of drainage from :func:`invade`.
    outlet : ndarray of bool, shape (N,)
        Pores connected to the outlet.
    n_inlets : int
        The first ``n_inlets`` steps are the inlets, drained at once and never trapped.

    Returns
    -------
    ndarray of bool, shape (K,)
        True for steps that the invasion with trapping does not take.
    """
    n = indptr.shape[0] - 1
    out = n
    parent = np.arange(n + 1).astype(indptr.dtype)
    size = np.ones(n + 1, dtype=indptr.dtype)
    present = np.ones(n, dtype=np.bool_)
    for i in range(order.shape[0]):
        present[order[i]] = False
    for p in range(n):
        if present[p]:
            if outlet[p]:
                uf_union(parent, size, p, out)
            for e in range(indptr[p], indptr[p + 1]):
                q = neighbours[e]
                if q < p and present[q]:
                    uf_union(parent, size, p, q)
    trapped = np.zeros(order.shape[0], dtype=np.bool_)
    for t in range(order.shape[0] - 1, -1, -1):
        p = order[t]
        present[p] = True
        root = p  # p is a singleton: its own root
        if outlet[p]:
            root = uf_link(parent, size, root, out)
        for e in range(indptr[p], indptr[p + 1]):
            q = neighbours[e]
            if present[q]:
                root = uf_link(parent, size, root, q)
        if t >= n_inlets:
            trapped[t] = root != uf_find(parent, out)
    return trapped


@njit
def enclosed_defender(
    indptr: np.ndarray, neighbours: np.ndarray, drained: np.ndarray, outlet: np.ndarray
) -> np.ndarray:
    """Defending pores whose cluster contains no outlet pore.

    Parameters
    ----------
    indptr, neighbours : ndarray of int64
        CSR adjacency.
    drained : ndarray of bool, shape (N,)
        Pores occupied by the invader.
    outlet : ndarray of bool, shape (N,)
        Pores connected to the outlet.

    Returns
    -------
    ndarray of bool, shape (N,)
    """
    n = drained.shape[0]
    out = n
    parent = np.arange(n + 1, dtype=np.int64)
    size = np.ones(n + 1, dtype=np.int64)
    for p in range(n):
        if drained[p]:
            continue
        if outlet[p]:
            uf_union(parent, size, p, out)
        for e in range(indptr[p], indptr[p + 1]):
            q = neighbours[e]
            if q < p and not drained[q]:
                uf_union(parent, size, p, q)
    root_out = uf_find(parent, out)
    result = np.zeros(n, dtype=np.bool_)
    for p in range(n):
        if not drained[p]:
            result[p] = uf_find(parent, p) != root_out
    return result
