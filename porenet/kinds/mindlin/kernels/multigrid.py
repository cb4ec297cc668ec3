"""Multigrid for the scalar fields of a square particle grid (docs/model.md, "Frictional
solid (kind hertz-mindlin)", "Solver").

With particle rotations held (the ``hertz-mindlin`` solid's default), the force balance of a
square lattice whose contacts carry normal and tangential stiffness splits into two scalar
problems, one per displacement component: ``u_x`` is joined along x by the normal stiffness of
the x-springs and along y by the tangential stiffness of the y-springs, and ``u_y`` the other
way round. Each is a weighted graph Laplacian on the ``m x m`` grid of free particles (the
fixed ring is a Dirichlet boundary), a symmetric positive definite five-point operator whose
weights jump by up to ``1e6`` (open contacts keep only the cohesive stiffness) and whose
anisotropy can reach ``1e3`` (``K_t / K_n = 1e-3``).

This module solves such systems by the conjugate gradient method preconditioned by one
V-cycle of a geometric multigrid that is robust to both:

* **operator-dependent interpolation** (Dendy's "black box multigrid", J. Comput. Phys. 48,
  366 (1982)): a fine point between two coarse points takes their values weighted by the
  operator's couplings, collapsed across the line, so a crack (a weak coupling) is not
  interpolated across;
* **Galerkin coarse operators** ``A_c = P^T A P`` (nine-point stencils on every coarse level);
* **line Gauss-Seidel** smoothing along the strongly coupled direction (every row, or every
  column in two colours, solved exactly by the Thomas algorithm), robust to anisotropy
  along the lines; the post-smoothing runs in the reverse order so that the V-cycle is a
  symmetric preconditioner;
* the coarsest level (at most ~15 x 15) solved by a dense Cholesky factor.

Every array is flat over the levels (:class:`Hierarchy`): level ``l``'s points are
``offset[l]:offset[l+1]`` in row-major order, its grid ``shape[l]``. Stencil slot
``k = 3 (dy + 1) + (dx + 1)`` holds the coupling of a point to its neighbour at row offset
``dy`` and column offset ``dx`` (slot 4 the diagonal); neighbours outside the grid are the
Dirichlet boundary (value 0). Coarse points are the fine points of odd row and odd column
(0-based), so any grid size coarsens.

The hierarchy is built from one operator and may precondition a later one (the same grid,
weights that changed since): the conjugate gradient iteration then uses the current operator
(:class:`Operator`) and stays exact, only its count of iterations grows. :func:`refresh_finest`
brings the finest level's smoother up to date at the cost of one pass over the grid (local
changes, a contact that opens or starts sliding, are then seen where they are), and the
caller rebuilds the whole hierarchy when many edges changed or the iterations grow
(``porenet/kinds/mindlin/grid_solver.py``, with the comparisons of
:mod:`porenet.kinds.mindlin.kernels.multigrid_drift`). The frictional solid builds it from the
operator with every sliding contact stuck and refreshes the finest level to the current one.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from porenet.jit.jit import njit
from porenet.kinds.mindlin.kernels.multigrid_levels import (
    C,
    E,
    N,
    S,
    W,
    cholesky_lower,
    compact_interpolation,
    dense_matrix,
    fine_stencil,
    galerkin,
    interpolation,
)
from porenet.kinds.mindlin.kernels.multigrid_smoothing import (
    column_residual,
    column_sweep,
    line_factors,
    off_row,
    row_residual,
    row_sweep,
    smoothing_lines,
)

#: Largest coarsest grid (points per side) solved by the dense factor.
COARSEST = 15


class Operator(NamedTuple):
    """A five-point operator on an ``m x m`` grid from its edge weights (stiffnesses).

    Attributes
    ----------
    across_columns : ndarray of float64, shape (m, m + 1)
        ``across_columns[r, c]`` joins ``(r, c - 1)`` and ``(r, c)``; column ``-1`` and
        ``m`` are the fixed boundary.
    across_rows : ndarray of float64, shape (m + 1, m)
        ``across_rows[r, c]`` joins ``(r - 1, c)`` and ``(r, c)``.
    diagonal : ndarray of float64, shape (m, m)
        Added to each point's diagonal (a foundation).

    The operator is ``(A u)_p = sum_q w_pq (u_p - u_q) + diagonal_p u_p`` over the
    neighbours ``q`` of ``p``, with ``u = 0`` on the boundary.
    """

    across_columns: np.ndarray
    across_rows: np.ndarray
    diagonal: np.ndarray


class Hierarchy(NamedTuple):
    """The levels of the multigrid (module docstring), flat over the levels.

    Each level's grid is stored with a ring of boundary points around it (always 0), so that
    level ``l``'s point ``(r, c)`` (0-based, interior) is at
    ``offset[l] + (r + 1) * (cols + 2) + (c + 1)``.

    Attributes
    ----------
    shape : ndarray of int64, shape (L, 2)
        Rows and columns of each level's grid (without the ring).
    offset : ndarray of int64, shape (L + 1,)
        Level ``l`` is ``offset[l]:offset[l + 1]`` of the per-point arrays.
    stencil : ndarray of float64, shape (9, offset[L])
        Each level's nine-point operator (0 on the ring), one array per slot.
    row_factor, column_factor : ndarray of float64, shape (2, offset[L])
        The Thomas algorithm's factors of each row's (column's) tridiagonal part: the
        eliminated upper coefficient and the inverse pivot.
    interpolation_weight : ndarray of float64, shape (4, offset[L])
        For the point ``(r, c)`` of level ``l < L - 1``, the weights of the level-``l+1``
        points at ring-padded ``(r // 2 + a, c // 2 + b)``, slot ``2 a + b`` (each point lies
        in the cell of those four; weight 0 where one is not a parent).
    coarsest_factor : ndarray of float64, shape (nc, nc)
        Lower Cholesky factor of the coarsest level's matrix (interior points, row-major).
    sweeps : int
        The smoother's lines: 1 rows, 2 columns (:func:`smoothing_lines`), 3 both.
    """

    shape: np.ndarray
    offset: np.ndarray
    stencil: np.ndarray
    row_factor: np.ndarray
    column_factor: np.ndarray
    interpolation_weight: np.ndarray
    coarsest_factor: np.ndarray
    sweeps: int


class Workspace(NamedTuple):
    """Scratch arrays of a V-cycle and of the conjugate gradient iteration.

    Attributes
    ----------
    solution, rhs, residual : ndarray of float64, shape (offset[L],)
        Per level (with its ring, kept 0): the correction, its right-hand side, its residual.
    line : ndarray of float64, shape (largest side + 2,)
        Forward elimination's scratch.
    conjugate : ndarray of float64, shape (3, offset[1])
        The conjugate gradient's iterate, search direction and ``A p`` on the finest level
        (ring-padded; its residual and ``M^-1 r`` are level 0 of ``rhs`` and ``solution``).
    """

    solution: np.ndarray
    rhs: np.ndarray
    residual: np.ndarray
    line: np.ndarray
    conjugate: np.ndarray


def level_shapes(m: int) -> list[tuple[int, int]]:
    """Grid sides of the levels of an ``m x m`` grid (coarsened until at most
    :data:`COARSEST` points per side)."""
    shapes = [(m, m)]
    while max(shapes[-1]) > COARSEST and min(shapes[-1]) >= 3:
        r, c = shapes[-1]
        shapes.append((r // 2, c // 2))
    return shapes


def build(operator: Operator) -> Hierarchy:
    """The multigrid hierarchy of ``operator`` (module docstring)."""
    m = operator.diagonal.shape[0]
    shapes = level_shapes(m)
    sizes = [(r + 2) * (c + 2) for r, c in shapes]
    offset = np.zeros(len(shapes) + 1, dtype=np.int64)
    offset[1:] = np.cumsum(sizes)
    total = int(offset[-1])
    shape = np.asarray(shapes, dtype=np.int64).reshape(-1, 2)
    stencil = np.zeros((9, total))
    frm = np.zeros((total, 4), dtype=np.int64)  # the interpolation as built: parents, weights
    weight = np.zeros((total, 4))
    fine_stencil(operator, stencil)
    for lvl in range(len(shapes) - 1):
        interpolation(stencil, shape, offset, lvl, frm, weight)
        galerkin(stencil, shape, offset, lvl, frm, weight)
    row_factor, column_factor = np.zeros((2, total)), np.zeros((2, total))
    for lvl in range(len(shapes)):
        line_factors(stencil, shape, offset, lvl, row_factor, column_factor, 3)
    last = len(shapes) - 1
    coarse = dense_matrix(stencil[:, int(offset[last]) :], *shapes[last])
    factor, definite = cholesky_lower(coarse)
    if not definite:
        raise np.linalg.LinAlgError("the coarsest level's matrix is not positive definite")
    compact = np.zeros((4, total))
    for lvl in range(len(shapes) - 1):
        compact_interpolation(shape, offset, lvl, frm, weight, compact)
    return Hierarchy(shape, offset, stencil, row_factor, column_factor, compact, factor,
                     smoothing_lines(operator))  # fmt: skip


def workspace(hierarchy: Hierarchy) -> Workspace:
    """Scratch arrays for :func:`solve` with ``hierarchy``."""
    total = int(hierarchy.offset[-1])
    side = int(hierarchy.shape.max()) + 2
    return Workspace(np.zeros(total), np.zeros(total), np.zeros(total), np.zeros(side),
                     np.zeros((3, int(hierarchy.offset[1]))))  # fmt: skip


@njit
def _restrict_residual(hierarchy: Hierarchy, lvl: int, work: Workspace) -> None:
    """Level ``lvl + 1``'s right-hand side: ``P^T (b - A x)`` of level ``lvl``, after its
    pre-smoothing (:func:`v_cycle`): with one direction of lines relaxed from zero, the
    residual is what that sweep left (:func:`row_residual`, :func:`column_residual`: a third
    of the stencil to read, none on the odd columns); after both directions, ``b - A x``."""
    stencil, weight = hierarchy.stencil, hierarchy.interpolation_weight
    rows, cols = hierarchy.shape[lvl, 0], hierarchy.shape[lvl, 1]
    base, width = hierarchy.offset[lvl], cols + 2
    x, b = work.solution, work.rhs
    corners = lvl > 0
    lines = hierarchy.sweeps
    cbase, cend = hierarchy.offset[lvl + 1], hierarchy.offset[lvl + 2]
    cwidth = hierarchy.shape[lvl + 1, 1] + 2
    for p in range(cbase, cend):
        b[p] = 0.0
    for r in range(rows):
        start = base + (r + 1) * width + 1
        parents = cbase + (r // 2) * cwidth
        odd = r % 2 == 1
        for c in range(0, cols, 2 if lines == 2 else 1):
            p = start + c
            if lines == 1:
                res = row_residual(stencil, x, p, width, corners)
            elif lines == 2:
                res = column_residual(stencil, x, p, c, width, corners)
            else:
                res = (b[p] - stencil[C, p] * x[p] - stencil[W, p] * x[p - 1]
                       - stencil[E, p] * x[p + 1]
                       - off_row(stencil, x, p, width, corners))  # fmt: skip
            q = parents + c // 2
            if not odd:  # an odd row's only parents are above it (Hierarchy)
                b[q] += weight[0, p] * res
                b[q + 1] += weight[1, p] * res
            b[q + cwidth] += weight[2, p] * res
            b[q + cwidth + 1] += weight[3, p] * res
    _zero_ring(b, cbase, hierarchy.shape[lvl + 1, 0], hierarchy.shape[lvl + 1, 1])


@njit(helper=True)
def _zero_ring(values: np.ndarray, base: int, rows: int, cols: int) -> None:
    """Set the boundary ring of a level to 0 (weights 0 only ever add 0 there, but a
    non-finite residual would not)."""
    width = cols + 2
    last = base + (rows + 1) * width
    for c in range(width):
        values[base + c] = 0.0
        values[last + c] = 0.0
    for r in range(1, rows + 1):
        values[base + r * width] = 0.0
        values[base + r * width + cols + 1] = 0.0


@njit
def _interpolate_correction(hierarchy: Hierarchy, lvl: int, x: np.ndarray) -> None:
    """``x += P x_c`` on level ``lvl``."""
    weight = hierarchy.interpolation_weight
    rows, cols = hierarchy.shape[lvl, 0], hierarchy.shape[lvl, 1]
    base, width = hierarchy.offset[lvl], cols + 2
    cbase, cwidth = hierarchy.offset[lvl + 1], hierarchy.shape[lvl + 1, 1] + 2
    for r in range(rows):
        start = base + (r + 1) * width + 1
        parents = cbase + (r // 2) * cwidth
        if r % 2 == 1:  # an odd row's only parents are above it: half the weights to read
            for c in range(cols):
                p = start + c
                q = parents + c // 2 + cwidth
                x[p] += weight[2, p] * x[q] + weight[3, p] * x[q + 1]
            continue
        for c in range(cols):
            p = start + c
            q = parents + c // 2
            x[p] += (weight[0, p] * x[q] + weight[1, p] * x[q + 1]
                     + weight[2, p] * x[q + cwidth] + weight[3, p] * x[q + cwidth + 1])  # fmt: skip


@njit
def _coarsest_solve(hierarchy: Hierarchy, lvl: int, work: Workspace) -> None:
    """The coarsest level exactly, by its dense Cholesky factor."""
    factor = hierarchy.coarsest_factor
    rows, cols = hierarchy.shape[lvl, 0], hierarchy.shape[lvl, 1]
    base, width = hierarchy.offset[lvl], cols + 2
    size = rows * cols
    y = work.residual[base : base + size]  # scratch
    for i in range(size):
        s = work.rhs[base + (i // cols + 1) * width + i % cols + 1]
        for j in range(i):
            s -= factor[i, j] * y[j]
        y[i] = s / factor[i, i]
    for i in range(size - 1, -1, -1):
        s = y[i]
        for j in range(i + 1, size):
            s -= factor[j, i] * y[j]
        y[i] = s / factor[i, i]
    for i in range(size):
        work.solution[base + (i // cols + 1) * width + i % cols + 1] = y[i]
    for i in range(size):
        y[i] = 0.0


@njit
def v_cycle(hierarchy: Hierarchy, work: Workspace) -> None:
    """One symmetric V-cycle: level 0 of ``work.solution`` becomes ``M^-1`` applied to
    level 0 of ``work.rhs`` (module docstring)."""
    x, b, line = work.solution, work.rhs, work.line
    levels = hierarchy.shape.shape[0]
    lines = hierarchy.sweeps
    for lvl in range(levels - 1):
        # pre-smoothing from x = 0: one direction's sweep knows it and writes every point
        if lines == 3:
            x[hierarchy.offset[lvl] : hierarchy.offset[lvl + 1]] = 0.0
        if lines & 1:
            row_sweep(hierarchy, lvl, x, b, line, False, lines == 1)
        if lines & 2:
            column_sweep(hierarchy, lvl, x, b, work.residual, False, lines == 2)
        _restrict_residual(hierarchy, lvl, work)
    _coarsest_solve(hierarchy, levels - 1, work)
    for lvl in range(levels - 2, -1, -1):
        _interpolate_correction(hierarchy, lvl, x)
        if lines & 2:
            column_sweep(hierarchy, lvl, x, b, work.residual, True, False)
        if lines & 1:
            row_sweep(hierarchy, lvl, x, b, line, True, False)


def refresh_finest(hierarchy: Hierarchy, operator: Operator) -> None:
    """Make the finest level (its stencil and line factors: the smoother) the current
    ``operator``'s, in place, keeping the interpolation and the coarse levels built from an
    earlier one (module docstring)."""
    fine_stencil(operator, hierarchy.stencil)
    line_factors(hierarchy.stencil, hierarchy.shape, hierarchy.offset, 0, hierarchy.row_factor,
                 hierarchy.column_factor, hierarchy.sweeps)  # fmt: skip


@njit
def _apply_finest(hierarchy: Hierarchy, x: np.ndarray, out: np.ndarray) -> float:
    """``out = A x`` on the finest level (ring-padded vectors) with its five-point stencil,
    which :func:`build` and :func:`refresh_finest` keep equal to the current operator;
    returns ``x . A x`` (read in the same pass)."""
    a = hierarchy.stencil
    rows, cols = hierarchy.shape[0, 0], hierarchy.shape[0, 1]
    width = cols + 2
    product = 0.0
    for r in range(rows):
        start = (r + 1) * width + 1
        for p in range(start, start + cols):
            out[p] = (a[C, p] * x[p] + a[W, p] * x[p - 1] + a[E, p] * x[p + 1]
                      + a[S, p] * x[p - width] + a[N, p] * x[p + width])  # fmt: skip
            product += x[p] * out[p]
    return product


@njit
def _largest_deformation(hierarchy: Hierarchy, x: np.ndarray, y: np.ndarray) -> tuple:
    """Largest change of an edge's length that a displacement increment ``x`` (ring-padded,
    finest level, 0 on the ring) makes, ``max |x_p - x_q|`` over joined neighbours, the
    fixed ring included; and ``x . y`` (read in the same pass)."""
    rows, cols = hierarchy.shape[0, 0], hierarchy.shape[0, 1]
    width = cols + 2
    largest, product = 0.0, 0.0
    for r in range(rows + 1):
        start = (r + 1) * width
        for p in range(start, start + cols + 1):
            largest = max(largest, abs(x[p] - x[p - 1]), abs(x[p] - x[p - width]))
            product += x[p] * y[p]
    return largest, product


@njit
def solve(
    operator: Operator,
    hierarchy: Hierarchy,
    work: Workspace,
    rhs: np.ndarray,
    x: np.ndarray,
    deformation_tolerance: float,
    force_tolerance: float,
    max_iterations: int,
) -> int:
    """Solve ``A x = rhs`` by the preconditioned conjugate gradient method, from the ``x``
    given (flat, m*m, updated in place). ``hierarchy``'s finest level must be ``operator``
    (:func:`build`, :func:`refresh_finest`).

    Stops when the correction one more V-cycle would make deforms no edge by more than
    ``deformation_tolerance`` (the V-cycle's output estimates the remaining error; that last
    correction is applied), or when no residual force exceeds ``force_tolerance``
    (round-off), or after ``max_iterations``.

    Returns
    -------
    int
        Iterations done (V-cycles applied); ``-1`` if it stopped at ``max_iterations``
        without meeting either criterion, ``-2`` if a non-finite value appeared.
    """
    rows, cols = hierarchy.shape[0, 0], hierarchy.shape[0, 1]
    width, fine = cols + 2, hierarchy.offset[1]
    # ring-padded vectors of the finest level: the residual lives in the V-cycle's
    # right-hand side and the preconditioned residual in its solution, so nothing is copied
    r, z = work.rhs[:fine], work.solution[:fine]
    xp, pdir, q = work.conjugate[0], work.conjugate[1], work.conjugate[2]
    xp[:] = 0.0
    for i in range(rows):
        for j in range(cols):
            xp[(i + 1) * width + j + 1] = x[i * cols + j]
    _apply_finest(hierarchy, xp, q)
    r[:] = 0.0
    largest = 0.0
    for i in range(rows):
        for j in range(cols):
            p = (i + 1) * width + j + 1
            r[p] = rhs[i * cols + j] - q[p]
            largest = max(largest, abs(r[p]))
    status = 0
    if largest > force_tolerance:
        status = -1
        rz = 0.0
        pdir[:] = 0.0
        for it in range(1, max_iterations + 1):
            v_cycle(hierarchy, work)  # z = M^-1 r
            deformation, rz_new = _largest_deformation(hierarchy, z, r)
            if deformation <= deformation_tolerance:
                for p in range(fine):
                    xp[p] += z[p]
                status = it
                break
            beta = rz_new / rz if it > 1 else 0.0
            for p in range(fine):
                pdir[p] = z[p] + beta * pdir[p]
            rz = rz_new
            pq = _apply_finest(hierarchy, pdir, q)
            if not math.isfinite(pq):
                status = -2
                break
            if pq <= 0.0:
                status = it
                break
            alpha = rz / pq
            largest = 0.0
            for p in range(fine):
                xp[p] += alpha * pdir[p]
                r[p] -= alpha * q[p]
                largest = max(largest, abs(r[p]))
            if largest <= force_tolerance:
                status = it
                break
    for i in range(rows):
        for j in range(cols):
            x[i * cols + j] = xp[(i + 1) * width + j + 1]
    return status
