"""The multigrid solver of the frictional solid against a sparse direct solve."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.sparse.linalg import spsolve

from porenet.kinds.mindlin.kernels import multigrid as mg
from porenet.kinds.mindlin.kernels import multigrid_drift as drift


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


def _apply_v_cycle(hierarchy, work, r):
    """``M^-1 r`` of one V-cycle, on the finest level's interior (flat, m*m)."""
    rows, cols = hierarchy.shape[0]
    fine = int(hierarchy.offset[1])
    padded = np.zeros((rows + 2, cols + 2))
    padded[1:-1, 1:-1] = r.reshape(rows, cols)
    work.rhs[:fine] = padded.ravel()
    mg.v_cycle(hierarchy, work)
    return work.solution[:fine].reshape(rows + 2, cols + 2)[1:-1, 1:-1].ravel().copy()


@pytest.mark.parametrize("flip", [False, True], ids=["rows", "columns"])
@pytest.mark.parametrize("crack", [0, 12])
def test_the_v_cycle_is_a_symmetric_positive_preconditioner(flip, crack):
    """The pre-smoothing starts from zero and its residual is taken from what it changed
    (docs/model.md, "Solver"); the post-smoothing runs the other way: the V-cycle stays a
    symmetric positive definite operator, as the conjugate gradient method needs, with either
    direction of lines."""
    m = 41
    op = random_operator(m, 0.3, crack, seed=7)
    if flip:
        op = mg.Operator(op.across_rows.T.copy(), op.across_columns.T.copy(), op.diagonal)
    hierarchy = mg.build(op)
    assert hierarchy.sweeps == (2 if flip else 1)
    work = mg.workspace(hierarchy)
    rng = np.random.default_rng(7)
    r1, r2 = rng.standard_normal(m * m), rng.standard_normal(m * m)
    z1, z2 = _apply_v_cycle(hierarchy, work, r1), _apply_v_cycle(hierarchy, work, r2)
    assert abs(z1 @ r2 - r1 @ z2) <= 1e-12 * abs(z1 @ r2)
    assert z1 @ r1 > 0 and z2 @ r2 > 0
    # linear: the V-cycle of a sum is the sum of the V-cycles (nothing left from a cycle)
    np.testing.assert_allclose(_apply_v_cycle(hierarchy, work, r1 + r2), z1 + z2,
                               rtol=0, atol=1e-12 * np.abs(z1 + z2).max())  # fmt: skip


@pytest.mark.parametrize("flip", [False, True], ids=["rows", "columns"])
def test_the_residual_after_smoothing_from_zero_is_b_minus_a_x(flip):
    """What :func:`row_residual` and :func:`column_residual` give after a forward sweep from
    zero is the plain residual ``b - A x`` of the finest level, from the sparse matrix."""
    from porenet.kinds.mindlin.kernels import multigrid_smoothing as sm

    m = 23
    op = random_operator(m, 0.5, 5, seed=11)
    if flip:
        op = mg.Operator(op.across_rows.T.copy(), op.across_columns.T.copy(), op.diagonal)
    hierarchy = mg.build(op)
    work = mg.workspace(hierarchy)
    b = np.random.default_rng(11).standard_normal(m * m)
    width = m + 2
    padded = np.zeros((m + 2, m + 2))
    padded[1:-1, 1:-1] = b.reshape(m, m)
    work.rhs[: width * width] = padded.ravel()
    work.solution[:] = 7.0  # not cleared by the sweep: every interior point is written
    work.solution[: width * width].reshape(width, width)[[0, -1], :] = 0.0
    work.solution[: width * width].reshape(width, width)[:, [0, -1]] = 0.0
    if flip:
        sm.column_sweep(hierarchy, 0, work.solution, work.rhs, work.residual, False, True)
    else:
        sm.row_sweep(hierarchy, 0, work.solution, work.rhs, work.line, False, True)
    x = work.solution[: width * width].reshape(width, width)[1:-1, 1:-1].ravel()
    plain = b - sparse_matrix(op) @ x
    fused = np.empty(m * m)
    for r in range(m):
        for c in range(m):
            p = (r + 1) * width + c + 1
            if flip:
                res = sm.column_residual(hierarchy.stencil, work.solution, p, c, width, False)
            else:
                res = sm.row_residual(hierarchy.stencil, work.solution, p, width, False)
            fused[r * m + c] = res
    np.testing.assert_allclose(fused, plain, rtol=0, atol=1e-12 * np.abs(b).max())


def test_drifted_edges_count_opened_contacts_not_sliding_ones():
    """The rebuild trigger counts edges whose weight changed by more than the threshold of
    itself (a contact that opened: its weight falls to 1e-6 of the others), but not edges
    that went to or from zero (a contact that started or stopped sliding with rotations held,
    whose tangential stiffness is then zero): with friction those change at nearly every
    update, and rebuilding for them cost more than the V-cycles it saved."""
    built = random_operator(20, 0.5, 0, seed=3)
    op = mg.Operator(built.across_columns.copy(), built.across_rows.copy(), built.diagonal)
    assert drift.drifted_edges(op, built, 0.5) == 0
    op.across_columns[4, 2:9] = 2e-6  # seven contacts opened
    assert drift.drifted_edges(op, built, 0.5) == 7
    op.across_rows[5, 0:12] = 0.0  # twelve started sliding
    assert drift.drifted_edges(op, built, 0.5) == 7
    assert drift.drifted_edges(built, op, 0.5) == 7  # and stopped
    op.across_rows[6, 0:3] *= 1.2  # small changes: below the threshold
    assert drift.drifted_edges(op, built, 0.5) == 7


def test_remember_stuck_keeps_a_sliding_contacts_last_stiffness():
    """The operator the frictional solid builds hierarchies from: every edge at its current
    weight, except an edge that went to zero (a contact sliding with rotations held), which
    keeps the weight it had when it last stuck; one that never stuck stays zero."""
    op = random_operator(20, 0.5, 3, seed=5, foundation=0.1)
    op.across_rows[2, 0:4] = 0.0  # sliding from the start: never stuck
    stuck = mg.Operator(np.zeros_like(op.across_columns), np.zeros_like(op.across_rows),
                        np.zeros_like(op.diagonal))  # fmt: skip
    assert drift.remember_stuck(op, stuck) == 0
    for a, b in zip(stuck, op, strict=True):
        np.testing.assert_array_equal(a, b)
    before = op.across_rows[5, 0:12].copy()
    op.across_rows[5, 0:12] = 0.0  # twelve start sliding
    op.across_columns[4, 2:9] = 2e-6  # seven open: taken as they are
    op.diagonal[:] = 0.2
    assert drift.remember_stuck(op, stuck) == 12
    np.testing.assert_array_equal(stuck.across_rows[5, 0:12], before)
    np.testing.assert_array_equal(stuck.across_columns, op.across_columns)
    np.testing.assert_array_equal(stuck.diagonal, op.diagonal)
    assert np.all(stuck.across_rows[2, 0:4] == 0.0)
    op.across_rows[5, 0:12] = 1.5 * before  # stuck again, at another stiffness
    assert drift.remember_stuck(op, stuck) == 0
    np.testing.assert_array_equal(stuck.across_rows, op.across_rows)


@pytest.mark.parametrize("sliding", [0.1, 0.5])
def test_a_hierarchy_of_the_stuck_operator_solves_the_sliding_one_exactly(sliding):
    """A hierarchy built with every sliding contact stuck, its finest level refreshed to the
    operator with them sliding (zero tangential edges), preconditions the conjugate gradients
    on the current operator: the sparse direct solution, to round-off, whatever fraction of
    the contacts slide."""
    m = 40
    stuck = random_operator(m, 0.5, 6, seed=8)
    rng = np.random.default_rng(8)
    op = mg.Operator(stuck.across_columns.copy(), stuck.across_rows.copy(), stuck.diagonal)
    op.across_rows[rng.random(op.across_rows.shape) < sliding] = 0.0
    hierarchy = mg.build(stuck)
    mg.refresh_finest(hierarchy, op)
    rhs = rng.standard_normal(m * m)
    x = np.zeros(m * m)
    its = mg.solve(op, hierarchy, mg.workspace(hierarchy), rhs, x, 0.0,
                   1e-12 * np.abs(rhs).max(), 400)  # fmt: skip
    exact = spsolve(sparse_matrix(op).tocsc(), rhs)
    assert its > 0
    np.testing.assert_allclose(x, exact, rtol=0, atol=1e-9 * np.abs(exact).max())


@settings(max_examples=40, deadline=None)
@given(size=st.integers(1, 40), seed=st.integers(0, 2**31 - 1), shift=st.floats(1e-6, 10.0))
def test_cholesky_of_the_coarsest_level_equals_lapacks(size, seed, shift):
    # the written-out factor (no LAPACK threads, docs/performance.md) against numpy's, on
    # symmetric positive definite matrices from well to poorly conditioned
    from porenet.kinds.mindlin.kernels.multigrid_levels import cholesky_lower

    rng = np.random.default_rng(seed)
    a = rng.standard_normal((size, size))
    matrix = a @ a.T + shift * np.eye(size)
    low, definite = cholesky_lower(matrix)
    assert definite
    reference = np.linalg.cholesky(matrix)
    np.testing.assert_allclose(low, reference, rtol=1e-8, atol=1e-10 * np.abs(reference).max())
    np.testing.assert_allclose(low @ low.T, matrix, rtol=1e-12, atol=1e-12 * np.abs(matrix).max())


def test_cholesky_reports_a_matrix_that_is_not_positive_definite():
    from porenet.kinds.mindlin.kernels.multigrid_levels import cholesky_lower

    for diagonal in ([1.0, 2.0, -1.0], [1.0, 0.0, 3.0], [np.nan, 1.0, 1.0]):
        assert not cholesky_lower(np.diag(diagonal))[1]
