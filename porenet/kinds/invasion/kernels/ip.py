"""Invasion percolation kernels (docs/model.md section 3).

Pure functions on arrays. Pressures are scaled by ``gamma / a`` and apertures by ``a``, so the
entry pressure of a throat of aperture ``r`` is ``2 / r``.

The whole invasion costs O(M) for M throats with smooth entry-pressure distributions:

* :func:`throat_ranks` orders the throats by entry pressure, ties by throat index, with an
  O(M) bucket sort (:mod:`porenet.kernels.sorting`). From then on throats are addressed by
  their rank, so comparing two throats is comparing two integers.
* The invasion *without* trapping (Wilkinson & Willemsen 1983) keeps, for every undrained pore
  next to the invader, the smallest rank of the throats joining it to the invader, in a
  priority queue of ranks (:mod:`porenet.kinds.invasion.kernels.bitqueue`); each step drains the
  pore with the smallest key, i.e. the pore behind the frontier throat of smallest entry pressure
  (Prim's algorithm). Keying pores rather than throats halves the queue operations: a throat whose
  two pores drain needs no removal.
* :func:`~porenet.kinds.invasion.kernels.trapping.trapped_steps` (in
  :mod:`porenet.kinds.invasion.kernels.trapping`; re-exported here) then finds which of those steps
  would have entered a defending cluster cut off from the outlet; removing them gives exactly
  the invasion *with* trapping.

Ties in entry pressure are broken by the lower throat index (canonical order).

The invasion loop is bound by memory latency, not arithmetic. It reads the adjacency as
interleaved (neighbour, rank) pairs (:func:`porenet.kernels.graph.rank_pairs`, padded to one
fixed-width row per pore on lattices, so a row is found without reading ``indptr``), and it
prefetches the rows of the two candidates for the next step (the pore behind the next-smallest
queued rank, and the pores whose key was just lowered) while it works on the current one.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from porenet.jit.jit import njit, prefetch
from porenet.kernels.graph import max_degree, rank_pairs
from porenet.kernels.sorting import rank_order
from porenet.kinds.invasion.kernels.bitqueue import (
    queue_insert,
    queue_min,
    queue_new,
    queue_pop_min,
    queue_remove,
)
from porenet.kinds.invasion.kernels.trapping import (
    Adjacency,
    TrapWork,
    drop_trapped,
)

#: Largest padding overhead (padded slots / CSR entries) for which the padded layout is used.
_MAX_PADDING = 1.25


def entry_pressures(apertures: np.ndarray) -> np.ndarray:
    """Capillary entry pressure ``p_e = 2 gamma / r`` in units of ``gamma / a``.

    Parameters
    ----------
    apertures : ndarray, shape (M,)
        Throat apertures ``r / a`` (positive).
    """
    return 2.0 / np.asarray(apertures, dtype=np.float64)


@njit
def step_pressures(entry: np.ndarray, via: np.ndarray) -> np.ndarray:
    """Entry pressure of the throat of each step (``entry[via]``), 0 where ``via`` is -1."""
    out = np.empty(via.shape[0], dtype=np.float64)
    for k in range(via.shape[0]):
        out[k] = entry[via[k]] if via[k] >= 0 else 0.0
    return out


def throat_ranks(entry: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Order throats by ascending entry pressure, ties by throat index.

    Returns
    -------
    by_rank : ndarray of int64, shape (M,)
        Throat index at each rank (rank 0 is invaded first).
    rank : ndarray of int64, shape (M,)
        Rank of each throat (the inverse permutation).
    """
    m = len(entry)
    by_rank, rank = np.empty(m, dtype=np.int64), np.empty(m, dtype=np.int64)
    _ranks_into(entry, by_rank, rank, np.empty(m, dtype=np.uint64))
    return by_rank, rank


def _ranks_into(entry: np.ndarray, by_rank: np.ndarray, rank: np.ndarray, keys: np.ndarray) -> None:
    """Fill ``by_rank`` and ``rank`` (:func:`throat_ranks`); ``keys`` is scratch space."""
    values = np.ascontiguousarray(entry, dtype=np.float64)
    if not rank_order(values, by_rank, rank, keys):  # very clustered values: numpy's sort
        by_rank[:] = np.argsort(values, kind="stable")
        rank[by_rank] = np.arange(len(values), dtype=rank.dtype)


def _arena(*specs: tuple[int, type]) -> list[np.ndarray]:
    """Work arrays of the given ``(length, dtype)``, carved out of one numpy allocation.

    One allocation instead of a dozen: numpy backs it with huge pages where the system allows
    (fewer page faults on first touch, fewer TLB misses on random access, unlike arrays
    allocated inside kernels), and the allocator can keep it for the next call of the same
    size instead of returning the memory to the system and faulting it in again.
    """
    align = 64
    offsets = []
    total = 0
    for length, dtype in specs:
        offsets.append(total)
        total += -(-max(length, 1) * np.dtype(dtype).itemsize // align) * align
    buffer = np.empty(total + align, dtype=np.uint8)
    shift = -buffer.ctypes.data % align
    return [
        buffer[shift + start : shift + start + length * np.dtype(dtype).itemsize].view(dtype)
        for start, (length, dtype) in zip(offsets, specs, strict=True)
    ]


@njit(helper=True)
def _row(indptr: np.ndarray, width: int, p: int) -> tuple[int, int]:
    """Slice ``[start, stop)`` of pore ``p``'s pairs (see :func:`rank_pairs`)."""
    if width > 0:
        start = 2 * width * p
        return start, start + 2 * width
    return 2 * indptr[p], 2 * indptr[p + 1]


class RankedGraph(NamedTuple):
    """The pore graph with every throat relabelled by its rank in entry pressure, in the
    layout :func:`porenet.kernels.graph.rank_pairs` builds.

    Attributes
    ----------
    indptr : ndarray of int, shape (N+1,)
        CSR row pointer of the pore adjacency.
    width : int
        Layout of ``pairs``: 0 for CSR order, else the padded row width.
    pairs : ndarray of int, shape (2 * 2M,) or (2 * width * N,)
        Interleaved (neighbour, throat rank) pairs.
    n_throats : int
        M (ranks are ``0 .. M-1``).
    """

    indptr: np.ndarray
    width: int
    pairs: np.ndarray
    n_throats: int


class InvasionStops(NamedTuple):
    """When :func:`invade_pairs` stops.

    Attributes
    ----------
    at_outlet : bool
        Stop right after the breakthrough step.
    max_steps : int
        Stop after this many recorded steps (inlets included).
    until_outlets_drained : bool
        Also stop once every outlet pore is drained (with trapping, every later step would
        enter a cluster cut off from the outlet).
    """

    at_outlet: bool
    max_steps: int
    until_outlets_drained: bool


class InvasionWork(NamedTuple):
    """The output and scratch arrays of :func:`invade_pairs` (int, of one width).

    Attributes
    ----------
    order, via : ndarray, shape (N,)
        Output: drained pores in order, in ``order[:K]``, and the rank of the throat through
        which each was entered (-1 for inlets).
    key, target : ndarray, shapes (N,) and (M,)
        Scratch: each pore's smallest rank to a drained pore (-1 once drained), and the pore
        that each queued rank leads to.
    """

    order: np.ndarray
    via: np.ndarray
    key: np.ndarray
    target: np.ndarray


@njit
def invade_pairs(
    graph: RankedGraph,
    inlets: np.ndarray,
    outlet: np.ndarray,
    stops: InvasionStops,
    work: InvasionWork,
) -> int:
    """Invasion percolation without trapping, on throats relabelled by rank.

    Parameters
    ----------
    graph : RankedGraph
        The throats by rank.
    inlets : ndarray of int64
        Pores drained at the start, recorded first in the given order.
    outlet : ndarray of bool, shape (N,)
        Pores connected to the outlet; breakthrough is the first drained outlet pore.
    stops : InvasionStops
    work : InvasionWork
        The output (``order``, ``via``) and scratch arrays.

    Returns
    -------
    int
        K, the number of steps recorded.
    """
    indptr, width, pairs, m = graph
    stop_at_outlet, max_steps, until_outlets_drained = stops
    order, via, key, target = work
    n = indptr.shape[0] - 1
    none = m  # key of an undrained pore with no drained neighbour: above every rank
    key[:n] = none
    words, offsets = queue_new(m)
    check_outlet = stop_at_outlet or until_outlets_drained
    outlets_left = 0
    if until_outlets_drained:
        for p in range(n):
            outlets_left += outlet[p]
    k = 0
    done = False
    for p in inlets:
        if k >= max_steps:
            break
        if key[p] < 0:
            continue
        if key[p] != none:
            queue_remove(words, offsets, key[p])
        key[p] = -1
        order[k] = p
        via[k] = -1
        k += 1
        if outlet[p]:
            outlets_left -= 1
            done |= stop_at_outlet
        start, stop = _row(indptr, width, p)
        for e in range(start, stop, 2):
            nb = pairs[e]
            r = pairs[e + 1]
            kn = key[nb]
            if r < kn:
                if kn != none:
                    queue_remove(words, offsets, kn)
                key[nb] = r
                target[r] = nb
                queue_insert(words, offsets, r)
    r = -1
    if not done and k < max_steps and not (until_outlets_drained and outlets_left == 0):
        r = queue_min(words, offsets)
    q = target[r] if r >= 0 else 0
    while r >= 0:
        key[q] = -1
        order[k] = q
        via[k] = r
        k += 1
        if check_outlet and outlet[q]:
            outlets_left -= 1
            if stop_at_outlet or outlets_left == 0:
                break
        if k >= max_steps:
            break
        # Candidate 1 for the next step: the next-smallest queued rank. Fetch its pore's row
        # now; its load overlaps with the work on q's neighbours.
        s = queue_pop_min(words, offsets, r)
        q_s = 0
        if s >= 0:
            q_s = target[s]
            prefetch(pairs, _row(indptr, width, q_s)[0])
        # Candidate 2: the smallest of the keys lowered now.
        new_rank = none
        new_pore = -1
        s_removed = False
        start, stop = _row(indptr, width, q)
        for e in range(start, stop, 2):
            nb = pairs[e]
            r2 = pairs[e + 1]
            kn = key[nb]
            if r2 < kn:  # nb undrained (key >= 0) and now reached more cheaply through q
                if kn != none:
                    queue_remove(words, offsets, kn)
                    s_removed |= kn == s
                key[nb] = r2
                target[r2] = nb
                queue_insert(words, offsets, r2)
                prefetch(pairs, _row(indptr, width, nb)[0])
                if r2 < new_rank:
                    new_rank = r2
                    new_pore = nb
        if s_removed:
            r = queue_min(words, offsets)
            if r >= 0:
                q = target[r]
        elif s >= 0 and s < new_rank:
            r = s
            q = q_s
        elif new_pore >= 0:
            r = new_rank
            q = new_pore
        else:
            r = -1
    return k


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
    """:func:`invade_pairs` on a CSR adjacency, allocating its own work arrays.

    ``neighbours`` holds the neighbouring pore and ``neighbour_rank`` the rank of the throat
    (``rank[throats]``) of each CSR entry; the other arguments are those of
    :func:`invade_pairs`. Returns ``(order, via_rank)``: the drained pores in order and the
    rank of the throat through which each was entered (-1 for inlets).
    """
    n = indptr.shape[0] - 1
    m = neighbour_rank.shape[0] // 2
    pairs = np.empty(2 * neighbours.shape[0], dtype=np.int64)
    for e in range(neighbours.shape[0]):
        pairs[2 * e] = neighbours[e]
        pairs[2 * e + 1] = neighbour_rank[e]
    order = np.empty(n, dtype=np.int64)
    via = np.empty(n, dtype=np.int64)
    key = np.empty(n, dtype=np.int64)
    target = np.empty(max(m, 1), dtype=np.int64)
    k = invade_pairs(
        RankedGraph(indptr, 0, pairs, m),
        inlets,
        outlet,
        InvasionStops(stop_at_outlet, max_steps, False),
        InvasionWork(order, via, key, target),
    )
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
    n = indptr.shape[0] - 1
    m = len(entry)
    index = np.int32 if max(n, m) < 2**31 - 1 else np.int64
    degree = max_degree(indptr)
    width = degree if degree * n <= _MAX_PADDING * len(neighbours) else 0
    work = _arena(
        (m, index),  # by_rank
        (m, index),  # rank
        (m, np.uint64),  # keys (sort)
        (2 * width * n if width else 2 * len(neighbours), index),  # pairs
        (n, index),  # order
        (n, index),  # via
        (n, index),  # key (invade)
        (m, index),  # target (invade)
        *(((n, np.uint8), (n, index), (n, np.bool_)) if trapping else ()),  # state, stack, trapped
    )
    by_rank, rank, keys, pairs, order, via, key, target = work[:8]
    _ranks_into(entry, by_rank, rank, keys)
    rank_pairs(indptr, neighbours, throats, rank, width, pairs)
    # read only from here on, like the lattice's adjacency: the flood fill shared with
    # enclosed_defender then compiles once (numba types read-only arrays apart)
    pairs.flags.writeable = False
    inlets = np.ascontiguousarray(inlets, dtype=np.int64)
    outlet = np.ascontiguousarray(outlet, dtype=np.bool_)
    max_steps = max(int(max_steps), 0)
    limit = n if trapping else max_steps
    graph = RankedGraph(indptr, width, pairs, m)
    k = invade_pairs(graph, inlets, outlet, InvasionStops(stop_at_outlet, limit, trapping),
                     InvasionWork(order, via, key, target))  # fmt: skip
    if trapping:
        adjacency = Adjacency(indptr, width, pairs, 2)
        kept = drop_trapped(adjacency, order, via, k, outlet, TrapWork(*work[8:]))
        k = min(kept, max_steps)
    throat = np.empty(k, dtype=np.int64)
    _rank_to_throat(via[:k], by_rank, throat)
    return order[:k].astype(np.int64), throat


@njit
def _rank_to_throat(via: np.ndarray, by_rank: np.ndarray, throat: np.ndarray) -> None:
    """``throat[k] = by_rank[via[k]]``, or -1 where ``via[k]`` is -1."""
    for k in range(via.shape[0]):
        throat[k] = by_rank[via[k]] if via[k] >= 0 else -1
