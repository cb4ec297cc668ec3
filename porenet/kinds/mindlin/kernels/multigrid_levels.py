"""The levels of the frictional solid's multigrid: the finest level's stencil, Dendy's
operator-dependent interpolation and the Galerkin coarse operators
(:mod:`porenet.kinds.mindlin.kernels.multigrid`, which builds a hierarchy from them and runs it).

Each level's grid is stored with a ring of boundary points (always 0) and its stencil one
array per slot ``k = 3 (dy + 1) + (dx + 1)`` (:class:`porenet.kinds.mindlin.kernels.multigrid.
Hierarchy`).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from porenet.jit.jit import njit
from porenet.kernels.dense import cholesky_columns

#: Stencil slots (``3 (dy + 1) + (dx + 1)``; dy is the row offset, "south" is dy = -1).
SW, S, SE, W, C, E, NW, N, NE = range(9)


@njit
def fine_stencil(operator: Any, out: np.ndarray) -> None:
    """Level 0's stencil (corners 0) from a five-point operator (:class:`porenet.kernels.
    mechanics.multigrid.Operator`)."""
    wc, wr, d = operator.across_columns, operator.across_rows, operator.diagonal
    m = d.shape[0]
    width = m + 2
    for r in range(m):
        for c in range(m):
            p = (r + 1) * width + c + 1
            west, east = wc[r, c], wc[r, c + 1]
            south, north = wr[r, c], wr[r + 1, c]
            out[W, p] = -west
            out[E, p] = -east
            out[S, p] = -south
            out[N, p] = -north
            out[C, p] = west + east + south + north + d[r, c]


@njit
def cholesky_lower(matrix: np.ndarray) -> tuple[np.ndarray, bool]:
    """Lower Cholesky factor ``L`` of a symmetric matrix (``L L^T = matrix``) and whether the
    matrix was positive definite (``False``: ``L`` has NaN from the first bad pivot on); the
    coarsest level's factor, written out rather than LAPACK's
    (:mod:`porenet.kernels.dense` says why)."""
    low = np.tril(matrix)
    definite = cholesky_columns(low, matrix.shape[0])
    return low, definite


def dense_matrix(stencil: np.ndarray, rows: int, cols: int) -> np.ndarray:
    """The matrix of a (ringed) level's stencil on its interior points (small grids only)."""
    size, width = rows * cols, cols + 2
    out = np.zeros((size, size))
    for r in range(rows):
        for c in range(cols):
            p = (r + 1) * width + c + 1
            for k in range(9):
                rr, cc = r + k // 3 - 1, c + k % 3 - 1
                if 0 <= rr < rows and 0 <= cc < cols:
                    out[r * cols + c, rr * cols + cc] += stencil[k, p]
    return 0.5 * (out + out.T)


@njit(helper=True)
def _collapsed_weight(coupling: float, centre: float, base: float) -> float:
    """``-coupling / centre``, with the full diagonal ``base`` where the collapsed centre is
    not positive (a coarse level's stencil need not stay diagonally dominant)."""
    if centre <= 1e-12 * base:
        centre = base
    return -coupling / centre


@njit
def interpolation(
    stencil: np.ndarray, shape: np.ndarray, offset: np.ndarray, lvl: int, frm: np.ndarray,
    weight: np.ndarray,
) -> None:  # fmt: skip
    """Dendy's operator-dependent interpolation from level ``lvl + 1`` (the points of odd
    row and column) to every point of level ``lvl`` (module docstring)."""
    rows, cols = shape[lvl, 0], shape[lvl, 1]
    crows, ccols = shape[lvl + 1, 0], shape[lvl + 1, 1]
    base, cbase = offset[lvl], offset[lvl + 1]
    width, cwidth = cols + 2, ccols + 2
    for p in range(base, offset[lvl + 1]):
        for k in range(4):
            frm[p, k] = cbase  # the coarse ring's corner: always 0
            weight[p, k] = 0.0
    for r in range(rows):
        for c in range(cols):
            p = base + (r + 1) * width + c + 1
            a = stencil[:, p]
            if r % 2 == 1 and c % 2 == 1:  # a coarse point
                frm[p, 0] = cbase + (r // 2 + 1) * cwidth + c // 2 + 1
                weight[p, 0] = 1.0
            elif r % 2 == 1:  # between two coarse points of its row
                row = cbase + (r // 2 + 1) * cwidth
                centre = a[S] + a[C] + a[N]
                left, right = c // 2 - 1, c // 2
                if left >= 0:
                    frm[p, 0] = row + left + 1
                    weight[p, 0] = _collapsed_weight(a[SW] + a[W] + a[NW], centre, a[C])
                if right < ccols:
                    frm[p, 1] = row + right + 1
                    weight[p, 1] = _collapsed_weight(a[SE] + a[E] + a[NE], centre, a[C])
            elif c % 2 == 1:  # between two coarse points of its column
                centre = a[W] + a[C] + a[E]
                below, above = r // 2 - 1, r // 2
                if below >= 0:
                    frm[p, 0] = cbase + (below + 1) * cwidth + c // 2 + 1
                    weight[p, 0] = _collapsed_weight(a[SW] + a[S] + a[SE], centre, a[C])
                if above < crows:
                    frm[p, 1] = cbase + (above + 1) * cwidth + c // 2 + 1
                    weight[p, 1] = _collapsed_weight(a[NW] + a[N] + a[NE], centre, a[C])
    # points of even row and column: from their eight neighbours, as interpolated above
    acc = np.zeros(4)
    for r in range(0, rows, 2):
        for c in range(0, cols, 2):
            p = base + (r + 1) * width + c + 1
            a = stencil[:, p]
            acc[:] = 0.0
            for k in range(9):
                if k == C or a[k] == 0.0:
                    continue
                q = p + (k // 3 - 1) * width + (k % 3 - 1)
                for j in range(4):
                    if weight[q, j] == 0.0:
                        continue
                    cr = (frm[q, j] - cbase) // cwidth - 1
                    cc = (frm[q, j] - cbase) % cwidth - 1
                    corner = (0 if 2 * cr + 1 < r else 2) + (0 if 2 * cc + 1 < c else 1)
                    acc[corner] += -a[k] * weight[q, j] / a[C]
            for corner in range(4):
                cr = r // 2 - 1 + corner // 2
                cc = c // 2 - 1 + corner % 2
                if 0 <= cr < crows and 0 <= cc < ccols and acc[corner] != 0.0:
                    frm[p, corner] = cbase + (cr + 1) * cwidth + cc + 1
                    weight[p, corner] = acc[corner]


@njit
def compact_interpolation(
    shape: np.ndarray, offset: np.ndarray, lvl: int, frm: np.ndarray, weight: np.ndarray,
    out: np.ndarray,
) -> None:  # fmt: skip
    """Level ``lvl``'s interpolation (parents ``frm``, ``weight``, as :func:`interpolation`
    writes them) in the compact layout of the V-cycle: ``out[2 a + b, p]`` is the weight of
    the parent at ring-padded ``(r // 2 + a, c // 2 + b)`` of the point ``p = (r, c)``."""
    rows, cols = shape[lvl, 0], shape[lvl, 1]
    base, cbase = offset[lvl], offset[lvl + 1]
    width, cwidth = cols + 2, shape[lvl + 1, 1] + 2
    for r in range(rows):
        for c in range(cols):
            p = base + (r + 1) * width + c + 1
            for k in range(4):
                out[k, p] = 0.0
            for j in range(4):
                if weight[p, j] == 0.0:
                    continue
                a = (frm[p, j] - cbase) // cwidth - r // 2
                b = (frm[p, j] - cbase) % cwidth - c // 2
                out[2 * a + b, p] = weight[p, j]


@njit
def galerkin(
    stencil: np.ndarray, shape: np.ndarray, offset: np.ndarray, lvl: int, frm: np.ndarray,
    weight: np.ndarray,
) -> None:  # fmt: skip
    """Level ``lvl + 1``'s operator, ``P^T A P`` of level ``lvl``'s, as nine-point stencils."""
    rows, cols = shape[lvl, 0], shape[lvl, 1]
    base, cbase = offset[lvl], offset[lvl + 1]
    width, cwidth = cols + 2, shape[lvl + 1, 1] + 2
    stencil[:, cbase : offset[lvl + 2]] = 0.0
    for r in range(rows):
        for c in range(cols):
            p = base + (r + 1) * width + c + 1
            for k in range(9):
                a = stencil[k, p]
                if a == 0.0:
                    continue
                q = p + (k // 3 - 1) * width + (k % 3 - 1)
                for i in range(4):
                    wi = weight[p, i] * a
                    if wi == 0.0:
                        continue
                    big_i = frm[p, i]
                    for j in range(4):
                        wj = weight[q, j]
                        if wj == 0.0:
                            continue
                        d = frm[q, j] - big_i
                        dy = (d + cwidth + 1) // cwidth - 1  # d = dy * cwidth + dx, |dx| <= 1
                        dx = d - dy * cwidth
                        stencil[3 * (dy + 1) + (dx + 1), big_i] += wi * wj
