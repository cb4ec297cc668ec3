"""Pressure diffusion in the defending fluid over one explicit step (MODEL.md section 4).

Forward Euler for the Darcy fluxes between undrained pores and to the outlet, over the active
pores only: a list of pores on generic lattices (CSR adjacency), a growing box of rows and
columns on canonical square grids, swept as a stencil. Pure numba helpers on arrays, in scaled
units (see :mod:`porenet.kernels.viscous`).
"""

from __future__ import annotations

import numpy as np

from porenet.kernels._jit import njit
from porenet.kernels.menisci import pore_after


@njit(helper=True)
def set_add(x: int, items: np.ndarray, pos: np.ndarray, cnt: np.ndarray, slot: int) -> None:
    """Add ``x`` to the indexed set ``items[:cnt[slot]]`` (``pos[x]`` its place, -1 if out)."""
    if pos[x] < 0:
        size = cnt[slot]
        items[size] = x
        pos[x] = size
        cnt[slot] = size + 1


@njit(helper=True)
def activate(j: int, act: np.ndarray, apos: np.ndarray, cnt: np.ndarray) -> None:
    set_add(j, act, apos, cnt, 3)


@njit(helper=True)
def csr_fluxes(
    na: int,
    act: np.ndarray,
    apos: np.ndarray,
    indptr: np.ndarray,
    nbr: np.ndarray,
    thr: np.ndarray,
    g_eff: np.ndarray,
    g_out: np.ndarray,
    p: np.ndarray,
    flux: np.ndarray,
) -> None:
    """Generic lattices: explicit flux into each active pore ``act[:na]`` (neighbours counted
    only while active, so what one pore gains its neighbour loses)."""
    for s in range(na):
        i = act[s]
        pi = p[i]
        total = -g_out[i] * pi
        for e in range(indptr[i], indptr[i + 1]):
            j = nbr[e]
            if apos[j] >= 0:
                total += g_eff[thr[e]] * (p[j] - pi)
        flux[i] = total


@njit(helper=True)
def csr_update(
    na: int,
    act: np.ndarray,
    dt: float,
    pnew: float,
    p: np.ndarray,
    flux: np.ndarray,
    gsum: np.ndarray,
    vol: np.ndarray,
    g_out: np.ndarray,
) -> tuple[float, float, float]:
    """Generic lattices: advance the active pores (explicit fluxes, implicit menisci); return
    the change of stored volume, the outflow rate (from the pressures at the start of the
    step) and the largest ``|dp/dt|`` from the explicit fluxes."""
    stored = 0.0
    out = 0.0
    largest = 0.0
    for s in range(na):
        i = act[s]
        pi = p[i]
        pn = pore_after(dt, i, p, flux, gsum, vol, pnew)
        out += g_out[i] * pi
        stored += vol[i] * (pn - pi)
        largest = max(largest, abs(flux[i]) / vol[i])
        p[i] = pn
    return stored, out, largest


@njit(helper=True)
def grid_flux(
    n: int, box: np.ndarray, k: int, p: np.ndarray, g_eff: np.ndarray, g_out: np.ndarray
) -> float:
    """Canonical n x n grids: explicit flux into pore ``k`` from its neighbours inside the box
    of active pores (rows ``[box[0], box[1])``, columns ``[box[2], box[3])``) and from the
    outlet; the same terms as :func:`grid_sweep`."""
    i = k // n
    j = k - i * n
    pk = p[k]
    vertical = n * (n - 1)
    total = -g_out[k] * pk
    if j > box[2]:
        total += g_eff[i * (n - 1) + j - 1] * (p[k - 1] - pk)
    if j < box[3] - 1:
        total += g_eff[i * (n - 1) + j] * (p[k + 1] - pk)
    if i > box[0]:
        total += g_eff[vertical + k - n] * (p[k - n] - pk)
    if i < box[1] - 1:
        total += g_eff[vertical + k] * (p[k + n] - pk)
    return total


@njit(helper=True)
def grid_sweep(
    n: int,
    box: np.ndarray,
    dt: float,
    g_eff: np.ndarray,
    g_out: np.ndarray,
    vol: np.ndarray,
    p: np.ndarray,
    p_next: np.ndarray,
) -> tuple[float, float, float]:
    """Canonical n x n grids: forward Euler for every pore of the box of active pores, from
    ``p`` into ``p_next``, in one pass (throats in canonical order: horizontal (i,j)-(i,j+1)
    is ``i (n-1) + j``, vertical (i,j)-(i+1,j) is ``n (n-1) + i n + j``). A throat touching
    a drained pore has ``g_eff = 0`` and a drained pore ``g_out = 0``, so drained pores keep
    their value with no test. Each pore gathers its own throat fluxes; ``g (p_j - p_i)`` and
    ``g (p_i - p_j)`` are exact negatives in floating point, so what one pore gains its
    neighbour loses, to the bit. Returns the change of stored volume, the outflow rate and
    the largest ``|dp/dt|``."""
    i0, i1, j0, j1 = box[0], box[1], box[2], box[3]
    vertical = n * (n - 1)
    stored = 0.0
    out = 0.0
    largest = 0.0
    for i in range(i0, i1):
        row = i * n
        h = i * (n - 1) - row  # throat (i, j)-(i, j+1) is h + k for pore k = row + j
        first, last = row + j0, row + j1 - 1
        up, down = i > i0, i < i1 - 1
        for k in range(first, last + 1):
            pk = p[k]
            total = -g_out[k] * pk
            if k > first:
                total += g_eff[h + k - 1] * (p[k - 1] - pk)
            if k < last:
                total += g_eff[h + k] * (p[k + 1] - pk)
            if up:
                total += g_eff[vertical + k - n] * (p[k - n] - pk)
            if down:
                total += g_eff[vertical + k] * (p[k + n] - pk)
            rate = total / vol[k]
            pn = pk + dt * rate
            p_next[k] = pn
            out += g_out[k] * pk
            stored += vol[k] * (pn - pk)
            largest = max(largest, abs(rate))
    return stored, out, largest


@njit(helper=True)
def grow_box(box: np.ndarray, n: int, i: int, j: int, margin: int) -> None:
    """Extend the box to hold pore (i, j) and ``margin`` pores around it (within the grid)."""
    box[0] = min(box[0], max(i - margin, 0))
    box[1] = max(box[1], min(i + margin + 1, n))
    box[2] = min(box[2], max(j - margin, 0))
    box[3] = max(box[3], min(j + margin + 1, n))


@njit(helper=True)
def spread(
    grid_n: int,
    box: np.ndarray,
    na: int,
    act: np.ndarray,
    apos: np.ndarray,
    cnt: np.ndarray,
    indptr: np.ndarray,
    nbr: np.ndarray,
    drained: np.ndarray,
    p: np.ndarray,
    floor: float,
) -> None:
    """Activate the undrained neighbours of active pores whose ``|p|`` exceeds ``floor``
    (on grids: grow the box by one row or column where its edge exceeds it)."""
    if grid_n == 0:
        for s in range(na):
            i = act[s]
            if abs(p[i]) > floor:
                for e in range(indptr[i], indptr[i + 1]):
                    j = nbr[e]
                    if apos[j] < 0 and not drained[j]:
                        activate(j, act, apos, cnt)
        return
    n = grid_n
    i0, i1, j0, j1 = box[0], box[1], box[2], box[3]
    top = bottom = left = right = False
    for j in range(j0, j1):
        top |= abs(p[i0 * n + j]) > floor
        bottom |= abs(p[(i1 - 1) * n + j]) > floor
    for i in range(i0, i1):
        left |= abs(p[i * n + j0]) > floor
        right |= abs(p[i * n + j1 - 1]) > floor
    box[0] = max(i0 - 1, 0) if top else i0
    box[1] = min(i1 + 1, n) if bottom else i1
    box[2] = max(j0 - 1, 0) if left else j0
    box[3] = min(j1 + 1, n) if right else j1
