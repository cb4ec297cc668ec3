"""The multifrontal Cholesky of the pore matrix on a square grid (:mod:`porenet.kernels.
viscous.grid_cholesky`) against scipy's sparse solver, on the matrix ``K = V/dt + L`` of
random conductances, with drained pores (rows decoupled) and grids whose side is not a
multiple of the leaf size."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp
from scipy.sparse.linalg import spsolve

from porenet.kinds.square.config import SquareLatticeConfig
from porenet.kinds.square.model import SquareLattice
from porenet.kinds.viscous.kernels.grid_cholesky import (
    grid_cholesky_factor,
    grid_cholesky_solve,
    grid_cholesky_symbolic,
    grid_fronts,
)
from porenet.kinds.viscous.kernels.pore_matrix import fill_diagonal


def pore_matrix(n: int, rng: np.random.Generator, drained_share: float):
    """``K = V/dt + L`` of an n x n grid (dense, the slow obvious way) and what the kernels
    read: the adjacency, the conductances (0 across a drained pore) and the diagonal."""
    lat = SquareLattice(SquareLatticeConfig(n=n, disorder=0.3), np.random.default_rng(0))
    indptr, nbr, thr = (np.asarray(a, np.int64) for a in lat.adjacency)
    tp = np.asarray(lat.throat_pores)
    g = rng.uniform(0.2, 2.0, len(tp))
    drained = rng.random(n * n) < drained_share
    g[drained[tp[:, 0]] | drained[tp[:, 1]]] = 0.0
    g_out = np.zeros(n * n)
    g_out[np.asarray(lat.outlet_mask("centre"))] = 0.7
    vol = rng.uniform(0.5, 1.5, n * n)
    dt = 0.3
    dense = np.diag(vol / dt + g_out)
    for t, (a, b) in enumerate(tp):
        dense[a, a] += g[t]
        dense[b, b] += g[t]
        dense[a, b] -= g[t]
        dense[b, a] -= g[t]
    diag = np.empty(n * n)
    fill_diagonal(dt, indptr, thr, vol, g, g_out, diag)
    return dense, indptr, nbr, thr, g, diag


@pytest.mark.parametrize(("n", "drained_share"), [(3, 0.0), (7, 0.2), (12, 0.0), (17, 0.35)])
def test_solve_agrees_with_scipy(n: int, drained_share: float) -> None:
    rng = np.random.default_rng(n)
    dense, indptr, nbr, thr, g, diag = pore_matrix(n, rng, drained_share)
    assert np.allclose(np.diag(dense), diag, rtol=1e-14)
    fronts = grid_cholesky_symbolic(n, indptr, nbr)
    fronts.diagonal[:] = diag
    grid_cholesky_factor(fronts, g, thr)
    for _ in range(3):
        rhs = rng.standard_normal(n * n)
        x = grid_cholesky_solve(fronts, rhs)
        expected = spsolve(sp.csc_matrix(dense), rhs)
        np.testing.assert_allclose(x, expected, rtol=1e-11, atol=1e-12)
        np.testing.assert_allclose(dense @ x, rhs, rtol=1e-11, atol=1e-11)


def test_nested_dissection_eliminates_every_pore_once() -> None:
    """The fronts' separators partition the grid's pores, and every child comes before its
    parent (postorder)."""
    for n in (1, 4, 9, 10, 23):
        nodes = grid_fronts(n)
        eliminated = [p for sep, _, _ in nodes for p in sep]
        assert sorted(eliminated) == list(range(n * n))
        for k, (_, _, children) in enumerate(nodes):
            assert all(c < k for c in children)
