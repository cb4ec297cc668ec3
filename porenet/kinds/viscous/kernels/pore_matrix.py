"""The pore matrix of the implicit integrator: ``K = V / dt + L`` over every pore (docs/model.md
section 4), its fixed sparsity pattern, and the rates and errors of a backward Euler step.

Pure functions on arrays, in scaled units (:mod:`porenet.kinds.viscous.kernels.state`). The stepper
that uses them is :mod:`porenet.kinds.viscous.implicit_steps`; the Cholesky factorisation for
canonical square grids is :mod:`porenet.kinds.viscous.kernels.grid_cholesky`.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import scipy.sparse as sp

from porenet.jit.jit import njit
from porenet.kinds.viscous.kernels.state import Conductances, Network


@njit
def _pattern_positions(
    indptr: np.ndarray, nbr: np.ndarray, cptr: np.ndarray, cind: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Positions in the (symmetric, sorted) matrix pattern of each diagonal and each CSR entry."""
    n = len(indptr) - 1
    diag = np.empty(n, dtype=np.int64)
    off = np.empty(len(nbr), dtype=np.int64)
    for i in range(n):
        for k in range(cptr[i], cptr[i + 1]):
            if cind[k] == i:
                diag[i] = k
        for e in range(indptr[i], indptr[i + 1]):
            j = nbr[e]
            for k in range(cptr[i], cptr[i + 1]):
                if cind[k] == j:
                    off[e] = k
    return diag, off


@njit(helper=True)
def _diagonal(
    i: int,
    dt: float,
    indptr: np.ndarray,
    thr: np.ndarray,
    vol: np.ndarray,
    g_eff: np.ndarray,
    g_out: np.ndarray,
) -> float:
    """Diagonal entry of pore ``i`` in ``K = V/dt + L``: ``V_i/dt + g_out,i + sum_j g_ij``."""
    total = vol[i] / dt + g_out[i]
    for e in range(indptr[i], indptr[i + 1]):
        total += g_eff[thr[e]]
    return total


@njit
def fill_matrix(
    dt: float,
    indptr: np.ndarray,
    thr: np.ndarray,
    vol: np.ndarray,
    g_eff: np.ndarray,
    g_out: np.ndarray,
    diag: np.ndarray,
    off: np.ndarray,
    data: np.ndarray,
) -> None:
    """Values of ``K = V/dt + L`` on the fixed pattern (drained pores: ``V/dt`` alone)."""
    for i in range(len(indptr) - 1):
        for e in range(indptr[i], indptr[i + 1]):
            data[off[e]] = -g_eff[thr[e]]
        data[diag[i]] = _diagonal(i, dt, indptr, thr, vol, g_eff, g_out)


@njit
def start_rates(
    net: Network,
    cond: Conductances,
    drained: np.ndarray,
    p: np.ndarray,
    fpore: np.ndarray,
    qstart: np.ndarray,
    rate: np.ndarray,
) -> float:
    """``dp_i/dt`` at the start of the step for every pore (0 for drained ones), with the
    meniscus fluxes ``qstart`` into the frontier pores ``fpore``; returns ``max |dp_i/dt|``."""
    indptr, nbr, thr, vol = net.indptr, net.neighbour, net.throat, net.volume
    g_eff, g_out = cond.between, cond.outlet
    n = len(indptr) - 1
    for i in range(n):
        if drained[i]:
            rate[i] = 0.0
            continue
        pi = p[i]
        total = -g_out[i] * pi
        for e in range(indptr[i], indptr[i + 1]):
            total += g_eff[thr[e]] * (p[nbr[e]] - pi)
        rate[i] = total
    for s in range(len(fpore)):
        rate[fpore[s]] += qstart[s]
    largest = 0.0
    for i in range(n):
        if not drained[i]:
            rate[i] /= vol[i]
            largest = max(largest, abs(rate[i]))
    return largest


@njit
def error_and_storage(
    dt: float,
    drained: np.ndarray,
    vol: np.ndarray,
    g_out: np.ndarray,
    p: np.ndarray,
    pnew: np.ndarray,
    rate: np.ndarray,
) -> tuple[float, float, float, float]:
    """Over undrained pores: ``max |p' - p - dt f|``, the stored volume change
    ``sum V (p' - p)``, the outflow rate ``sum g_out p'`` and ``max |p' - p| / dt``."""
    err = 0.0
    stored = 0.0
    out = 0.0
    largest = 0.0
    for i in range(len(p)):
        if drained[i]:
            continue
        change = pnew[i] - p[i]
        err = max(err, abs(change - dt * rate[i]))
        stored += vol[i] * change
        out += g_out[i] * pnew[i]
        largest = max(largest, abs(change))
    return err, stored, out, largest / dt


def pore_matrix_pattern(indptr: np.ndarray, nbr: np.ndarray) -> dict[str, Any]:
    """The fixed sparsity pattern of the pore matrix (CSC, symmetric, sorted) and the
    positions of its diagonal and of each adjacency entry, for :func:`fill_matrix`."""
    n = len(indptr) - 1
    adj = sp.csr_matrix((np.ones(len(nbr)), nbr, indptr), shape=(n, n))
    pattern = (adj + sp.identity(n, format="csr")).tocsc()
    pattern.sort_indices()
    cptr = pattern.indptr.astype(np.int64)
    cind = pattern.indices.astype(np.int64)
    diag, off = _pattern_positions(indptr, nbr, cptr, cind)
    return {"indptr": pattern.indptr, "indices": pattern.indices, "diag": diag, "off": off,
            "data": np.zeros(len(cind)), "n": n}  # fmt: skip


@njit
def fill_diagonal(
    dt: float,
    indptr: np.ndarray,
    thr: np.ndarray,
    vol: np.ndarray,
    g_eff: np.ndarray,
    g_out: np.ndarray,
    diag: np.ndarray,
) -> None:
    """The diagonal of ``K = V/dt + L`` (the grid Cholesky reads the off-diagonal from
    ``g_eff``)."""
    for i in range(len(indptr) - 1):
        diag[i] = _diagonal(i, dt, indptr, thr, vol, g_eff, g_out)
