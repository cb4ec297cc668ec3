"""Union-find (disjoint sets) on int64 arrays, for use inside other kernels.

Path halving and union by size: near-constant amortised cost per operation (Tarjan 1975).
"""

from __future__ import annotations

import numpy as np

from porenet.kernels._jit import njit


@njit
def uf_find(parent: np.ndarray, x: int) -> int:
    """Root of ``x``'s set (path halving)."""
    while parent[x] != x:
        parent[x] = parent[parent[x]]
        x = parent[x]
    return x


@njit
def uf_union(parent: np.ndarray, size: np.ndarray, a: int, b: int) -> None:
    """Merge the sets of ``a`` and ``b`` (union by size)."""
    ra = uf_find(parent, a)
    rb = uf_find(parent, b)
    if ra == rb:
        return
    if size[ra] < size[rb]:
        ra, rb = rb, ra
    parent[rb] = ra
    size[ra] += size[rb]


@njit
def uf_link(parent: np.ndarray, size: np.ndarray, root: int, b: int) -> int:
    """Merge ``b``'s set into the set whose root is ``root``; return the new root.

    Saves the second find of :func:`uf_union` when the caller already holds a root (adding one
    element and linking it to each of its neighbours in turn).
    """
    rb = uf_find(parent, b)
    if rb == root:
        return root
    if size[root] < size[rb]:
        root, rb = rb, root
    parent[rb] = root
    size[root] += size[rb]
    return root
