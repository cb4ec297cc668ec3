"""The smoother of the frictional solid's multigrid (:mod:`porenet.kinds.hertz.kernels.
multigrid`): line Gauss-Seidel along rows, zebra line relaxation along columns, each line
solved exactly by the Thomas algorithm from factors computed once per hierarchy, and the
choice of the lines to relax (docs/model.md, "Frictional solid (kind hertz-mindlin)",
"Solver").

Arrays follow :class:`porenet.kinds.mindlin.kernels.multigrid.Hierarchy`: level ``l``'s points
(with a ring of boundary points, always 0) at ``offset[l]:offset[l+1]``, its stencil one row
per slot ``k = 3 (dy + 1) + (dx + 1)``.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from porenet.jit.jit import njit
from porenet.kinds.mindlin.kernels.multigrid_levels import NE, NW, SE, SW, C, E, N, S, W

#: Rows whose Thomas factors :func:`line_factors` computes side by side.
LINE_BLOCK = 8


def smoothing_lines(operator: Any) -> int:
    """The lines the smoother relaxes: those of the more strongly coupled direction (1: rows,
    when the summed weights across columns are the larger; 2: columns). Relaxing whole lines
    along the strong direction smooths well for any anisotropy along them, the isotropic
    case included, at about half the cost of alternating directions for a few more
    iterations (``tests/benchmarks/bench_multigrid.py``; docs/model.md, "Solver")."""
    across_columns = float(operator.across_columns.sum())
    across_rows = float(operator.across_rows.sum())
    return 1 if across_columns >= across_rows else 2


@njit(helper=True)
def _eliminate(
    diagonal: float, lower: float, upper: float, previous: float, factor: np.ndarray, p: int,
) -> float:  # fmt: skip
    """One step of the Thomas algorithm's factorisation at point ``p`` of a line: stores the
    eliminated upper coefficient and the inverse pivot in ``factor[:, p]`` and returns the
    former (the next point's ``previous``)."""
    inverse = 1.0 / (diagonal - lower * previous)
    factor[0, p] = upper * inverse
    factor[1, p] = inverse
    return factor[0, p]


@njit
def line_factors(
    stencil: np.ndarray, shape: np.ndarray, offset: np.ndarray, lvl: int,
    row_factor: np.ndarray, column_factor: np.ndarray, sweeps: int,
) -> None:  # fmt: skip
    """The Thomas algorithm's factors of every row's (``sweeps & 1``) and column's
    (``sweeps & 2``) tridiagonal part.

    Each line's factors are a recurrence whose every step waits for a division, so the lines
    are eliminated side by side (all rows column by column, all columns row by row), the
    step of one line overlapping those of the others; the arithmetic of each line is as if it
    were eliminated alone."""
    rows, cols = shape[lvl, 0], shape[lvl, 1]
    base, width = offset[lvl], cols + 2
    if sweeps & 1:
        previous = np.zeros(LINE_BLOCK)  # each row's eliminated upper coefficient so far
        for first in range(0, rows, LINE_BLOCK):  # a block of rows at a time: cache lines
            block = min(LINE_BLOCK, rows - first)  # are read once, not once per row
            previous[:] = 0.0
            for c in range(cols):
                for k in range(block):
                    p = base + (first + k + 1) * width + c + 1
                    lower = stencil[W, p] if c > 0 else 0.0
                    upper = stencil[E, p] if c < cols - 1 else 0.0
                    previous[k] = _eliminate(stencil[C, p], lower, upper, previous[k],
                                             row_factor, p)  # fmt: skip
    if sweeps & 2:
        previous = np.zeros(cols)
        for r in range(rows):
            for c in range(cols):
                p = base + (r + 1) * width + c + 1
                lower = stencil[S, p] if r > 0 else 0.0
                upper = stencil[N, p] if r < rows - 1 else 0.0
                previous[c] = _eliminate(stencil[C, p], lower, upper, previous[c],
                                         column_factor, p)  # fmt: skip


@njit(helper=True)
def off_row_below(a: np.ndarray, x: np.ndarray, p: int, width: int, corners: bool) -> float:
    """``sum a_k x_k`` over the neighbours of ``p`` in the row below it (``a`` the stencil,
    per slot; the corners only if ``corners``)."""
    below = p - width
    total = a[S, p] * x[below]
    if corners:
        total += a[SW, p] * x[below - 1] + a[SE, p] * x[below + 1]
    return total


@njit(helper=True)
def off_row_above(a: np.ndarray, x: np.ndarray, p: int, width: int, corners: bool) -> float:
    """``sum a_k x_k`` over the neighbours of ``p`` in the row above it."""
    above = p + width
    total = a[N, p] * x[above]
    if corners:
        total += a[NW, p] * x[above - 1] + a[NE, p] * x[above + 1]
    return total


@njit(helper=True)
def off_row(a: np.ndarray, x: np.ndarray, p: int, width: int, corners: bool) -> float:
    """``sum a_k x_k`` over the neighbours of ``p`` off its row."""
    return off_row_below(a, x, p, width, corners) + off_row_above(a, x, p, width, corners)


@njit(helper=True)
def off_column(a: np.ndarray, x: np.ndarray, p: int, width: int, corners: bool) -> float:
    """``sum a_k x_k`` over the neighbours of ``p`` off its column."""
    total = a[W, p] * x[p - 1] + a[E, p] * x[p + 1]
    if corners:
        below, above = p - width, p + width
        total += (a[SW, p] * x[below - 1] + a[SE, p] * x[below + 1]
                  + a[NW, p] * x[above - 1] + a[NE, p] * x[above + 1])  # fmt: skip
    return total


@njit
def row_sweep(
    hierarchy: Any, lvl: int, x: np.ndarray, b: np.ndarray, line: np.ndarray,
    backward: bool, from_zero: bool,
) -> None:  # fmt: skip
    """One Gauss-Seidel sweep over level ``lvl``'s rows, each solved exactly.

    ``from_zero`` (a forward sweep only): ``x`` is zero on entry, so the rows above a row are
    not read (they are not even cleared first: every point is written). The residual left is
    then :func:`off_row_above` of the result, negated (:func:`row_residual`)."""
    a, factor = hierarchy.stencil, hierarchy.row_factor
    rows, cols = hierarchy.shape[lvl, 0], hierarchy.shape[lvl, 1]
    base, width = hierarchy.offset[lvl], cols + 2
    corners = lvl > 0
    for step in range(rows):
        r = rows - 1 - step if backward else step
        start = base + (r + 1) * width + 1
        previous = 0.0
        for c in range(cols):
            p = start + c
            rhs = b[p] - off_row_below(a, x, p, width, corners)
            if not from_zero:
                rhs -= off_row_above(a, x, p, width, corners)
            previous = (rhs - a[W, p] * previous) * factor[1, p]
            line[c] = previous
        value = 0.0
        for c in range(cols - 1, -1, -1):
            value = line[c] - factor[0, start + c] * value
            x[start + c] = value


@njit
def column_sweep(
    hierarchy: Any, lvl: int, x: np.ndarray, b: np.ndarray, scratch: np.ndarray,
    backward: bool, from_zero: bool,
) -> None:  # fmt: skip
    """One zebra sweep over level ``lvl``'s columns, each solved exactly: the even columns,
    then the odd ones (the other way round when ``backward``). The columns of one colour are
    eliminated together, row by row, so that memory is read in rows; ``scratch`` (per point)
    holds the forward elimination.

    ``from_zero`` (a forward sweep only): ``x`` is zero on entry, so the even columns, relaxed
    first, do not read their neighbours (nor is ``x`` cleared first: every point is
    written). The residual left is then :func:`off_column` of the result, negated, on the
    even columns and zero on the odd ones (:func:`column_residual`)."""
    a, factor = hierarchy.stencil, hierarchy.column_factor
    rows, cols = hierarchy.shape[lvl, 0], hierarchy.shape[lvl, 1]
    base, width = hierarchy.offset[lvl], cols + 2
    corners = lvl > 0
    for half in range(2):
        colour = 1 - half if backward else half
        first = base + width + 1 + colour
        for r in range(rows):
            start = first + r * width
            isolated = from_zero and colour == 0
            for p in range(start, start - colour + cols, 2):
                rhs = b[p] - a[S, p] * scratch[p - width]
                if not isolated:
                    rhs -= off_column(a, x, p, width, corners)
                scratch[p] = rhs * factor[1, p]
        for step in range(rows):
            start = first + (rows - 1 - step) * width
            for p in range(start, start - colour + cols, 2):
                x[p] = scratch[p] - factor[0, p] * x[p + width]


@njit(helper=True)
def row_residual(a: np.ndarray, x: np.ndarray, p: int, width: int, corners: bool) -> float:
    """The residual ``b - A x`` at ``p`` after a forward :func:`row_sweep` from zero: each row
    was solved exactly with the rows above it at zero, so only their terms are left."""
    return -off_row_above(a, x, p, width, corners)


@njit(helper=True)
def column_residual(
    a: np.ndarray, x: np.ndarray, p: int, column: int, width: int, corners: bool,
) -> float:  # fmt: skip
    """The residual at ``p`` (in ``column``, 0-based) after a forward :func:`column_sweep`
    from zero: the odd columns were solved last, exactly (0); the even ones saw the odd ones
    at zero."""
    if column % 2 == 1:
        return 0.0
    return -off_column(a, x, p, width, corners)
