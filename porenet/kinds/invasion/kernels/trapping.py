"""Trapping for invasion percolation (docs/model.md section 3): which pores of the defending
fluid are cut off from the outlet.

* :func:`trapped_steps` finds which steps of an invasion *without* trapping would have entered a
  defending cluster cut off from the outlet, by adding the invaded pores back in reverse order
  and growing the set of pores connected to the outlet (each pore joins it once, so the pass is
  O(N + M)). Removing those steps (:func:`drop_trapped`) gives exactly the invasion *with*
  trapping: an enclosed cluster is surrounded by invaded pores for ever, so invading it never
  changes the frontier elsewhere (Sheppard, Knackstedt, Pinczewski & Sahimi 1999; Masson 2016).
* :func:`enclosed_defender` marks the defending pores of one drainage state that are cut off
  (a flood fill from the undrained outlet pores), for models that drain otherwise.

Both read the adjacency in either layout of :mod:`porenet.kinds.invasion.kernels.ip`: CSR, or
interleaved (neighbour, rank) pairs padded to a fixed width per pore (:class:`Adjacency`).
Pure functions on arrays; the pore states of a flood fill are 0 absent (drained), 1 present
(defending), 2 connected to the outlet.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from porenet.jit.jit import njit, prefetch

#: How many steps ahead the reverse trapping pass prefetches adjacency rows.
_AHEAD = 16


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
    contains an outlet pore. Adding the pores back in reverse order answers this for every
    step: the set of present pores connected to an outlet pore only grows, so a pore added next
    to it (or an outlet pore) joins it together with its whole cluster (a flood fill), and each
    pore joins once; a pore added elsewhere is trapped. O(N + M) in all.

    Parameters
    ----------
    indptr, neighbours : ndarray of int
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
    k = order.shape[0]
    trapped = np.empty(k, dtype=np.bool_)
    state = np.empty(n, dtype=np.uint8)
    stack = np.empty(max(n, 1), dtype=indptr.dtype)
    _trapped(Adjacency(indptr, 0, neighbours, 1), order, k, outlet, n_inlets,
             TrapWork(state, stack, trapped))  # fmt: skip
    return trapped


class Adjacency(NamedTuple):
    """Where each pore's neighbours are, in either layout: pore ``p``'s neighbours are
    ``entries[start:start + stride * count:stride]`` with ``(start, count)`` from
    :func:`_span`: CSR entries scaled by ``stride`` if ``width == 0``, else ``width`` padded
    slots from ``stride * width * p`` (a padding slot is ``p`` itself, which is harmless)."""

    indptr: np.ndarray
    width: int
    entries: np.ndarray
    stride: int


class TrapWork(NamedTuple):
    """Scratch of the trapping pass: ``state`` and ``stack`` (N), ``trapped`` (K)."""

    state: np.ndarray
    stack: np.ndarray
    trapped: np.ndarray


@njit
def _trapped(
    adjacency: Adjacency,
    order: np.ndarray,
    k: int,
    outlet: np.ndarray,
    n_inlets: int,
    work: TrapWork,
) -> None:
    """:func:`trapped_steps` of ``order[:k]`` into ``work.trapped[:k]``, on either adjacency
    layout."""
    indptr, width, entries, stride = adjacency
    state, stack, trapped = work
    n = indptr.shape[0] - 1
    absent, present, connected = 0, 1, 2
    state[:n] = present
    for t in range(k):
        state[order[t]] = absent
    for p in range(n):  # the pores never drained
        if state[p] == present and outlet[p]:
            state[p] = connected
            _flood(indptr, width, entries, stride, state, stack, p)
    for t in range(k - 1, -1, -1):
        p = order[t]
        if t >= _AHEAD:  # the pores to come are known: start loading their rows now
            prefetch(entries, _span(indptr, width, stride, order[t - _AHEAD])[0])
        reach = outlet[p]
        if not reach:
            start, count = _span(indptr, width, stride, p)
            for i in range(count):
                if state[entries[start + stride * i]] == connected:
                    reach = True
                    break
        trapped[t] = (not reach) and t >= n_inlets
        if not reach:
            state[p] = present
            continue
        state[p] = connected  # and so is its cluster
        _flood(indptr, width, entries, stride, state, stack, p)


@njit(helper=True)
def _span(indptr: np.ndarray, width: int, stride: int, p: int) -> tuple[int, int]:
    """First entry and number of entries of pore ``p`` in an adjacency of the given layout."""
    if width > 0:
        return stride * width * p, width
    return stride * indptr[p], indptr[p + 1] - indptr[p]


@njit(helper=True)
def _flood(
    indptr: np.ndarray,
    width: int,
    adjacency: np.ndarray,
    stride: int,
    state: np.ndarray,
    stack: np.ndarray,
    p: int,
) -> None:
    """Mark (state 2) every pore of state 1 connected to ``p`` through pores of state 1."""
    stack[0] = p
    top = 1
    while top > 0:
        top -= 1
        x = stack[top]
        start, count = _span(indptr, width, stride, x)
        for i in range(count):
            y = adjacency[start + stride * i]
            if state[y] == 1:
                state[y] = 2
                stack[top] = y
                top += 1


@njit
def drop_trapped(
    adjacency: Adjacency,
    order: np.ndarray,
    via: np.ndarray,
    k: int,
    outlet: np.ndarray,
    work: TrapWork,
) -> int:
    """Move the steps of ``order[:k], via[:k]`` that are not trapped (:func:`trapped_steps`)
    to the front, in order; return their number. The leading steps with ``via == -1`` are the
    inlets. ``work`` is scratch space (N, N, K)."""
    n_inlets = 0
    while n_inlets < k and via[n_inlets] < 0:
        n_inlets += 1
    _trapped(adjacency, order, k, outlet, n_inlets, work)
    trapped = work.trapped
    kept = 0
    for t in range(k):
        if not trapped[t]:
            order[kept] = order[t]
            via[kept] = via[t]
            kept += 1
    return kept


@njit
def enclosed_defender(
    indptr: np.ndarray, neighbours: np.ndarray, drained: np.ndarray, outlet: np.ndarray
) -> np.ndarray:
    """Defending pores whose cluster contains no outlet pore.

    A flood fill of the defending pores from the undrained outlet pores, O(N + M).

    Parameters
    ----------
    indptr, neighbours : ndarray of int
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
    state = np.zeros(n, dtype=np.uint8)  # 0 drained, 1 defending, 2 defending and reached
    for p in range(n):
        if not drained[p]:
            state[p] = 1
    stack = np.empty(max(n, 1), dtype=indptr.dtype)
    for p in range(n):
        if state[p] == 1 and outlet[p]:
            state[p] = 2
            _flood(indptr, 0, neighbours, 1, state, stack, p)
    result = np.zeros(n, dtype=np.bool_)
    for p in range(n):
        result[p] = state[p] == 1
    return result


__all__ = ["Adjacency", "TrapWork", "drop_trapped", "enclosed_defender", "trapped_steps"]
