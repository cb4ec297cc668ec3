"""Step-by-step ("online") invasion percolation with entry pressures that may change between steps.

The kernels of :mod:`porenet.kinds.invasion.kernels.ip` precompute the whole invasion from quenched
entry pressures and apply trapping afterwards, in reverse. When the medium deforms after every
drained pore, the entry pressures change between steps and neither trick applies. The kernels here
advance the invasion one pore at a time instead, keeping its state in plain arrays
(:func:`online_state`) that the caller passes back at every call:

* the *frontier* (the throats joining a drained pore to an undrained, untrapped one) is a
  compact list with the undrained pore behind each throat, plus the position of every throat in
  the list (-1 when absent), so a throat is added or removed in O(1) (the last entry fills the
  hole);
* each step scans the whole list for the throat of smallest entry pressure, ties by the lower
  throat index: O(F) for F frontier throats, with no assumption about how the pressures changed
  since the last step;
* with trapping, the defending clusters that the drained pore splits off from the outlet are
  found right after it drains (below) and their pores are trapped for good.

With entry pressures that never change, the sequence equals that of
:func:`porenet.kinds.invasion.kernels.ip.invasion_sequence` (same pores and throats, same
tie-breaking, same treatment of repeated inlets, of inlets cut off from the outlet and of
breakthrough).

Online trapping
---------------
Before pore ``p`` drains, its defending cluster contains an outlet pore (else ``p`` would be
trapped). Draining ``p`` may split it into pieces, each holding some undrained neighbours of
``p``. One breadth-first search starts from each distinct undrained neighbour; the searches
advance in lock-step (one pore each per round) and label the pores they reach:

* a search that reaches an outlet pore has a connected piece and stops;
* a search that reaches a pore labelled by another search is in the same piece: it hands its
  queue over to that one (union-find over at most ``degree(p)`` searches) and stops;
* a search whose queue runs dry has explored a whole piece without an outlet pore: trapped;
* when one search is left undecided and no other reached an outlet pore, its piece holds the
  outlet pore of ``p``'s former cluster: it is connected, and is not explored further. This
  needs ``p`` not to be an outlet pore itself; when it is, every search runs until decided.

Cost of the trapping update of one step, with ``d = degree(p)``: every search stops after at
most as many rounds as the search decided last but one, so at most ``d`` times the work of that
one is done, where the work of a trapped piece is its size, that of a connected piece is the
breadth-first ball up to its nearest outlet pore, and two searches in one piece count until
they meet (quick when the neighbours are joined near ``p``, e.g. through the pore diagonal to
``p`` on a square lattice). The largest piece, usually the one holding the outlet, is explored
no further than the others; when only one piece is left nothing is explored. Each trapped
piece is flood-filled once in the whole run (O(N + M) in all). The worst case is O(N + M) per
step. Labels carry a stamp that grows with every step, so nothing is cleared between steps,
and the queues are linked lists through one array of N entries, so handing one over is O(1).

Typical use, with entry pressures that change after every step::

    graph = Graph(indptr, neighbours, throats)
    state = online_state(n_pores, n_throats, max_degree(indptr))
    online_start(graph, inlets, outlet, trapping, state)
    while True:
        pore, throat, pressure = online_step(graph, entry, outlet, trapping, state)
        if pore < 0 or (stop_at_outlet and outlet[pore]):
            break
        ...  # deform the medium, then refresh entry[online_frontier(state)]

:func:`online_advance` takes many steps in one call when the entries do not change in between.

Length (over the ~500 lines of docs/architecture.md's rule): one algorithm: the step, the
frontier it keeps and the trapping it updates after every step share the layout of OnlineState,
and ``_trap_after`` (a third of the module) is called only by the step. Apart, the same layout
would be described in two places.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from porenet.jit.jit import njit
from porenet.kernels.graph import max_degree

#: Pore status: defending, in a cluster with an outlet pore.
UNDRAINED = 0
#: Pore status: occupied by the invader.
DRAINED = 1
#: Pore status: defending, in a cluster without an outlet pore; never drained.
TRAPPED = 2

# Rows of the ``frontier`` state array (M columns).
_FRONT = 0  # frontier throats in [:count]
_BEHIND = 1  # the undrained pore behind each (same columns)
_POS = 2  # column of each throat in _FRONT, -1 if not on the frontier

# Rows of the ``scratch`` state array (N columns).
_MARK = 0  # search label of each pore (labels only grow: nothing to clear between steps)
_LINK = 1  # next pore in its search queue; also the flood-fill stack

# Entries of the ``counters`` state array.
_COUNT = 0  # number of frontier throats
_STAMP = 1  # first search label of the next step
_BROKE = 2  # 1 once an outlet pore is drained
_WORK = 3  # pores reached by the trapping searches so far (a cost diagnostic)

# Rows of the ``search`` state array (one column per search, i.e. per neighbour of the pore).
_PARENT = 0  # union-find parent (a search that met another hands over to it)
_STATE = 1  # _ACTIVE, _SAFE or _CUT, for a search that is its own parent
_HEAD = 2  # first pore of its queue (-1 when empty)
_TAIL = 3  # last pore of its queue
_START = 4  # the neighbour it started from

_ACTIVE = 0  # undecided
_SAFE = 1  # its piece holds an outlet pore
_CUT = 2  # its piece holds no outlet pore: trapped


class Graph(NamedTuple):
    """The CSR adjacency of the pores, throats in increasing index in each row
    (:attr:`porenet.core.interfaces.Lattice.adjacency`): pore ``i``'s neighbours are
    ``neighbours[indptr[i]:indptr[i + 1]]``, through ``throats[...]``."""

    indptr: np.ndarray
    neighbours: np.ndarray
    throats: np.ndarray


class OnlineState(NamedTuple):
    """The state of one online invasion (:func:`online_state`; rows and entries by the
    module's named constants).

    Attributes
    ----------
    status : ndarray of uint8, shape (N,)
        :data:`UNDRAINED`, :data:`DRAINED` or :data:`TRAPPED` for each pore.
    frontier : ndarray of int64, shape (3, M)
        The frontier throats, the pore behind each, each throat's column.
    scratch : ndarray of int64, shape (2, N)
        Search labels and queue links (also the flood fill's stack).
    search : ndarray of int64, shape (5, degree)
        One column per trapping search of a step.
    counters : ndarray of int64, shape (4,)
        Frontier size, next label, breakthrough flag, search work.
    """

    status: np.ndarray
    frontier: np.ndarray
    scratch: np.ndarray
    search: np.ndarray
    counters: np.ndarray


def online_state(n_pores: int, n_throats: int, degree: int) -> OnlineState:
    """Allocate the state of one invasion (initialised by :func:`online_start`).

    Parameters
    ----------
    n_pores, n_throats : int
        N and M.
    degree : int
        Largest number of neighbours of a pore (:func:`porenet.kernels.graph.max_degree`).

    Returns
    -------
    OnlineState
        ``status`` (pores' :data:`UNDRAINED`, :data:`DRAINED` or :data:`TRAPPED`);
        ``frontier``: row 0 the frontier throats, in ``[:counters[0]]``, in no particular
        order (:func:`online_frontier`), row 1 the undrained pore behind each, row 2 the
        column of each throat in row 0, -1 if it is not on the frontier; ``scratch``: search
        labels (kept between steps) and search queues; ``search``: bookkeeping of the searches
        of one step; ``counters``: number of frontier throats, next search label, 1 once an
        outlet pore is drained, pores reached by the trapping searches so far (their cost).
    """
    n, m = int(n_pores), int(n_throats)
    return OnlineState(
        np.zeros(n, dtype=np.uint8),
        np.zeros((3, m), dtype=np.int64),
        np.zeros((2, n), dtype=np.int64),
        np.zeros((5, max(int(degree), 1)), dtype=np.int64),
        np.zeros(4, dtype=np.int64),
    )


def online_frontier(state: OnlineState) -> np.ndarray:
    """The throats now on the frontier, in no particular order.

    The next step reads the entry pressures of these throats only, so after the medium deforms
    only they need a new one.

    Parameters
    ----------
    state : OnlineState
        From :func:`online_state`.

    Returns
    -------
    ndarray of int64, shape (F,)
        A view into the state, valid until the next step (copy it to keep it).
    """
    return state.frontier[_FRONT, : state.counters[_COUNT]]


@njit(helper=True)
def _add(frontier: np.ndarray, counters: np.ndarray, t: int, q: int) -> None:
    """Put throat ``t`` (into undrained pore ``q``) on the frontier, if it is not there."""
    if frontier[_POS, t] >= 0:
        return
    i = counters[_COUNT]
    frontier[_FRONT, i] = t
    frontier[_BEHIND, i] = q
    frontier[_POS, t] = i
    counters[_COUNT] = i + 1


@njit(helper=True)
def _remove(frontier: np.ndarray, counters: np.ndarray, t: int) -> None:
    """Take throat ``t`` off the frontier, if it is there: the last entry fills its place."""
    i = frontier[_POS, t]
    if i < 0:
        return
    last = counters[_COUNT] - 1
    moved = frontier[_FRONT, last]
    frontier[_FRONT, i] = moved
    frontier[_BEHIND, i] = frontier[_BEHIND, last]
    frontier[_POS, moved] = i
    frontier[_POS, t] = -1
    counters[_COUNT] = last


@njit(helper=True)
def _find(search: np.ndarray, i: int) -> int:
    """Root of search ``i`` (union-find with path halving)."""
    while search[_PARENT, i] != i:
        search[_PARENT, i] = search[_PARENT, search[_PARENT, i]]
        i = search[_PARENT, i]
    return i


@njit(helper=True)
def _flood(graph: Graph, state: OnlineState, start: int, old: int, new: int) -> None:
    """Set the status to ``new`` on ``start`` and on every pore it reaches through pores of
    status ``old`` (as ``start``), and drop the throats from them to drained pores from the
    frontier. O(pores reached + their throats)."""
    indptr, neighbours, throats = graph
    status, frontier, scratch, counters = (state.status, state.frontier, state.scratch,
                                           state.counters)  # fmt: skip
    status[start] = new
    scratch[_LINK, 0] = start
    top = 1
    while top > 0:
        top -= 1
        x = scratch[_LINK, top]
        for e in range(indptr[x], indptr[x + 1]):
            y = neighbours[e]
            if status[y] == old:
                status[y] = new
                scratch[_LINK, top] = y
                top += 1
            elif status[y] == DRAINED:
                _remove(frontier, counters, throats[e])


@njit(helper=True)
def _trap_after(graph: Graph, outlet: np.ndarray, p: int, state: OnlineState) -> None:
    """Trap the defending clusters cut off from the outlet by draining pore ``p``.

    Lock-step breadth-first searches from the distinct undrained neighbours of ``p`` (module
    docstring). A pore reached by search ``i`` of this step gets the label ``base + i``.
    """
    indptr, neighbours = graph.indptr, graph.neighbours
    status, scratch, search, counters = state.status, state.scratch, state.search, state.counters
    base = counters[_STAMP]
    d = 0
    for e in range(indptr[p], indptr[p + 1]):
        q = neighbours[e]
        if status[q] != UNDRAINED or scratch[_MARK, q] >= base:  # or already a start
            continue
        scratch[_MARK, q] = base + d
        search[_PARENT, d] = d
        search[_START, d] = q
        search[_STATE, d] = _SAFE if outlet[q] else _ACTIVE
        search[_HEAD, d] = -1 if outlet[q] else q
        search[_TAIL, d] = q
        scratch[_LINK, q] = -1
        d += 1
    counters[_STAMP] = base + d
    if d == 0 or (d == 1 and not outlet[p]):
        return  # nothing left, or a single piece: p's cluster minus p, with its outlet pore
    alone = not outlet[p]  # then the last undecided search is connected if no other one is
    while True:
        undecided = 0
        safe = False
        last = -1
        for i in range(d):
            if search[_PARENT, i] == i:
                if search[_STATE, i] == _ACTIVE:
                    undecided += 1
                    last = i
                elif search[_STATE, i] == _SAFE:
                    safe = True
        if undecided == 0:
            break
        if undecided == 1 and alone and not safe:
            search[_STATE, last] = _SAFE
            break
        for i in range(d):  # one round: each undecided search expands one pore
            if search[_PARENT, i] != i or search[_STATE, i] != _ACTIVE:
                continue
            x = search[_HEAD, i]
            if x < 0:
                search[_STATE, i] = _CUT
                continue
            search[_HEAD, i] = scratch[_LINK, x]
            cur = i  # the search that x now belongs to (changes when i meets another one)
            for e in range(indptr[x], indptr[x + 1]):
                y = neighbours[e]
                if status[y] != UNDRAINED:
                    continue
                label = scratch[_MARK, y] - base
                if label < 0:  # not reached yet in this step
                    scratch[_MARK, y] = base + cur
                    counters[_WORK] += 1
                    if outlet[y]:
                        search[_STATE, cur] = _SAFE
                        break
                    scratch[_LINK, y] = -1
                    if search[_HEAD, cur] < 0:
                        search[_HEAD, cur] = y
                    else:
                        scratch[_LINK, search[_TAIL, cur]] = y
                    search[_TAIL, cur] = y
                    continue
                r = _find(search, label)
                if r == cur:
                    continue
                search[_PARENT, cur] = r  # same piece: hand over to r
                if search[_STATE, r] != _ACTIVE:  # r is connected (it cannot be cut off)
                    break
                if search[_HEAD, cur] >= 0:  # append cur's queue to r's
                    if search[_HEAD, r] < 0:
                        search[_HEAD, r] = search[_HEAD, cur]
                    else:
                        scratch[_LINK, search[_TAIL, r]] = search[_HEAD, cur]
                    search[_TAIL, r] = search[_TAIL, cur]
                cur = r
    for i in range(d):
        if search[_PARENT, i] == i and search[_STATE, i] == _CUT:
            _flood(graph, state, search[_START, i], UNDRAINED, TRAPPED)


@njit
def online_start(
    graph: Graph, inlets: np.ndarray, outlet: np.ndarray, trapping: bool, state: OnlineState
) -> int:
    """Reset the state and drain the inlets.

    With trapping, the defending clusters without an outlet pore once the inlets are drained
    are trapped at once (a flood fill from the outlet pores, O(N + M)), as in
    :func:`porenet.kinds.invasion.kernels.ip.invasion_sequence`.

    Parameters
    ----------
    graph : Graph
        The adjacency.
    inlets : ndarray of int64
        Pores drained at the start; a repeated pore is drained once.
    outlet : ndarray of bool, shape (N,)
        Pores connected to the outlet.
    trapping : bool
        Whether defending clusters cut off from the outlet are trapped.
    state : OnlineState
        From :func:`online_state`, overwritten.

    Returns
    -------
    int
        Number of distinct inlets (they are the pores of ``inlets`` in order of first
        appearance, as :func:`porenet.kinds.invasion.kernels.ip.invasion_sequence` records them).
    """
    indptr, neighbours, throats = graph
    status, frontier, scratch, counters = (state.status, state.frontier, state.scratch,
                                           state.counters)  # fmt: skip
    n = indptr.shape[0] - 1
    status[:] = UNDRAINED
    frontier[_POS, :] = -1
    scratch[_MARK, :] = -1
    counters[:] = 0
    k = 0
    for p in inlets:
        if status[p] == UNDRAINED:
            status[p] = DRAINED
            k += 1
            counters[_BROKE] |= outlet[p]
    if trapping:  # trap every undrained pore, then free those that the outlet pores reach
        for p in range(n):
            if status[p] == UNDRAINED:
                status[p] = TRAPPED
        for p in range(n):
            if outlet[p] and status[p] == TRAPPED:
                _flood(graph, state, p, TRAPPED, UNDRAINED)
    for p in inlets:
        for e in range(indptr[p], indptr[p + 1]):
            if status[neighbours[e]] == UNDRAINED:
                _add(frontier, counters, throats[e], neighbours[e])
    return k


@njit(helper=True)
def _step(
    graph: Graph, entry: np.ndarray, outlet: np.ndarray, trapping: bool, state: OnlineState
) -> tuple[int, int, float]:
    """:func:`online_step`, shared with :func:`online_advance`."""
    indptr, neighbours, throats = graph
    status, frontier, counters = state.status, state.frontier, state.counters
    count = counters[_COUNT]
    if count == 0:
        return -1, -1, np.nan
    best = 0
    t_best = frontier[_FRONT, 0]
    v_best = entry[t_best]
    for i in range(1, count):
        t = frontier[_FRONT, i]
        v = entry[t]
        if v < v_best or (v == v_best and t < t_best):
            best = i
            t_best = t
            v_best = v
    p = frontier[_BEHIND, best]
    status[p] = DRAINED
    for e in range(indptr[p], indptr[p + 1]):
        q = neighbours[e]
        if status[q] == DRAINED:  # the throat of this step among them
            _remove(frontier, counters, throats[e])
        elif status[q] == UNDRAINED:
            _add(frontier, counters, throats[e], q)
    counters[_BROKE] |= outlet[p]
    if trapping:
        _trap_after(graph, outlet, p, state)
    return p, t_best, v_best


@njit
def online_step(
    graph: Graph, entry: np.ndarray, outlet: np.ndarray, trapping: bool, state: OnlineState
) -> tuple[int, int, float]:
    """Drain one pore: the one behind the frontier throat of smallest entry pressure.

    Ties go to the lower throat index. Costs O(F) for the F frontier throats (a scan: any of
    their entry pressures may have changed since the last step) plus the trapping update
    (module docstring). It does not stop at breakthrough: check ``outlet[pore]``.

    Parameters
    ----------
    graph : Graph
        The adjacency, as for :func:`online_start`.
    entry : ndarray of float64, shape (M,)
        Current entry pressures (any consistent unit); only those of the frontier throats
        (:func:`online_frontier`) are read.
    outlet : ndarray of bool, shape (N,)
    trapping : bool
        As given to :func:`online_start`.
    state : OnlineState
        Updated in place.

    Returns
    -------
    pore : int
        The pore drained, -1 when nothing is left to invade (the state is then unchanged).
    throat : int
        The throat it was entered through (-1 if none).
    pressure : float
        ``entry[throat]`` at this step (NaN if none).
    """
    return _step(graph, entry, outlet, trapping, state)


@njit
def online_advance(
    graph: Graph,
    entry: np.ndarray,
    outlet: np.ndarray,
    trapping: bool,
    state: OnlineState,
    max_steps: int,
    stop_at_outlet: bool,
    steps_out: tuple[np.ndarray, np.ndarray, np.ndarray],
) -> int:
    """Up to ``max_steps`` steps of :func:`online_step` in one call, with fixed ``entry``.

    Parameters
    ----------
    graph, entry, outlet, trapping, state
        As for :func:`online_step`.
    max_steps : int
        Steps to take at most (inlets not counted).
    stop_at_outlet : bool
        Stop right after the step that drains an outlet pore, and take no step once one is
        drained (an inlet included): successive calls then give the steps of one call.
    steps_out : (order, via, pressure), ndarrays of shape (>= max_steps,)
        Output: the pores drained, the throats they were entered through (int64) and the
        entry pressure of each of those throats (float64), in ``[:K]``.

    Returns
    -------
    int
        K, the number of steps taken (fewer than ``max_steps`` at breakthrough or when nothing
        is left to invade).
    """
    order_out, via_out, pressure_out = steps_out
    k = 0
    if stop_at_outlet and state.counters[_BROKE]:
        return 0
    while k < max_steps:
        p, t, v = _step(graph, entry, outlet, trapping, state)
        if p < 0:
            break
        order_out[k] = p
        via_out[k] = t
        pressure_out[k] = v
        k += 1
        if stop_at_outlet and outlet[p]:
            break
    return k


def online_sequence(
    adjacency: tuple[np.ndarray, np.ndarray, np.ndarray],
    entry: np.ndarray,
    inlets: np.ndarray,
    outlet: np.ndarray,
    *,
    trapping: bool,
    stop_at_outlet: bool,
    max_steps: int,
) -> tuple[np.ndarray, np.ndarray]:
    """A whole invasion with fixed entry pressures, online: the arguments and the result of
    :func:`porenet.kinds.invasion.kernels.ip.invasion_sequence` (``max_steps`` counts the inlets).

    Returns
    -------
    order : ndarray of int64, shape (K,)
        Pores in order of drainage, inlets first.
    via : ndarray of int64, shape (K,)
        Throat through which each was entered (-1 for inlets).
    """
    indptr, neighbours, throats = adjacency
    n = indptr.shape[0] - 1
    entry = np.ascontiguousarray(entry, dtype=np.float64)
    outlet = np.ascontiguousarray(outlet, dtype=np.bool_)
    inlets = np.ascontiguousarray(inlets, dtype=np.int64)
    graph = Graph(indptr, neighbours, throats)
    state = online_state(n, len(entry), max_degree(indptr))
    k0 = online_start(graph, inlets, outlet, trapping, state)
    max_steps = max(int(max_steps), 0)
    order = np.empty(n, dtype=np.int64)
    via = np.full(n, -1, dtype=np.int64)
    order[:k0] = list(dict.fromkeys(inlets.tolist()))  # the distinct inlets, as drained
    pressure = np.empty(n, dtype=np.float64)
    k = online_advance(graph, entry, outlet, trapping, state, max(max_steps - k0, 0),
                       stop_at_outlet, (order[k0:], via[k0:], pressure))  # fmt: skip
    k = min(k0 + k, max_steps)
    return order[:k].copy(), via[:k].copy()
