"""Dense Cholesky columns, written out: the multifrontal factor of the pore matrix eliminates
each front's separator with it, the multigrid factors its coarsest level with it.

Written out rather than LAPACK's: the matrices are small (fronts of a few hundred pores, a
coarsest level of at most 225 points), and LAPACK's threads, which wait for a core when
another program uses one, made a 144-row factor take 29 ms instead of ~0.1 ms on a busy
machine (docs/performance.md, "Frictional solid").
"""

from __future__ import annotations

import numpy as np

from porenet.jit.jit import njit


@njit(helper=True)
def cholesky_columns(f: np.ndarray, columns: int) -> bool:
    """Factor the first ``columns`` columns of the symmetric matrix whose lower triangle is in
    ``f`` (square, ``m x m``), in place: afterwards ``f[:, :columns]`` holds those columns of
    ``L`` (``L L^T`` = the matrix, restricted to them); the rest of ``f`` is not touched (a
    front's Schur complement is formed by its caller). Reads only the lower triangle.

    Returns whether every pivot was positive; a pivot that is not (zero, negative or NaN)
    is taken as NaN, which fills its column and those after it, and the factorisation
    carries on (the caller decides what to report)."""
    m = f.shape[0]
    definite = True
    for j in range(columns):
        d = f[j, j]
        for t in range(j):
            d -= f[j, t] * f[j, t]
        if d > 0.0:
            d = np.sqrt(d)
        else:
            definite = False
            d = np.nan
        f[j, j] = d
        for i in range(j + 1, m):
            v = f[i, j]
            for t in range(j):
                v -= f[i, t] * f[j, t]
            f[i, j] = v / d
    return definite
