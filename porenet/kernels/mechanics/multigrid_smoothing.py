"""The smoother of the frictional solid's multigrid (:mod:`porenet.kernels.mechanics.
multigrid`): line Gauss-Seidel along rows, zebra line relaxation along columns, each line
solved exactly by the Thomas algorithm from factors computed once per hierarchy, and the
choice of the lines to relax (docs/model.md, "Frictional solid (kind hertz-mindlin)",
"Solver").

Arrays follow :class:`porenet.kernels.mechanics.multigrid.Hierarchy`: level ``l``'s points
(with a ring of boundary points, always 0) at ``offset[l]:offset[l+1]``, its stencil one row
per slot ``k = 3 (dy + 1) + (dx + 1)``.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from porenet.kernels.jit import njit
from porenet.kernels.mechanics.multigrid_levels import NE, NW, SE, SW, C, E, N, S, W


def smoothing_lines(operator: Any) -> int:
    """The lines the smoother relaxes: those of the more strongly coupled direction (1: rows,
    when the summed weights across columns are the larger; 2: columns). Relaxing whole lines
    along the strong direction smooths well for any anisotropy along them, the isotropic
    case included, at about half the cost of alternating directions for a few more
    iterations (``tests/benchmarks/bench_multigrid.py``; docs/model.md, "Solver")."""
    across_columns = float(operator.across_columns.sum())
    across_rows = float(operator.across_rows.sum())
    return 1 if across_columns >= across_rows else 2


@njit
def line_factors(
    stencil: np.ndarray, shape: np.ndarray, offset: np.ndarray, lvl: int,
    row_factor: np.ndarray, column_factor: np.ndarray, sweeps: int,
) -> None:  # fmt: skip
    """The Thomas algorithm's factors of every row's (``sweeps & 1``) and column's
    (``sweeps & 2``) tridiagonal part."""
    rows, cols = shape[lvl, 0], shape[lvl, 1]
    base, width = offset[lvl], cols + 2
    for r in range(rows if sweeps & 1 else 0):
        previous = 0.0  # eliminated upper coefficient of the previous point
        for c in range(cols):
            p = base + (r + 1) * width + c + 1
            lower = stencil[W, p] if c > 0 else 0.0
            upper = stencil[E, p] if c < cols - 1 else 0.0
            inverse = 1.0 / (stencil[C, p] - lower * previous)
            previous = upper * inverse
            row_factor[0, p] = previous
            row_factor[1, p] = inverse
    for c in range(cols if sweeps & 2 else 0):
        previous = 0.0
        for r in range(rows):
            p = base + (r + 1) * width + c + 1
            lower = stencil[S, p] if r > 0 else 0.0
            upper = stencil[N, p] if r < rows - 1 else 0.0
            inverse = 1.0 / (stencil[C, p] - lower * previous)
            previous = upper * inverse
            column_factor[0, p] = previous
            column_factor[1, p] = inverse


@njit(helper=True)
def off_row(a: np.ndarray, x: np.ndarray, p: int, width: int, corners: bool) -> float:
    """``sum a_k x_k`` over the neighbours of ``p`` off its row (``a`` the stencil, per slot;
    the corners only if ``corners``)."""
    below, above = p - width, p + width
    total = a[S, p] * x[below] + a[N, p] * x[above]
    if corners:
        total += (a[SW, p] * x[below - 1] + a[SE, p] * x[below + 1]
                  + a[NW, p] * x[above - 1] + a[NE, p] * x[above + 1])  # fmt: skip
    return total


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
    backward: bool,
) -> None:  # fmt: skip
    """One Gauss-Seidel sweep over level ``lvl``'s rows, each solved exactly."""
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
            rhs = b[p] - off_row(a, x, p, width, corners)
            previous = (rhs - a[W, p] * previous) * factor[1, p]
            line[c] = previous
        value = 0.0
        for c in range(cols - 1, -1, -1):
            value = line[c] - factor[0, start + c] * value
            x[start + c] = value


@njit
def column_sweep(
    hierarchy: Any, lvl: int, x: np.ndarray, b: np.ndarray, scratch: np.ndarray,
    backward: bool,
) -> None:  # fmt: skip
    """One zebra sweep over level ``lvl``'s columns, each solved exactly: the even columns,
    then the odd ones (the other way round when ``backward``). The columns of one colour are
    eliminated together, row by row, so that memory is read in rows; ``scratch`` (per point)
    holds the forward elimination."""
    a, factor = hierarchy.stencil, hierarchy.column_factor
    rows, cols = hierarchy.shape[lvl, 0], hierarchy.shape[lvl, 1]
    base, width = hierarchy.offset[lvl], cols + 2
    corners = lvl > 0
    for half in range(2):
        colour = 1 - half if backward else half
        first = base + width + 1 + colour
        for r in range(rows):
            start = first + r * width
            for p in range(start, start - colour + cols, 2):
                rhs = b[p] - off_column(a, x, p, width, corners) - a[S, p] * scratch[p - width]
                scratch[p] = rhs * factor[1, p]
        for step in range(rows):
            start = first + (rows - 1 - step) * width
            for p in range(start, start - colour + cols, 2):
                x[p] = scratch[p] - factor[0, p] * x[p + width]
