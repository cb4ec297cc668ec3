"""The invasion-percolation kernels against the slow reference implementation."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from porenet.kernels.graph import csr_adjacency
from porenet.kinds.invasion.kernels import ip
from porenet.kinds.invasion.kernels import trapping as trap
from porenet.kinds.invasion.kernels.bitqueue import queue_insert, queue_min, queue_new, queue_remove
from porenet.kinds.square.model import canonical_throats
from porenet.testing.reference import reference_invasion


def square(n: int, rng: np.random.Generator, ties: bool = False):
    tp = canonical_throats(n)
    if ties:
        r = rng.integers(1, 4, size=len(tp)).astype(float)  # many exact ties
    else:
        r = rng.uniform(0.7, 1.3, size=len(tp))
    outlet = np.zeros((n, n), dtype=bool)
    outlet[0, :] = outlet[-1, :] = outlet[:, 0] = outlet[:, -1] = True
    return tp, ip.entry_pressures(r), outlet.ravel()


def run_kernel(tp, entry, inlets, outlet, trapping, stop):
    adj = csr_adjacency(tp, len(outlet))
    return ip.invasion_sequence(
        adj,
        entry,
        inlets,
        outlet,
        trapping=trapping,
        stop_at_outlet=stop,
        max_steps=len(outlet),
    )


@pytest.mark.parametrize("trapping", [False, True])
@pytest.mark.parametrize("stop", [False, True])
@pytest.mark.parametrize("ties", [False, True])
@pytest.mark.parametrize("n", [3, 4, 9, 24])
def test_matches_reference(n, trapping, stop, ties):
    for seed in range(3):
        tp, entry, outlet = square(n, np.random.default_rng(seed), ties)
        inlets = np.array([(n // 2) * n + n // 2])
        order, via = run_kernel(tp, entry, inlets, outlet, trapping, stop)
        ref_order, _ = reference_invasion(
            tp, entry, inlets, outlet, trapping=trapping, stop_at_outlet=stop
        )
        assert order.tolist() == ref_order
        assert via[0] == -1
        # each pore was entered through a throat that touches it and an earlier drained pore
        pos = {p: i for i, p in enumerate(order.tolist())}
        for k in range(1, len(order)):
            a, b = tp[via[k]]
            other = b if a == order[k] else a
            assert order[k] in (a, b) and pos[other] < k


def test_edge_injection_matches_reference():
    n = 12
    tp, entry, _ = square(n, np.random.default_rng(5))
    grid = np.arange(n * n).reshape(n, n)
    inlets, outlet = grid[:, 0], np.zeros(n * n, dtype=bool)
    outlet[grid[:, -1]] = True
    for trapping in (False, True):
        order, _ = run_kernel(tp, entry, inlets, outlet, trapping, True)
        ref, _ = reference_invasion(
            tp, entry, inlets, outlet, trapping=trapping, stop_at_outlet=True
        )
        assert order.tolist() == ref


def test_trapped_set_matches_reference():
    n = 20
    tp, entry, outlet = square(n, np.random.default_rng(11))
    inlets = np.array([(n // 2) * n + n // 2])
    order, _ = run_kernel(tp, entry, inlets, outlet, True, False)
    _, ref_trapped = reference_invasion(
        tp, entry, inlets, outlet, trapping=True, stop_at_outlet=False
    )
    drained = np.zeros(n * n, dtype=bool)
    drained[order] = True
    indptr, nbrs, _ = csr_adjacency(tp, n * n)
    enclosed = trap.enclosed_defender(indptr, nbrs, drained, outlet)
    assert set(np.flatnonzero(enclosed).tolist()) == ref_trapped
    assert drained.sum() + len(ref_trapped) == n * n  # complete: every pore drained or trapped


def test_max_steps_counts_after_trapping():
    n = 16
    tp, entry, outlet = square(n, np.random.default_rng(2))
    inlets = np.array([(n // 2) * n + n // 2])
    adj = csr_adjacency(tp, n * n)
    full, _ = ip.invasion_sequence(
        adj, entry, inlets, outlet, trapping=True, stop_at_outlet=False, max_steps=n * n
    )
    part, _ = ip.invasion_sequence(
        adj, entry, inlets, outlet, trapping=True, stop_at_outlet=False, max_steps=50
    )
    assert part.tolist() == full[:50].tolist()


@settings(max_examples=60, deadline=None)
@given(st.lists(st.tuples(st.booleans(), st.integers(0, 5000)), min_size=1, max_size=400))
def test_bitqueue_is_a_priority_queue(ops):
    words, offsets = queue_new(5001)
    model: set[int] = set()
    for insert, key in ops:
        if insert:
            queue_insert(words, offsets, key)
            model.add(key)
        else:
            queue_remove(words, offsets, key)
            model.discard(key)
        assert queue_min(words, offsets) == (min(model) if model else -1)


def test_csr_adjacency_lists_every_throat_twice_in_order():
    tp = canonical_throats(5)
    indptr, nbrs, thr = csr_adjacency(tp, 25)
    assert indptr[-1] == 2 * len(tp)
    for p in range(25):
        ts = thr[indptr[p] : indptr[p + 1]]
        assert np.all(np.diff(ts) > 0)
        for q, t in zip(nbrs[indptr[p] : indptr[p + 1]], ts, strict=False):
            assert {p, q} == set(tp[t].tolist())


def test_throat_ranks_break_ties_by_index():
    entry = np.array([2.0, 1.0, 2.0, 1.0, 3.0])
    by_rank, rank = ip.throat_ranks(entry)
    assert by_rank.tolist() == [1, 3, 0, 2, 4]
    assert rank[by_rank].tolist() == list(range(5))


@settings(max_examples=80, deadline=None)
@given(
    st.lists(
        st.one_of(st.floats(0.1, 10.0), st.sampled_from([1.0, 2.0, 1e-3, 1e3])),
        min_size=1,
        max_size=300,
    )
)
def test_stable_argsort_equals_numpy_stable(values):
    from porenet.kernels.sorting import stable_argsort

    v = np.asarray(values)
    np.testing.assert_array_equal(stable_argsort(v), np.argsort(v, kind="stable"))


def test_stable_argsort_falls_back_on_uneven_distributions():
    from porenet.kernels.sorting import MAX_BUCKET, stable_argsort

    v = np.concatenate([np.linspace(1.0, 1.0 + 1e-9, 10 * MAX_BUCKET), [1e6]])  # one big bucket
    v = np.random.default_rng(0).permutation(v)
    np.testing.assert_array_equal(stable_argsort(v), np.argsort(v, kind="stable"))


@settings(max_examples=80, deadline=None)
@given(
    st.lists(
        st.one_of(
            st.floats(-10.0, 10.0),
            st.sampled_from([0.0, -0.0, 1.0, 2.0, 1e-300, -1e300, np.inf, -np.inf, np.nan]),
        ),
        min_size=0,
        max_size=3000,
    )
)
def test_rank_order_equals_numpy_stable(values):
    from porenet.kernels.sorting import rank_order

    v = np.asarray(values, dtype=np.float64)
    by_rank = np.empty(len(v), dtype=np.int32)
    rank = np.empty(len(v), dtype=np.int32)
    assert rank_order(v, by_rank, rank, np.empty(len(v), dtype=np.uint64))
    np.testing.assert_array_equal(by_rank, np.argsort(v, kind="stable"))
    np.testing.assert_array_equal(rank[by_rank], np.arange(len(v)))


def test_rank_order_gives_up_on_values_clustered_below_its_resolution():
    from porenet.kernels.sorting import rank_order

    # 20,000 values 1 ulp apart in descending order, in one bucket of both levels (the values
    # 1 + 2**-5 and 2 stretch the ranges): the insertion pass would be quadratic.
    ulp = np.spacing(1.0)
    v = np.concatenate([1.0 + ulp * np.arange(19_998)[::-1], [1.0 + 2.0**-5, 2.0]])
    out = np.empty(len(v), dtype=np.int64)
    assert not rank_order(v, out, np.empty_like(out), np.empty(len(v), dtype=np.uint64))
    by_rank, rank = ip.throat_ranks(v)  # numpy's sort instead
    np.testing.assert_array_equal(by_rank, np.argsort(v, kind="stable"))
    np.testing.assert_array_equal(rank[by_rank], np.arange(len(v)))


@settings(max_examples=60, deadline=None)
@given(st.lists(st.tuples(st.booleans(), st.integers(0, 5000)), min_size=1, max_size=400))
def test_queue_pop_min_is_remove_then_min(ops):
    from porenet.kinds.invasion.kernels.bitqueue import queue_pop_min

    words, offsets = queue_new(5001)
    for insert, key in ops:
        if insert:
            queue_insert(words, offsets, key)
        else:
            queue_remove(words, offsets, key)
    expected = words.copy()
    smallest = queue_min(words, offsets)
    while smallest >= 0:
        queue_remove(expected, offsets, smallest)
        following = queue_pop_min(words, offsets, smallest)
        np.testing.assert_array_equal(words, expected)
        assert following == queue_min(expected, offsets)
        smallest = following


def irregular_graph(n: int, rng: np.random.Generator):
    """A square lattice plus a hub joined to every 3rd pore: degrees too uneven for the padded
    (ELLPACK) layout, so the invasion kernel reads the CSR layout."""
    tp = canonical_throats(n)
    hub = n * n
    spokes = np.stack([np.arange(0, n * n, 3), np.full(len(range(0, n * n, 3)), hub)], axis=1)
    tp = np.concatenate([tp, spokes])
    outlet = np.zeros(n * n + 1, dtype=bool)
    outlet[rng.choice(n * n, size=n, replace=False)] = True
    return tp, ip.entry_pressures(rng.integers(1, 6, size=len(tp)).astype(float)), outlet


@pytest.mark.parametrize("trapping", [False, True])
@pytest.mark.parametrize("stop", [False, True])
def test_irregular_graph_matches_reference(trapping, stop):
    from porenet.kernels.graph import max_degree

    for seed in range(3):
        rng = np.random.default_rng(seed)
        tp, entry, outlet = irregular_graph(9, rng)
        indptr, nbrs, _ = csr_adjacency(tp, len(outlet))
        assert max_degree(indptr) * len(outlet) > 1.25 * len(nbrs)  # the CSR layout is used
        inlets = np.array([40, 7])
        order, via = run_kernel(tp, entry, inlets, outlet, trapping, stop)
        ref, _ = reference_invasion(
            tp, entry, inlets, outlet, trapping=trapping, stop_at_outlet=stop
        )
        assert order.tolist() == ref
        assert via[:2].tolist() == [-1, -1]
        for k in range(2, len(order)):
            assert order[k] in tp[via[k]]


def test_trapped_steps_and_invade_give_the_invasion_with_trapping():
    n = 20
    tp, entry, outlet = square(n, np.random.default_rng(3), ties=True)
    indptr, nbrs, thr = csr_adjacency(tp, n * n)
    inlets = np.array([(n // 2) * n + n // 2])
    by_rank, rank = ip.throat_ranks(entry)
    order, via_rank = ip.invade(indptr, nbrs, rank[thr], inlets, outlet, False, n * n)
    full, full_via = run_kernel(tp, entry, inlets, outlet, False, False)
    assert order.tolist() == full.tolist()
    assert np.where(via_rank >= 0, by_rank[via_rank], -1).tolist() == full_via.tolist()
    trapped = trap.trapped_steps(indptr, nbrs, order, outlet, len(inlets))
    with_trapping, _ = run_kernel(tp, entry, inlets, outlet, True, False)
    assert order[~trapped].tolist() == with_trapping.tolist()
    assert trapped.any()
