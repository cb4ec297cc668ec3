"""The multigrid solver of the frictional solid against a sparse direct solve."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.sparse.linalg import spsolve

from porenet.kernels.mechanics import multigrid as mg


def random_operator(m: int, ratio: float, crack: int, seed: int, foundation: float = 0.0):
    """Weights ~2 across columns and ~2 ratio across rows, a cross of near-zero weights
    (open contacts, 1e-6 of the others) of half-length ``crack`` at the centre."""
    rng = np.random.default_rng(seed)
    wc = 2.0 * (1 + 0.5 * rng.random((m, m + 1)))
    wr = ratio * 2.0 * (1 + 0.5 * rng.random((m + 1, m)))
    if crack:
        c0 = m // 2
        lo, hi = max(c0 - crack, 0), min(c0 + crack, m)
        wc[c0, lo:hi] = 2e-6
        wr[lo:hi, c0] = 2e-6 * ratio
    return mg.Operator(wc, wr, np.full((m, m), foundation))


def sparse_matrix(op: mg.Operator) -> sp.csr_matrix:
    """The operator as a matrix, from its definition (a slow, obvious reference)."""
    m = op.diagonal.shape[0]
    rows, cols, vals = [], [], []
    for r in range(m):
        for c in range(m):
            p = r * m + c
            diag = op.diagonal[r, c]
            for w, rr, cc in ((op.across_columns[r, c], r, c - 1),
                              (op.across_columns[r, c + 1], r, c + 1),
                              (op.across_rows[r, c], r - 1, c),
                              (op.across_rows[r + 1, c], r + 1, c)):  # fmt: skip
                diag += w
                if 0 <= rr < m and 0 <= cc < m:
                    rows.append(p)
                    cols.append(rr * m + cc)
                    vals.append(-w)
            rows.append(p)
            cols.append(p)
            vals.append(diag)
    return sp.csr_matrix((vals, (rows, cols)), shape=(m * m, m * m))


def solve_both(op: mg.Operator, rhs: np.ndarray, tolerance: float = 0.0):
    hierarchy = mg.build(op)
    x = np.zeros_like(rhs)
    its = mg.solve(op, hierarchy, mg.workspace(hierarchy), rhs, x, tolerance,
                   1e-13 * np.abs(rhs).max(), 300)  # fmt: skip
    return x, spsolve(sparse_matrix(op).tocsc(), rhs), its


@settings(max_examples=25, deadline=None)
@given(
    m=st.integers(3, 40),
    ratio=st.sampled_from([1e-3, 0.1, 0.5, 1.0, 2.0]),
    crack=st.integers(0, 15),
    seed=st.integers(0, 2**16),
    foundation=st.sampled_from([0.0, 0.02]),
)
def test_multigrid_solves_to_round_off(m, ratio, crack, seed, foundation):
    op = random_operator(m, ratio, crack, seed, foundation)
    rhs = np.random.default_rng(seed).standard_normal(m * m)
    x, reference, its = solve_both(op, rhs)
    assert its > 0
    scale = np.abs(reference).max()
    np.testing.assert_allclose(x, reference, rtol=0, atol=1e-9 * scale)
    residual = sparse_matrix(op) @ x - rhs
    assert np.abs(residual).max() <= 1e-12 * np.abs(rhs).max() * 10


@pytest.mark.parametrize("ratio, crack", [(1.0, 0), (1e-3, 0), (0.3, 30), (1.0, 30)])
def test_iterations_stay_few_on_hard_operators(ratio, crack):
    """Open contacts (1e-6 weights) and a 1e3 anisotropy: the iteration count does not blow
    up (robust interpolation and line smoothing), here on 127 x 127."""
    m = 127
    op = random_operator(m, ratio, crack, seed=3)
    rhs = np.zeros(m * m)
    rhs[np.random.default_rng(3).integers(0, m * m, 40)] = 1.0
    x, reference, its = solve_both(op, rhs)
    assert 0 < its <= 15, its
    np.testing.assert_allclose(x, reference, rtol=0, atol=1e-9 * np.abs(reference).max())


@pytest.mark.parametrize("tolerance", [1e-2, 1e-4, 1e-6])
def test_the_deformation_tolerance_bounds_the_error(tolerance):
    """Stopping once the next correction would deform no edge by more than the tolerance
    leaves an error whose edge differences are below the tolerance (the V-cycle's output is
    a good estimate of the error)."""
    m = 63
    op = random_operator(m, 0.3, 10, seed=5)
    rhs = np.zeros(m * m)
    rhs[np.random.default_rng(5).integers(0, m * m, 10)] = 1.0
    x, reference, its = solve_both(op, rhs, tolerance)
    error = (x - reference).reshape(m, m)
    largest = max(np.abs(np.diff(error, axis=0)).max(), np.abs(np.diff(error, axis=1)).max())
    assert largest <= tolerance
    _, _, exact_its = solve_both(op, rhs, 0.0)
    assert its < exact_its


def test_levels_coarsen_any_size():
    assert mg.level_shapes(399) == [(399, 399), (199, 199), (99, 99), (49, 49), (24, 24),
                                    (12, 12)]  # fmt: skip
    assert mg.level_shapes(7) == [(7, 7)]
