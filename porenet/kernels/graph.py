"""Graph structure kernels."""

from __future__ import annotations

import numpy as np

from porenet.jit.jit import njit


@njit
def _fill_csr(throat_pores: np.ndarray, indptr: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    m = throat_pores.shape[0]
    cursor = indptr[:-1].copy()
    neighbours = np.empty(2 * m, dtype=indptr.dtype)
    throats = np.empty(2 * m, dtype=indptr.dtype)
    for t in range(m):
        a = throat_pores[t, 0]
        b = throat_pores[t, 1]
        neighbours[cursor[a]] = b
        throats[cursor[a]] = t
        cursor[a] += 1
        neighbours[cursor[b]] = a
        throats[cursor[b]] = t
        cursor[b] += 1
    return neighbours, throats


def csr_adjacency(
    throat_pores: np.ndarray, n_pores: int
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Pore neighbour lists in CSR form, O(N + M).

    Parameters
    ----------
    throat_pores : ndarray of int64, shape (M, 2)
        The two pores each throat joins.
    n_pores : int

    Returns
    -------
    indptr : ndarray of int32 (int64 for more than 2**30 throats), shape (N+1,)
    neighbours : ndarray, shape (2M,)
        ``neighbours[indptr[p]:indptr[p+1]]`` are the pores next to ``p``...
    throats : ndarray, shape (2M,)
        ...through these throats, in increasing throat index.
    """
    small = 2 * len(throat_pores) < 2**31 - 1
    index = np.int32 if small else np.int64
    tp = np.ascontiguousarray(throat_pores, dtype=index)
    counts = np.bincount(tp.ravel(), minlength=n_pores)
    indptr = np.zeros(n_pores + 1, dtype=index)
    np.cumsum(counts, out=indptr[1:])
    neighbours, throats = _fill_csr(tp, indptr)
    return indptr, neighbours, throats


@njit
def max_degree(indptr: np.ndarray) -> int:
    """Largest number of neighbours of a pore (0 without pores)."""
    degree = 0
    for p in range(indptr.shape[0] - 1):
        degree = max(degree, indptr[p + 1] - indptr[p])
    return degree


@njit
def rank_pairs(
    indptr: np.ndarray,
    neighbours: np.ndarray,
    throats: np.ndarray,
    rank: np.ndarray,
    width: int,
    pairs: np.ndarray,
) -> np.ndarray:
    """The adjacency as interleaved ``(neighbour, throat rank)`` pairs, one cache line per pore.

    Parameters
    ----------
    indptr, neighbours, throats : ndarray of int
        CSR adjacency (:func:`csr_adjacency`).
    rank : ndarray of int, shape (M,)
        Rank of each throat.
    width : int
        0 for CSR order: pore ``p``'s pairs fill ``[2 indptr[p], 2 indptr[p+1])``. A positive
        ``width`` at least the largest degree gives a padded (ELLPACK) layout: pore ``p``'s
        pairs fill ``[2 width p, 2 width (p+1))``, so its row is found without reading
        ``indptr``; unused slots hold the pair ``(p, 0)`` (a loop onto the pore itself).
    pairs : ndarray of int, shape (2 * 2M,) for CSR order or (2 * width * N,) padded
        Output, returned.
    """
    n = indptr.shape[0] - 1
    if width == 0:
        for e in range(neighbours.shape[0]):
            pairs[2 * e] = neighbours[e]
            pairs[2 * e + 1] = rank[throats[e]]
        return pairs
    for p in range(n):
        a = indptr[p]
        degree = indptr[p + 1] - a
        j = 2 * width * p
        for i in range(width):
            if i < degree:
                pairs[j + 2 * i] = neighbours[a + i]
                pairs[j + 2 * i + 1] = rank[throats[a + i]]
            else:
                pairs[j + 2 * i] = p
                pairs[j + 2 * i + 1] = 0
    return pairs
