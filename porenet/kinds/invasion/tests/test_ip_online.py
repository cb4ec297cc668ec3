"""The online invasion-percolation kernel against the one-shot kernel and a slow reference."""

from __future__ import annotations

from collections import deque

import numpy as np
import pytest

from porenet.kernels.graph import csr_adjacency, max_degree
from porenet.kinds.invasion.kernels import ip
from porenet.kinds.invasion.kernels import online as io
from porenet.kinds.invasion.kernels import trapping as trap
from porenet.kinds.square.model import canonical_throats


def square(n: int, rng: np.random.Generator, ties: bool = False):
    """Throat pairs, CSR adjacency, entry pressures and boundary outlet of an n x n lattice."""
    tp = canonical_throats(n)
    if ties:
        r = rng.integers(1, 4, size=len(tp)).astype(float)  # many exact ties
    else:
        r = rng.uniform(0.7, 1.3, size=len(tp))
    outlet = np.zeros((n, n), dtype=bool)
    outlet[0, :] = outlet[-1, :] = outlet[:, 0] = outlet[:, -1] = True
    return tp, csr_adjacency(tp, n * n), ip.entry_pressures(r), outlet.ravel()


def centre(n: int) -> np.ndarray:
    return np.array([(n // 2) * n + n // 2], dtype=np.int64)


def edges(n: int) -> tuple[np.ndarray, np.ndarray]:
    """Left-edge inlets and right-edge outlet."""
    grid = np.arange(n * n).reshape(n, n)
    outlet = np.zeros(n * n, dtype=bool)
    outlet[grid[:, -1]] = True
    return grid[:, 0].astype(np.int64), outlet


def start(adj, n_throats, inlets, outlet, trapping):
    state = io.online_state(len(outlet), n_throats, max_degree(adj[0]))
    k = io.online_start(io.Graph(*adj), inlets, outlet, trapping, state)
    return state, k


def frontier_by_definition(tp, status):
    """Throats joining a drained pore to an undrained, untrapped one."""
    a, b = status[tp[:, 0]], status[tp[:, 1]]
    d, u = io.DRAINED, io.UNDRAINED
    return set(np.flatnonzero(((a == d) & (b == u)) | ((a == u) & (b == d))).tolist())


def compare(adj, entry, inlets, outlet, trapping, stop):
    kwargs = {"trapping": trapping, "stop_at_outlet": stop, "max_steps": len(outlet)}
    order, via = ip.invasion_sequence(adj, entry, inlets, outlet, **kwargs)
    order2, via2 = io.online_sequence(adj, entry, inlets, outlet, **kwargs)
    assert order2.tolist() == order.tolist()
    assert via2.tolist() == via.tolist()


@pytest.mark.parametrize("ties", [False, True])
@pytest.mark.parametrize("n", [3, 5, 20, 40])
def test_matches_invasion_sequence(n, ties):
    for seed in range(3):
        _, adj, entry, outlet = square(n, np.random.default_rng(seed), ties)
        edge_inlets, edge_outlet = edges(n)
        for trapping in (False, True):
            for stop in (False, True):
                compare(adj, entry, centre(n), outlet, trapping, stop)
                compare(adj, entry, edge_inlets, edge_outlet, trapping, stop)


def test_max_steps_and_inlet_cases_match_invasion_sequence():
    n = 9
    _, adj, entry, outlet = square(n, np.random.default_rng(3))
    kwargs = {"trapping": True, "stop_at_outlet": True}
    for max_steps in (0, 1, 7, n * n):
        a = ip.invasion_sequence(adj, entry, centre(n), outlet, max_steps=max_steps, **kwargs)
        b = io.online_sequence(adj, entry, centre(n), outlet, max_steps=max_steps, **kwargs)
        assert b[0].tolist() == a[0].tolist()
    grid = np.arange(n * n).reshape(n, n)
    ring = np.concatenate([grid[2, 2:7], grid[6, 2:7], grid[3:6, 2], grid[3:6, 6]])
    cases = [
        np.array([40, 40, 41], dtype=np.int64),  # a repeated inlet is drained once
        np.array([40, 0], dtype=np.int64),  # an inlet that is an outlet pore: breakthrough
        ring.astype(np.int64),  # encloses pores that are trapped from the start
    ]
    for inlets in cases:
        for trapping in (False, True):
            for stop in (False, True):
                compare(adj, entry, inlets, outlet, trapping, stop)


@pytest.mark.parametrize("edge", [False, True])
def test_online_trapping_and_frontier_after_every_step(edge):
    n = 15
    tp, adj, entry, outlet = square(n, np.random.default_rng(7))
    inlets = centre(n)
    if edge:
        inlets, outlet = edges(n)
    state, _ = start(adj, len(tp), inlets, outlet, True)
    status = state.status
    steps = 0
    while True:
        drained = status == io.DRAINED
        enclosed = trap.enclosed_defender(adj[0], adj[1], drained, outlet)
        assert np.array_equal(status == io.TRAPPED, enclosed)
        assert set(io.online_frontier(state).tolist()) == frontier_by_definition(tp, status)
        pore, throat, pressure = io.online_step(io.Graph(*adj), entry, outlet, True, state)
        if pore < 0:
            break
        assert status[pore] == io.DRAINED and pressure == entry[throat]
        steps += 1
    assert np.all(status != io.UNDRAINED)  # exhausted: every pore drained or trapped
    assert 0 < np.sum(status == io.TRAPPED) < n * n - steps
    before = [a.copy() for a in state]
    assert io.online_step(io.Graph(*adj), entry, outlet, True, state)[0] == -1
    assert all(np.array_equal(a, b) for a, b in zip(before, state, strict=True))


def test_advance_in_chunks_equals_one_call():
    n = 20
    tp, adj, entry, outlet = square(n, np.random.default_rng(4))
    out = [np.empty(n * n, dtype=np.int64), np.empty(n * n, dtype=np.int64), np.empty(n * n)]
    for trapping in (False, True):
        for stop in (False, True):
            state, _ = start(adj, len(tp), centre(n), outlet, trapping)
            graph = io.Graph(*adj)
            k = io.online_advance(graph, entry, outlet, trapping, state, n * n, stop, tuple(out))
            whole = [a[:k].copy() for a in out]
            state, _ = start(adj, len(tp), centre(n), outlet, trapping)
            parts: list[list[np.ndarray]] = [[], [], []]
            while True:
                j = io.online_advance(graph, entry, outlet, trapping, state, 17, stop, tuple(out))
                for part, a in zip(parts, out, strict=True):
                    part.append(a[:j].copy())
                if j < 17:
                    break
            for a, part in zip(whole, parts, strict=True):
                assert np.array_equal(np.concatenate(part), a)
            assert np.array_equal(whole[2], entry[whole[1]])


def _enclosed(nbrs, drained, outlet):
    """Undrained pores that reach no undrained outlet pore (breadth-first from the outlet)."""
    reached = [bool(o) and not d for o, d in zip(outlet, drained, strict=True)]
    queue = deque(p for p in range(len(outlet)) if reached[p])
    while queue:
        p = queue.popleft()
        for q, _ in nbrs[p]:
            if not drained[q] and not reached[q]:
                reached[q] = True
                queue.append(q)
    return [not d and not r for d, r in zip(drained, reached, strict=True)]


def reference_changing(tp, inlets, outlet, trapping, entries):
    """Invasion by its definition, with entry pressures ``entries[k]`` at step k."""
    n = len(outlet)
    nbrs: list[list[tuple[int, int]]] = [[] for _ in range(n)]
    for t, (a, b) in enumerate(tp.tolist()):
        nbrs[a].append((b, t))
        nbrs[b].append((a, t))
    drained = [False] * n
    for p in inlets.tolist():
        drained[p] = True
    trapped = _enclosed(nbrs, drained, outlet) if trapping else [False] * n
    steps = []
    for entry in entries:
        best = None
        for t, (a, b) in enumerate(tp.tolist()):
            for x, q in ((a, b), (b, a)):
                if drained[x] and not drained[q] and not trapped[q]:
                    best = min(best or (np.inf, t, q), (float(entry[t]), t, q))
        if best is None:
            break
        pressure, t, q = best
        drained[q] = True
        steps.append((q, t, pressure))
        if trapping:
            trapped = _enclosed(nbrs, drained, outlet)
    return steps


@pytest.mark.parametrize("ties", [False, True])
@pytest.mark.parametrize("trapping", [False, True])
def test_entries_changing_between_steps_match_reference(trapping, ties):
    n = 10
    rng = np.random.default_rng(12)
    tp, adj, _, outlet = square(n, rng)
    entries = [square(n, rng, ties)[2] for _ in range(n * n)]
    for inlets, out in [(centre(n), outlet), edges(n)]:
        expected = reference_changing(tp, inlets, out, trapping, entries)
        state, _ = start(adj, len(tp), inlets, out, trapping)
        entry = entries[0].copy()
        steps = []
        for k in range(len(entries)):
            # refresh only the frontier throats, as a mechanical update would
            front = io.online_frontier(state)
            entry[front] = entries[k][front]
            pore, throat, pressure = io.online_step(io.Graph(*adj), entry, out, trapping, state)
            if pore < 0:
                break
            steps.append((pore, throat, pressure))
        assert steps == expected
