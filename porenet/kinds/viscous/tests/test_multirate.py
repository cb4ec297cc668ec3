"""Kernels of local time stepping (:mod:`porenet.kinds.viscous.kernels.multirate`,
:mod:`porenet.kinds.viscous.kernels.window`): the ring of a window, the coarse step's shadow sums
(exact volume bookkeeping across the window's edge) and the far-field update (volume conserved to
round-off)."""

from __future__ import annotations

import numpy as np
import pytest

from porenet.kinds.viscous.kernels import multirate as mk
from porenet.kinds.viscous.kernels.chebyshev import stage_count
from porenet.kinds.viscous.kernels.state import Total
from porenet.kinds.viscous.kernels.window import Ring, WindowInt
from porenet.kinds.viscous.local_steps import LocalSteps
from porenet.simulation import Simulation

N = 30


@pytest.fixture(scope="module")
def fluid():
    """A set-up 30 x 30 RKC run, its pressures replaced by a rough random field (the shadow
    sums must be exact for any state, not only smooth ones)."""
    sim = Simulation.from_scene(
        {
            "seed": 3,
            "lattice": {"n": N, "disorder": 0.5, "pore_size": 1e-7},
            "fluid": {"kind": "viscous", "capillary_number": 1e-5, "integrator": "rkc"},
            "classifier": {"kind": "none"},
        }
    )
    sim.fluid.setup(sim.state)
    f = sim.fluid
    f.front.box[:] = (0, N, 0, N)
    f.flow.pressure[:] = np.random.default_rng(0).uniform(-0.5, 1.0, N * N)
    f.flow.pressure[sim.state.drained] = f.flow.totals[Total.INVADING_PRESSURE]
    return f


def _window(fluid, wbox):
    steps = LocalSteps(fluid, 1.0)
    win = steps.win
    win.box[:] = wbox
    box, ring = fluid.front.box, win.ring_index
    win.ints[WindowInt.N_RING] = mk.window_ring(N, win.box, box, ring)
    win.ints[WindowInt.N_OUTLET] = mk.outlet_links(
        N, box, fluid.conductances.outlet, ring, win.ints[WindowInt.N_RING]
    )
    return steps, win


def test_ring_lists_each_throat_across_the_edge_once(fluid):
    """A box inside the active box has 2 (rows + columns) ring throats, each joining a pore of
    the box to its neighbour outside; the outlet links are the edge pores of the grid."""
    _, win = _window(fluid, np.array([5, 17, 8, 23]))
    k = int(win.ints[WindowInt.N_RING])
    assert k == 2 * (12 + 15)
    tp = fluid.network.throat_pores
    for w, r, t in win.ring_index[:, :k].T:
        assert {w, r} == set(tp[t].tolist())
        iw, jw, ir, jr = w // N, w % N, r // N, r % N
        assert 5 <= iw < 17 and 8 <= jw < 23
        assert not (5 <= ir < 17 and 8 <= jr < 23)
    links = win.ring_index[:, k : k + int(win.ints[WindowInt.N_OUTLET])]
    assert np.all(links[1] == -1)
    assert len(links[0]) == np.count_nonzero(fluid.conductances.outlet > 0)
    # a box on the active box's edge has no ring there
    _, edge = _window(fluid, np.array([0, 10, 0, 30]))
    assert int(edge.ints[WindowInt.N_RING]) == 30


def test_coarse_shadow_sums_book_the_window_exactly(fluid):
    """After a coarse step the window's stored-volume change is exactly the volume its sources
    put in, less what its ring throats and its outlet links carried out (the shadow sums),
    to round-off: the bookkeeping refluxing relies on."""
    wbox = np.array([6, 20, 4, 30])  # touches the outlet on one side
    steps, win = _window(fluid, wbox)
    sources = np.array([10 * N + 12, 14 * N + 16], dtype=np.int64)
    rates = np.array([0.7, 0.3])
    h = 40.0
    m = stage_count(h, fluid.spectral_radius)
    p, vol, rkc = fluid.flow.pressure, fluid.network.volume, fluid.rkc
    field = steps.sweep_field(fluid.front.box)
    menisci0, pump0 = fluid.no_menisci()
    p1 = np.zeros_like(p)
    ebox = np.zeros(4, dtype=np.int64)
    step = mk.CoarseStep(h, m, sources, rates, menisci0, pump0, 1e9)
    outflow = mk.coarse_step(field, p, win, step, rkc.stages, rkc.f0, rkc.fnew, rkc.zero, p1,
                             ebox)  # fmt: skip
    inside = np.zeros((N, N), dtype=bool)
    inside[6:20, 4:30] = True
    inside = inside.ravel()
    gained = float(np.sum((vol * (p1 - p))[inside]))
    k, n_out = int(win.ints[WindowInt.N_RING]), int(win.ints[WindowInt.N_OUTLET])
    coarse = win.ring_value[Ring.COARSE]
    ring_out = coarse[:k].sum()
    links = win.ring_index[0, k : k + n_out]
    w_out = coarse[k : k + n_out][inside[links]].sum()
    expected = h * rates.sum() - ring_out - w_out
    scale = float(np.sum(np.abs(vol * (p1 - p))[inside]))
    assert abs(gained - expected) < 1e-13 * scale
    assert w_out > 0 and abs(outflow - coarse[k : k + n_out].sum()) < 1e-12


def test_far_update_conserves_volume(fluid):
    """The far field after a fine integration that reached part of the macro step: its
    stored-volume change plus its outflow is exactly the volume the fine integration booked
    out of the window, whatever that was (refluxing puts the difference back)."""
    wbox = np.array([8, 22, 0, 15])
    steps, win = _window(fluid, wbox)
    sources = np.array([15 * N + 5], dtype=np.int64)
    h = 25.0
    vol, rkc = fluid.network.volume, fluid.rkc
    field = steps.sweep_field(fluid.front.box)
    menisci0, pump0 = fluid.no_menisci()
    p1 = np.zeros_like(fluid.flow.pressure)
    step = mk.CoarseStep(h, stage_count(h, fluid.spectral_radius), sources, np.array([1.0]),
                         menisci0, pump0, 1e9)  # fmt: skip
    mk.coarse_step(field, fluid.flow.pressure, win, step, rkc.stages, rkc.f0, rkc.fnew,
                   rkc.zero, p1, np.zeros(4, dtype=np.int64))  # fmt: skip
    p = fluid.flow.pressure.copy()
    mk.start_fine(win, p, p1, field, 0.0, h)
    k = int(win.ints[WindowInt.N_RING])
    booked = np.random.default_rng(1).uniform(0.0, 0.02, k)  # what a fine run carried out
    win.ring_value[Ring.FLUX, :k] = booked
    before = p.copy()
    stored, outflow, _ = mk.far_update(field, p, p1, vol, fluid.flow.drained, win, 0.6)
    change = float(np.sum(vol * (p - before)))
    assert abs(change - stored) < 1e-12
    assert abs(stored + outflow - booked.sum()) < 1e-12
    # inside the window only the refluxed volumes arrive, near its edge (rows 8 and 21,
    # column 14 are on it)
    rows, cols = np.divmod(np.flatnonzero(p != before), N)
    inside = (rows >= 8) & (rows < 22) & (cols < 15)
    edge = np.minimum(np.minimum(rows - 8, 21 - rows), 14 - cols)[inside]
    assert inside.any() and edge.max() <= mk.DEPOSIT_REACH
