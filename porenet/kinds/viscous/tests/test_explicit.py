"""Drainage events of the viscous model (:func:`porenet.kinds.viscous.kernels.explicit.drain_pore`)
against their definitions: after any sequence of events the frontier is exactly the throats
between a drained and an undrained pore, the active pores are the undrained neighbours of
drained ones, the box holds them, and the totals and records book each event."""

from __future__ import annotations

import numpy as np
import pytest

from porenet.kinds.square.config import SquareLatticeConfig
from porenet.kinds.square.model import SquareLattice
from porenet.kinds.viscous.kernels.explicit import drain_pore
from porenet.kinds.viscous.kernels.state import (
    Column,
    Conductances,
    Count,
    Network,
    Total,
    new_flow,
    new_front,
    new_records,
)


@pytest.mark.parametrize("seed", range(4))
def test_fronts_and_books_after_random_events(seed: int) -> None:
    n = 8
    lat = SquareLattice(SquareLatticeConfig(n=n, disorder=0.3), np.random.default_rng(seed))
    indptr, nbr, thr = (np.asarray(a, np.int64) for a in lat.adjacency)
    tp = np.asarray(lat.throat_pores, np.int64)
    rng = np.random.default_rng(seed)
    vol = rng.uniform(0.5, 1.5, n * n)
    m = len(tp)
    net = Network(indptr, nbr, thr, tp, vol, 1.0 / vol, np.zeros(n * n, bool), n)
    cond = Conductances(np.ones(m), np.ones(m), np.ones(m), np.ones(m), np.full(n * n, 0.3))
    flow = new_flow(n * n, m, 2.0, 1.7)
    flow.pressure[:] = rng.uniform(0.0, 1.0, n * n)
    front, records = new_front(n * n, m, n), new_records(n * n)
    pressures = flow.pressure.copy()
    order = list(rng.permutation(n * n)[:20])
    for k, pore in enumerate(order):
        drain_pore(int(pore), k - 1, net, cond, flow, front, records, 2.0)
    drained = flow.drained
    assert drained.sum() == 20 and flow.counters[Count.EVENTS] == 20
    n_front = flow.counters[Count.N_FRONT]
    frontier = set(front.throats[:n_front].tolist())
    expected = {t for t, (a, b) in enumerate(tp) if drained[a] != drained[b]}
    assert frontier == expected
    assert all(front.throat_slot[t] == s for s, t in enumerate(front.throats[:n_front]))
    active = set(front.pores[: flow.counters[Count.N_ACTIVE]].tolist())
    neighbours = {int(b) for a, b in tp if drained[a] and not drained[b]}
    neighbours |= {int(a) for a, b in tp if drained[b] and not drained[a]}
    assert active == neighbours
    rows, cols = np.divmod(np.flatnonzero(drained), n)
    box = front.box
    assert box[0] <= max(rows.min() - 1, 0) and box[1] >= min(rows.max() + 2, n)
    assert box[2] <= max(cols.min() - 1, 0) and box[3] >= min(cols.max() + 2, n)
    # drained pores stop conducting, release their storage at the invading pressure
    touching = drained[tp[:, 0]] | drained[tp[:, 1]]
    assert np.all(cond.between[touching] == 0) and np.all(cond.outlet[drained] == 0)
    assert flow.totals[Total.RELEASED] == pytest.approx(float(vol[order] @ pressures[order]))
    assert flow.totals[Total.DRAINED_PORE_VOLUME] == pytest.approx(float(vol[order].sum()))
    assert np.all(flow.pressure[drained] == 1.7)
    assert records.order[:20].tolist() == [int(p) for p in order]
    assert records.via[:20].tolist() == list(range(-1, 19))
    assert records.series[:20, Column.N_DRAINED].tolist() == list(range(1, 21))
