"""The pressure diffusion over the active pores (:mod:`porenet.kinds.viscous.kernels.diffusion`)
against slow, obvious references: a forward Euler step written pore by pore over a dense
neighbour list, the throat refresh written from its formulas."""

from __future__ import annotations

import numpy as np
import pytest

from porenet.kinds.square.config import SquareLatticeConfig
from porenet.kinds.square.model import SquareLattice
from porenet.kinds.viscous.kernels.diffusion import (
    DENSE_ACTIVE,
    csr_copy,
    csr_fluxes,
    csr_update,
    grid_flux,
    grid_sweep,
    grow_where_reached,
    refresh_throats,
    spread,
)
from porenet.kinds.viscous.kernels.state import Conductances, Count, Network, Sweep


def grid(n: int, seed: int):
    lat = SquareLattice(SquareLatticeConfig(n=n, disorder=0.3), np.random.default_rng(seed))
    indptr, nbr, thr = (np.asarray(a, np.int64) for a in lat.adjacency)
    rng = np.random.default_rng(seed + 1)
    g = rng.uniform(0.2, 2.0, len(lat.throat_pores))
    g_out = np.where(np.asarray(lat.outlet_mask("centre")), 0.5, 0.0)
    vol = rng.uniform(0.5, 1.5, n * n)
    return lat, indptr, nbr, thr, g, g_out, vol


def reference_step(n, box, bounds, dt, tp, g, g_out, vol, p):
    """Forward Euler over the pores of ``box``: each pore's flux from its neighbours inside
    ``bounds`` and from the outlet, pore by pore (the obvious way)."""
    inside = lambda k, b: b[0] <= k // n < b[1] and b[2] <= k % n < b[3]  # noqa: E731
    flux = -g_out * p
    for t, (a, c) in enumerate(tp):
        if inside(a, bounds) and inside(c, bounds):
            flux[a] += g[t] * (p[c] - p[a])
            flux[c] += g[t] * (p[a] - p[c])
    new = p.copy()
    stored = out = 0.0
    for k in range(n * n):
        if inside(k, box):
            new[k] = p[k] + dt * flux[k] / vol[k]
            stored += vol[k] * (new[k] - p[k])
            out += g_out[k] * p[k]
    return new, stored, out


@pytest.mark.parametrize(
    ("box", "bounds"),
    [((0, 9, 0, 9), (0, 9, 0, 9)), ((2, 7, 1, 8), (2, 7, 1, 8)), ((3, 6, 3, 6), (1, 8, 2, 9)),
     ((0, 9, 4, 5), (0, 9, 4, 5))],
)  # fmt: skip
def test_grid_sweep_is_forward_euler_over_the_box(box, bounds) -> None:
    n = 9
    lat, indptr, nbr, thr, g, g_out, vol = grid(n, 4)
    p = np.random.default_rng(0).standard_normal(n * n)
    b, nb = np.array(box, np.int64), np.array(bounds, np.int64)
    idx = np.zeros(1, np.int64)
    field = Sweep(n, b, 0, idx, idx, indptr, nbr, thr, g, g_out, 1.0 / vol, np.zeros(n * n), nb)
    p_next = p.copy()
    stored, out = grid_sweep(field, 0.07, vol, p, p_next)
    expected, stored_ref, out_ref = reference_step(n, box, bounds, 0.07,
                                                   np.asarray(lat.throat_pores), g, g_out, vol,
                                                   p)  # fmt: skip
    np.testing.assert_allclose(p_next, expected, rtol=1e-13, atol=1e-14)
    assert stored == pytest.approx(stored_ref, rel=1e-12, abs=1e-13)
    assert out == pytest.approx(out_ref, rel=1e-12, abs=1e-13)


def test_the_listed_sweep_equals_the_grid_sweep() -> None:
    """Every pore active: the list kernels (any lattice) give the grid stencil's fluxes and
    step to round-off."""
    n = 8
    _, indptr, nbr, thr, g, g_out, vol = grid(n, 7)
    p = np.random.default_rng(2).standard_normal(n * n)
    act = np.arange(n * n, dtype=np.int64)
    box = np.array([0, n, 0, n], np.int64)
    listed = Sweep(0, box, n * n, act, act.copy(), indptr, nbr, thr, g, g_out, 1.0 / vol,
                   np.zeros(n * n), box)  # fmt: skip
    flux = np.zeros(n * n)
    csr_fluxes(listed, p, flux)
    for k in range(n * n):
        assert flux[k] == pytest.approx(grid_flux(n, box, k, p, g, g_out), rel=1e-13, abs=1e-14)
    p_next = np.zeros(n * n)
    stored, out, largest = csr_update(listed._replace(scratch=flux), 0.05, p, p_next, vol)
    grid_next = p.copy()
    field = listed._replace(grid_n=n)
    stored_g, out_g = grid_sweep(field, 0.05, vol, p, grid_next)
    np.testing.assert_allclose(p_next, grid_next, rtol=1e-12, atol=1e-13)
    assert stored == pytest.approx(stored_g, rel=1e-11) and out == pytest.approx(out_g)
    assert largest == pytest.approx(np.max(np.abs(flux / vol)))


@pytest.mark.parametrize("share", [0.1, 0.6, 1.0])
def test_the_listed_sweep_over_some_active_pores_in_any_order(share) -> None:
    """Active pores listed in a random order, fewer or more than DENSE_ACTIVE of them (the
    list or the index-order sweep): each pore's flux and new pressure are the reference's,
    to the bit on the list whichever the order; inactive pores are left alone; the sums
    agree to round-off; the copy writes the active pores only."""
    n = 12
    lat, indptr, nbr, thr, g, g_out, vol = grid(n, 3)
    rng = np.random.default_rng(5)
    p = rng.standard_normal(n * n)
    act = rng.permutation(n * n)[: int(share * n * n)].astype(np.int64)
    apos = np.full(n * n, -1, np.int64)
    apos[act] = np.arange(len(act))
    pores = np.zeros(n * n, np.int64)
    pores[: len(act)] = act
    box = np.array([0, n, 0, n], np.int64)
    field = Sweep(0, box, len(act), pores, apos, indptr, nbr, thr, g, g_out, 1.0 / vol,
                  np.full(n * n, np.nan), box)  # fmt: skip
    assert (len(act) >= DENSE_ACTIVE * n * n) == (share > DENSE_ACTIVE)
    flux = field.scratch
    csr_fluxes(field, p, flux)
    on = apos >= 0
    ref = -g_out * p
    for t, (a, c) in enumerate(np.asarray(lat.throat_pores)):
        if on[a] and on[c]:
            ref[a] += g[t] * (p[c] - p[a])
            ref[c] += g[t] * (p[a] - p[c])
    np.testing.assert_allclose(flux[on], ref[on], rtol=1e-13, atol=1e-14)
    assert np.all(np.isnan(flux[~on]))
    p_next = np.full(n * n, np.nan)
    stored, out, largest = csr_update(field, 0.05, p, p_next, vol)
    np.testing.assert_array_equal(p_next[on], p[on] + 0.05 * (flux[on] / vol[on]))
    assert np.all(np.isnan(p_next[~on]))
    assert stored == pytest.approx(np.sum(vol[on] * (p_next[on] - p[on])), rel=1e-12)
    assert out == pytest.approx(np.sum(g_out[on] * p[on]), rel=1e-12, abs=1e-15)
    assert largest == np.max(np.abs(flux[on] / vol[on]))
    copied = np.zeros(n * n)
    csr_copy(field, p_next, copied)
    np.testing.assert_array_equal(copied[on], p_next[on])
    assert np.all(copied[~on] == 0.0)


def test_spread_activates_as_before_and_settles_pores() -> None:
    """The pressure's spread on a list: every undrained neighbour of an active pore above
    the floor is activated, in the order of the active list, and a pore whose neighbours are
    then all active or drained is settled and not visited again."""
    n = 6
    _, indptr, nbr, thr, g, g_out, vol = grid(n, 1)
    apos = np.full(n * n, -1, np.int64)
    pores = np.zeros(n * n, np.int64)
    counters = np.zeros(len(Count), np.int64)
    for k in (14, 15):
        apos[k] = counters[Count.N_ACTIVE]
        pores[counters[Count.N_ACTIVE]] = k
        counters[Count.N_ACTIVE] += 1
    drained = np.zeros(n * n, bool)
    drained[8] = True  # above pore 14
    p = np.zeros(n * n)
    p[14] = 1.0  # only 14 is above the floor
    box = np.zeros(4, np.int64)
    settled = np.zeros(n * n, bool)
    field = Sweep(0, box, int(counters[Count.N_ACTIVE]), pores, apos, indptr, nbr, thr, g,
                  g_out, 1.0 / vol, np.zeros(n * n), box)  # fmt: skip
    spread(field, settled, counters, drained, p, 1e-9)
    # 14's neighbours: 8 (drained), 13, 15 (active), 20, in the CSR order
    expected = [14, 15] + [j for j in nbr[indptr[14] : indptr[15]] if j not in (8, 15)]
    assert list(pores[: counters[Count.N_ACTIVE]]) == expected
    assert settled[14] and not settled[15]
    before = counters.copy()
    p[14] = 2.0
    spread(field._replace(n_active=int(counters[Count.N_ACTIVE])), settled, counters, drained,
           p, 1e-9)  # fmt: skip
    assert np.array_equal(counters, before)  # nothing left for 14 to activate


def test_refresh_throats_follows_the_formulas() -> None:
    """Area c_A r^2, A k = c_A c_k r^4, conductance A k / l between undrained pores (0 next to
    a drained one), entry pressure 2 / r; the stability limit of the pores of throats that
    conduct more, inf for throats that narrowed."""
    n = 6
    lat, indptr, nbr, thr, _, g_out, vol = grid(n, 3)
    tp = np.asarray(lat.throat_pores, np.int64)
    m = len(tp)
    r = np.random.default_rng(5).uniform(0.7, 1.3, m)
    drained = np.zeros(n * n, bool)
    drained[14] = True
    net = Network(indptr, nbr, thr, tp, vol, 1.0 / vol, np.zeros(n * n, bool), n)
    cond = Conductances(np.zeros(m), np.zeros(m), np.zeros(m), np.zeros(m), g_out.copy())
    every = np.arange(m, dtype=np.int64)
    limit = refresh_throats(every, r, (1.5, 0.25, 2.0), net, cond, drained)
    np.testing.assert_allclose(cond.area, 1.5 * r**2)
    np.testing.assert_allclose(cond.meniscus, 1.5 * 0.25 * r**4)
    touching = drained[tp[:, 0]] | drained[tp[:, 1]]
    np.testing.assert_allclose(cond.between, np.where(touching, 0.0, 1.5 * 0.25 * r**4 / 2.0))
    np.testing.assert_allclose(cond.entry_pressure, 2.0 / r)
    degree = g_out.copy()
    np.add.at(degree, tp[:, 0], cond.between)
    np.add.at(degree, tp[:, 1], cond.between)
    assert limit == pytest.approx(np.min(vol[~drained] / degree[~drained]), rel=1e-12)
    narrower = refresh_throats(every, 0.5 * r, (1.5, 0.25, 2.0), net, cond, drained)
    assert narrower == np.inf


def test_the_box_grows_where_its_edge_is_reached() -> None:
    n = 10
    box = np.array([3, 6, 3, 6], np.int64)
    p = np.zeros(n * n)
    p[3 * n + 4] = 1.0  # on the top edge
    assert grow_where_reached(box, n, p, 0.1, 2)
    assert box.tolist() == [1, 6, 3, 6]
    assert not grow_where_reached(box, n, np.zeros(n * n), 0.1, 2)
