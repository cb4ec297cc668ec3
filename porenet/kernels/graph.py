"""Graph structure kernels."""

from __future__ import annotations

import numpy as np

from porenet.kernels._jit import njit


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
