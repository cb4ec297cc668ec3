"""Runge-Kutta-Chebyshev numerics on the pore field: coefficients, stage counts, sweeps.

Pure functions on arrays, in scaled units (see :mod:`porenet.kinds.viscous.kernels.explicit`), for
the stabilised integrator of :mod:`porenet.kinds.viscous.kernels.rkc`: the damped (``eps = 2/13``)
second-order RKC scheme in the IMEX form of Verwer & Sommeijer (2004) and of the IRKC code
(Shampine, Sommeijer & Verwer 2006), the rule for its number of stages, the spectral radius of the
pore-to-pore operator that sets it, and one stage as a single stencil sweep over the active pores (a
box on canonical grids, a list elsewhere).
"""

from __future__ import annotations

import math

import numpy as np

from porenet.jit.jit import THREADS, njit, prange, serial_and_parallel, threaded_box
from porenet.kinds.viscous.kernels.diffusion import csr_fluxes, grid_flux
from porenet.kinds.viscous.kernels.state import LISTS, Sweep
from porenet.kinds.viscous.kernels.stencil import Stencil, interior_run

#: Most stages of one step (the step is cut to what they make stable).
MAX_STAGES = 400


@njit(helper=True)
def stage_count(h: float, rho: float) -> int:
    """The fewest stages (at least 3, at most :data:`MAX_STAGES`) whose
    :func:`longest_step` is at least ``h``: ``ceil(1 + sqrt(1 + 1.54 h rho))`` (the RKC code
    rounds down instead, which its true stability bound ``~0.653 m^2`` allows for the explicit
    scheme but not for every IMEX pair at small m)."""
    m = math.ceil(1.0 + math.sqrt(1.0 + 1.54 * h * rho) - 1e-12)
    return max(3, min(m, MAX_STAGES))


@njit(helper=True)
def longest_step(m: int, rho: float) -> float:
    """The longest step ``m`` stages keep stable (the inverse of :func:`stage_count`)."""
    return ((m - 1.0) ** 2 - 1.0) / (1.54 * rho)


@njit
def coefficients(m: int) -> tuple[float, np.ndarray]:
    """``mu~_1`` and, for stages ``j = 2 .. m`` (row ``j - 2``), ``(mu_j, nu_j, mu~_j,
    g~_j)`` of the damped (``eps = 2/13``) second-order RKC scheme in its IMEX form."""
    w0 = 1.0 + 2.0 / (13.0 * m * m)
    t1 = w0 * w0 - 1.0
    t2 = math.sqrt(t1)
    arg = m * math.log(w0 + t2)
    w1 = math.sinh(arg) * t1 / (math.cosh(arg) * m * t2 - w0 * math.sinh(arg))
    bjm1 = 1.0 / w0
    bjm2 = 1.0 / (2.0 * w0) ** 2
    mus1 = w1 * bjm1
    out = np.empty((max(m - 1, 0), 4))
    zjm1, zjm2, dzjm1, dzjm2, d2zjm1, d2zjm2 = w0, 1.0, 1.0, 0.0, 0.0, 0.0
    for j in range(2, m + 1):
        zj = 2.0 * w0 * zjm1 - zjm2
        dzj = 2.0 * w0 * dzjm1 - dzjm2 + 2.0 * zjm1
        d2zj = 2.0 * w0 * d2zjm1 - d2zjm2 + 4.0 * dzjm1
        bj = d2zj / (dzj * dzj)
        ajm1 = 1.0 - zjm1 * bjm1
        mu = 2.0 * w0 * bj / bjm1
        nu = -bj / bjm2
        mus = mu * w1 / w0
        out[j - 2, 0] = mu
        out[j - 2, 1] = nu
        out[j - 2, 2] = mus
        out[j - 2, 3] = -ajm1 * mus
        bjm2, bjm1 = bjm1, bj
        zjm2, zjm1 = zjm1, zj
        dzjm2, dzjm1 = dzjm1, dzj
        d2zjm2, d2zjm1 = d2zjm1, d2zj
    return mus1, out


# -- sweeps over the active pores ---------------------------------------------------------------
#
# The stages are written for increments ``d_j = W_j - y_n``: ``F_E`` is linear and homogeneous
# (``F_E(y) = L y``, the outlet at p = 0), so ``F_E(W_j) = F_E(y_n) + L d_j`` and a stage reads
# ``d_{j-1}``, ``d_{j-2}`` and ``F_E(y_n)`` but not ``y_n``: one memory stream fewer than the
# full form, and the increments carry no cancellation error.


@njit(helper=True)
def _row_stage(
    run: Stencil,
    inv_vol: np.ndarray,
    y2: np.ndarray,
    f0: np.ndarray,
    coef: tuple[float, float, float, float],
    out: np.ndarray,
) -> None:
    """One stage for a run of a row with both horizontal neighbours in the box (aligned views,
    :func:`porenet.kinds.viscous.kernels.stencil.interior_run`): ``out = c1 y1 + c2 y2 + (ce L y1 +
    cf f0) / V`` with ``y1 = run.centre`` (only rows on the lattice's edge read the outlet
    conductances). No reduction, so it compiles to SIMD instructions without reordering any
    sum: every pore is computed the same way, whatever the alignment of the arrays (a run is
    bitwise reproducible)."""
    c1, c2, ce, cf = coef
    pc, pw, east, pu, pd = run.centre, run.west, run.east, run.up, run.down
    gw, ge, gu, gd, g_out = run.g_west, run.g_east, run.g_up, run.g_down, run.g_outlet
    up, down, outlet = run.has_up, run.has_down, run.on_outlet
    for j in range(pc.size):
        pk = pc[j]
        total = gw[j] * (pw[j] - pk) + ge[j] * (east[j] - pk)
        if outlet:
            total -= g_out[j] * pk
        if up:
            total += gu[j] * (pu[j] - pk)
        if down:
            total += gd[j] * (pd[j] - pk)
        out[j] = c1 * pk + c2 * y2[j] + (ce * total + cf * f0[j]) * inv_vol[j]


@njit(helper=True)
def _row_flux(run: Stencil, out: np.ndarray) -> None:
    """``L y1`` (volumetric) of a run of a row into ``out``. The same loop as
    :func:`_row_stage` without the combination: one loop with a ``flux_only`` branch instead
    was measured slower (the branch is not hoisted out of the SIMD loop)."""
    pc, pw, east, pu, pd = run.centre, run.west, run.east, run.up, run.down
    gw, ge, gu, gd, g_out = run.g_west, run.g_east, run.g_up, run.g_down, run.g_outlet
    up, down, outlet = run.has_up, run.has_down, run.on_outlet
    for j in range(pc.size):
        pk = pc[j]
        total = gw[j] * (pw[j] - pk) + ge[j] * (east[j] - pk)
        if outlet:
            total -= g_out[j] * pk
        if up:
            total += gu[j] * (pu[j] - pk)
        if down:
            total += gd[j] * (pd[j] - pk)
        out[j] = total


@njit(helper=True)
def _stage_row(
    i: int,
    field: Sweep,
    y1: np.ndarray,
    y2: np.ndarray,
    f0: np.ndarray,
    coef: tuple[float, float, float, float],
    out: np.ndarray,
    flux_only: bool,
) -> float:
    """Row ``i`` of :func:`grid_stage`; returns its outflow rate (a sequential sum)."""
    n, box, nbox = field.grid_n, field.box, field.bounds
    g_eff, g_out, inv_vol = field.between, field.outlet, field.inverse_volume
    c1, c2, ce, cf = coef
    j0, j1 = box[2], box[3]
    row_out = 0.0
    row = i * n
    up, down = i > nbox[0], i < nbox[1] - 1
    outlet = i == 0 or i == n - 1
    a, b = row + j0 + 1, row + j1 - 1
    if b > a:
        run = interior_run(y1, g_eff, g_out, n, a, b, up, down)
        if flux_only:
            _row_flux(run, out[a:b])
        else:
            _row_stage(run, inv_vol[a:b], y2[a:b], f0[a:b], coef, out[a:b])
        if outlet:  # the outlet's pores inside the run
            for k in range(a, b):
                row_out += g_out[k] * y1[k]
    for k in (row + j0, row + j1 - 1):
        total = grid_flux(n, nbox, k, y1, g_eff, g_out)
        if flux_only:
            out[k] = total
        else:
            out[k] = c1 * y1[k] + c2 * y2[k] + (ce * total + cf * f0[k]) * inv_vol[k]
        row_out += g_out[k] * y1[k]
        if j1 - j0 == 1:
            break
    return row_out


def _stage_rows(
    field: Sweep,
    y1: np.ndarray,
    y2: np.ndarray,
    f0: np.ndarray,
    coef: tuple[float, float, float, float],
    out: np.ndarray,
    flux_only: bool,
    partial: np.ndarray,
) -> None:
    """:func:`_stage_row` over the box's rows (they write disjoint parts of ``out``)."""
    box = field.box
    for i in prange(box[0], box[1]):
        partial[i - box[0]] = _stage_row(i, field, y1, y2, f0, coef, out, flux_only)


_stage_rows_serial, _stage_rows_parallel = serial_and_parallel(_stage_rows)


@njit
def grid_stage(
    field: Sweep,
    y1: np.ndarray,
    y2: np.ndarray,
    f0: np.ndarray,
    coef: tuple[float, float, float, float],
    out: np.ndarray,
    flux_only: bool,
) -> float:
    """Canonical n x n grids, over the box ``field.box``: ``out = c1 y1 + c2 y2 + (ce L y1 +
    cf f0) / V`` (``coef = (c1, c2, ce, cf)``), or with ``flux_only`` ``out = L y1``
    (volumetric; ``L y`` is the Darcy flux into each pore, ``F_E``). Neighbours outside
    ``field.bounds`` (which holds the box: the active pores; the box itself when the whole of
    it is swept) do not count, as in :func:`porenet.kinds.viscous.kernels.diffusion.grid_sweep`;
    neighbours outside the box but inside the bounds do, with the values ``y1`` holds there
    (a window's ring, :mod:`porenet.kinds.viscous.kernels.multirate`). Returns the outflow rate
    ``sum g_out y1`` over the box (per row, then over the rows in order: the same bits on any
    number of threads). Boxes of :data:`porenet.jit.jit.PARALLEL_MIN` pores or more are
    swept by several threads."""
    box = field.box
    rows = box[1] - box[0]
    partial = np.empty(max(rows, 0))
    if THREADS and threaded_box(box):
        _stage_rows_parallel(field, y1, y2, f0, coef, out, flux_only, partial)
    else:
        _stage_rows_serial(field, y1, y2, f0, coef, out, flux_only, partial)
    total_out = 0.0
    for r in range(rows):
        total_out += partial[r]
    return total_out


@njit
def csr_stage(
    field: Sweep,
    y1: np.ndarray,
    y2: np.ndarray,
    f0: np.ndarray,
    coef: tuple[float, float, float, float],
    out: np.ndarray,
    flux_only: bool,
) -> float:
    """Generic lattices, over the active pores ``field.pores[:n_active]``: as
    :func:`grid_stage` (``field.scratch`` holds ``L y1``)."""
    c1, c2, ce, cf = coef
    act, g_out, inv_vol, scratch = field.pores, field.outlet, field.inverse_volume, field.scratch
    csr_fluxes(field, y1, scratch)
    total_out = 0.0
    for s in range(field.n_active):
        k = act[s]
        total_out += g_out[k] * y1[k]
        if flux_only:
            out[k] = scratch[k]
        else:
            out[k] = c1 * y1[k] + c2 * y2[k] + (ce * scratch[k] + cf * f0[k]) * inv_vol[k]
    return total_out


@njit
def sweep(
    field: Sweep,
    y1: np.ndarray,
    y2: np.ndarray,
    f0: np.ndarray,
    coef: tuple[float, float, float, float],
    out: np.ndarray,
    flux_only: bool,
) -> float:
    """:func:`grid_stage` or :func:`csr_stage` over the active pores of ``field`` (a
    :class:`~porenet.kinds.viscous.kernels.state.Sweep`)."""
    if LISTS and field.grid_n == 0:
        return csr_stage(field, y1, y2, f0, coef, out, flux_only)
    return grid_stage(field, y1, y2, f0, coef, out, flux_only)


def spectral_radius(
    throat_pores: np.ndarray, g_eff: np.ndarray, g_out: np.ndarray, vol: np.ndarray
) -> float:
    """Largest eigenvalue of ``V^-1 L`` (``L`` the pore-to-pore and outlet conductances),
    by Lanczos (``scipy.sparse.linalg.eigsh`` on the symmetric ``V^-1/2 L V^-1/2``), raised by
    2 % against its convergence tolerance; the Gershgorin bound ``max 2 sum g / V`` if Lanczos
    fails. The start vector is fixed, so the value (and the run) is reproducible. Removing
    conductances (drained pores) only lowers it, so the value at the start of
    a run bounds the whole run on a rigid medium. On the square lattice with lambda = 0.3 it
    is ~0.7 of the Gershgorin bound, which saves ~16 % of the stages."""
    import scipy.sparse as sp
    from scipy.sparse.linalg import ArpackNoConvergence, eigsh

    n = len(vol)
    a, b = throat_pores[:, 0], throat_pores[:, 1]
    degree = np.asarray(g_out, dtype=np.float64).copy()
    np.add.at(degree, a, g_eff)
    np.add.at(degree, b, g_eff)
    gershgorin = float(np.max(2.0 * degree / vol))
    if n < 3 or not np.any(g_eff > 0):
        return gershgorin
    scale = 1.0 / np.sqrt(vol)
    w = -g_eff * scale[a] * scale[b]
    mat = sp.coo_matrix((np.r_[w, w], (np.r_[a, b], np.r_[b, a])), shape=(n, n)).tocsr()
    mat = mat + sp.diags(degree * scale * scale)
    try:
        start = np.random.default_rng(0).standard_normal(n)  # ARPACK's own start is random
        top = eigsh(mat, k=1, which="LA", return_eigenvectors=False, tol=1e-3, v0=start)[0]
        top = float(top)
    except (ArpackNoConvergence, ValueError):  # pragma: no cover - fall back on the bound
        return gershgorin
    return min(gershgorin, 1.02 * top)
