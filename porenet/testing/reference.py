"""Slow, obvious reference implementations, for tests (docs/architecture.md, rule 5).

These follow the textbook definitions literally (a heap of tuples; a flood fill after every
step to find trapped clusters) and are O(N^2) in the worst case: use them on small lattices.
"""

from __future__ import annotations

import heapq
from collections import deque

import numpy as np


def _neighbours(throat_pores: np.ndarray, n_pores: int) -> list[list[tuple[int, int]]]:
    nbrs: list[list[tuple[int, int]]] = [[] for _ in range(n_pores)]
    for t, (a, b) in enumerate(np.asarray(throat_pores).tolist()):
        nbrs[a].append((b, t))
        nbrs[b].append((a, t))
    return nbrs


def _cut_off(
    start: int, drained: np.ndarray, nbrs: list[list[tuple[int, int]]], outlet: np.ndarray
) -> set[int]:
    """The defending cluster of ``start``, or an empty set if it reaches the outlet."""
    seen = {start}
    queue = deque([start])
    while queue:
        p = queue.popleft()
        if outlet[p]:
            return set()
        for q, _ in nbrs[p]:
            if not drained[q] and q not in seen:
                seen.add(q)
                queue.append(q)
    return seen


def reference_invasion(
    throat_pores: np.ndarray,
    entry: np.ndarray,
    inlets: np.ndarray,
    outlet: np.ndarray,
    *,
    trapping: bool,
    stop_at_outlet: bool,
) -> tuple[list[int], set[int]]:
    """Invasion percolation by its definition.

    Each step drains the undrained pore behind the frontier throat of smallest entry pressure
    (ties: lower throat index). With trapping, after every step each defending cluster next to
    the drained pore is flood-filled; one that reaches no outlet pore is trapped and its
    throats are never taken again.

    Returns
    -------
    order : list of int
        Pores in order of drainage (inlets first).
    trapped : set of int
        Defending pores trapped at the end (empty without trapping).
    """
    n = len(outlet)
    nbrs = _neighbours(throat_pores, n)
    drained = np.zeros(n, dtype=bool)
    trapped = np.zeros(n, dtype=bool)
    heap: list[tuple[float, int, int]] = []
    order: list[int] = []

    def drain(p: int) -> None:
        drained[p] = True
        order.append(p)
        for q, t in nbrs[p]:
            if not drained[q]:
                heapq.heappush(heap, (float(entry[t]), t, q))

    for p in inlets:
        drain(int(p))
    if stop_at_outlet and any(outlet[p] for p in order):
        return order, set()
    while heap:
        _, _, q = heapq.heappop(heap)
        if drained[q] or trapped[q]:
            continue
        drain(q)
        if stop_at_outlet and outlet[q]:
            break
        if trapping:
            for r, _ in nbrs[q]:
                if not drained[r] and not trapped[r]:
                    for s in _cut_off(r, drained, nbrs, outlet):
                        trapped[s] = True
    return order, {int(p) for p in np.flatnonzero(trapped)}
