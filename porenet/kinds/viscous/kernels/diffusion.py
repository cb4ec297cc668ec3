"""Pressure diffusion in the defending fluid over one explicit step (docs/model.md section 4).

Forward Euler for the Darcy fluxes between undrained pores and to the outlet, over the active
pores only: a list of pores on generic lattices (CSR adjacency), a growing box of rows and
columns on canonical square grids, swept as a stencil. Pure numba helpers on arrays, in scaled
units (see :mod:`porenet.kinds.viscous.kernels.explicit`).
"""

from __future__ import annotations

import numpy as np

from porenet.jit.jit import THREADS, njit, prange, serial_and_parallel, threaded_box
from porenet.kinds.viscous.kernels.state import LISTS, Conductances, Count, Network, Sweep
from porenet.kinds.viscous.kernels.stencil import Stencil, interior_run


@njit(helper=True)
def set_add(x: int, items: np.ndarray, pos: np.ndarray, cnt: np.ndarray, slot: int) -> None:
    """Add ``x`` to the indexed set ``items[:cnt[slot]]`` (``pos[x]`` its place, -1 if out)."""
    if pos[x] < 0:
        size = cnt[slot]
        items[size] = x
        pos[x] = size
        cnt[slot] = size + 1


@njit(helper=True)
def set_remove(x: int, items: np.ndarray, pos: np.ndarray, cnt: np.ndarray, slot: int) -> None:
    """Remove ``x`` from the indexed set (the last item takes its place)."""
    s = pos[x]
    if s >= 0:
        last = cnt[slot] - 1
        moved = items[last]
        items[s] = moved
        pos[moved] = s
        pos[x] = -1
        cnt[slot] = last


@njit(helper=True)
def activate(j: int, act: np.ndarray, apos: np.ndarray, cnt: np.ndarray) -> None:
    """Add pore ``j`` to the active pores (counted in ``cnt[Count.N_ACTIVE]``)."""
    set_add(j, act, apos, cnt, Count.N_ACTIVE)


@njit(helper=True)
def _csr_flux(i: int, field: Sweep, p: np.ndarray) -> float:
    """The explicit flux into active pore ``i`` from its active neighbours and the outlet."""
    apos, indptr, nbr, thr, g_eff = (field.pore_slot, field.indptr, field.neighbour,
                                     field.throat, field.between)  # fmt: skip
    pi = p[i]
    total = -field.outlet[i] * pi
    for e in range(indptr[i], indptr[i + 1]):
        j = nbr[e]
        if apos[j] >= 0:
            total += g_eff[thr[e]] * (p[j] - pi)
    return total


#: The list kernels sweep every pore in index order, skipping the inactive ones, rather than
#: the active pores in the order they became active, once at least this fraction of the
#: pores is active: the neighbours of pores near in index are near in memory (a cubic
#: lattice of 262 144 pores nearly all active: fluxes 3.3 ms against 35 ms;
#: ``tests/benchmarks/bench_csr.py``). Each pore's value is the same either way; sums over
#: the pores run in the sweep's order.
DENSE_ACTIVE = 0.25


@njit(helper=True)
def csr_fluxes(field: Sweep, p: np.ndarray, flux: np.ndarray) -> None:
    """Generic lattices: explicit flux into each active pore ``field.pores[:n_active]``
    (neighbours counted only while active, so what one pore gains its neighbour loses)."""
    act, apos = field.pores, field.pore_slot
    if dense(field):
        for i in range(len(apos)):
            if apos[i] >= 0:
                flux[i] = _csr_flux(i, field, p)
        return
    for s in range(field.n_active):
        i = act[s]
        flux[i] = _csr_flux(i, field, p)


@njit(helper=True)
def dense(field: Sweep) -> bool:
    """Whether the list kernels sweep every pore in index order, skipping the inactive ones
    (see :data:`DENSE_ACTIVE`), rather than the active pores in the order they became
    active."""
    return field.n_active >= DENSE_ACTIVE * len(field.pore_slot)


@njit(helper=True)
def csr_update(
    field: Sweep, dt: float, p: np.ndarray, p_next: np.ndarray, vol: np.ndarray
) -> tuple[float, float, float]:
    """Generic lattices: forward Euler for the active pores, from ``p`` into ``p_next`` with
    the fluxes ``field.scratch`` (:func:`csr_fluxes`); return the change of stored volume,
    the outflow rate (from the pressures at the start of the step) and the largest
    ``|dp/dt|``. The sums run over the pores in the order of the sweep (:func:`dense`)."""
    stored = 0.0
    out = 0.0
    largest = 0.0
    act, apos, flux, g_out = field.pores, field.pore_slot, field.scratch, field.outlet
    sweep_all = dense(field)
    for s in range(len(apos) if sweep_all else field.n_active):
        if sweep_all:
            i = s
            if apos[i] < 0:
                continue
        else:
            i = act[s]
        pi = p[i]
        rate = flux[i] / vol[i]
        pn = pi + dt * rate
        p_next[i] = pn
        out += g_out[i] * pi
        stored += vol[i] * (pn - pi)
        largest = max(largest, abs(rate))
    return stored, out, largest


@njit(helper=True)
def csr_copy(field: Sweep, src: np.ndarray, dst: np.ndarray) -> None:
    """Generic lattices: ``dst = src`` over the active pores."""
    act, apos = field.pores, field.pore_slot
    if dense(field):
        for i in range(len(apos)):
            if apos[i] >= 0:
                dst[i] = src[i]
        return
    for s in range(field.n_active):
        dst[act[s]] = src[act[s]]


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


@njit(helper=True, reassociate=True)
def _row_interior(
    run: Stencil,
    vol: np.ndarray,
    inv_vol: np.ndarray,
    dt: float,
    p_next: np.ndarray,
) -> tuple[float, float]:
    """Forward Euler for a run of pores of one row with both horizontal neighbours in the box
    (:func:`porenet.kinds.viscous.kernels.stencil.interior_run`; ``vol``, ``inv_vol`` and ``p_next``
    aligned on the run too): the loop compiles to SIMD instructions. Returns the change of
    stored volume and the outflow rate of the run."""
    pc, pw, east, pu, pd = run.centre, run.west, run.east, run.up, run.down
    gw, ge, gu, gd, g_out = run.g_west, run.g_east, run.g_up, run.g_down, run.g_outlet
    up, down = run.has_up, run.has_down
    stored = 0.0
    out = 0.0
    for j in range(pc.size):
        pk = pc[j]
        total = gw[j] * (pw[j] - pk) + ge[j] * (east[j] - pk) - g_out[j] * pk
        if up:
            total += gu[j] * (pu[j] - pk)
        if down:
            total += gd[j] * (pd[j] - pk)
        pn = pk + dt * (total * inv_vol[j])
        p_next[j] = pn
        out += g_out[j] * pk
        stored += vol[j] * (pn - pk)
    return stored, out


@njit(helper=True)
def _sweep_row(
    i: int, field: Sweep, dt: float, vol: np.ndarray, p: np.ndarray, p_next: np.ndarray
) -> tuple[float, float]:
    """Row ``i`` of :func:`grid_sweep`; returns its stored-volume change and outflow rate."""
    n, box, nbox = field.grid_n, field.box, field.bounds
    g_eff, g_out, inv_vol = field.between, field.outlet, field.inverse_volume
    j0, j1 = box[2], box[3]
    stored = 0.0
    out = 0.0
    row = i * n
    up, down = i > nbox[0], i < nbox[1] - 1
    a, b = row + j0 + 1, row + j1 - 1  # the interior run of the row: pores [a, b)
    if b > a:
        run = interior_run(p, g_eff, g_out, n, a, b, up, down)
        stored, out = _row_interior(run, vol[a:b], inv_vol[a:b], dt, p_next[a:b])
    for k in (row + j0, row + j1 - 1):
        pk = p[k]
        total = grid_flux(n, nbox, k, p, g_eff, g_out)
        pn = pk + dt * (total * inv_vol[k])
        p_next[k] = pn
        out += g_out[k] * pk
        stored += vol[k] * (pn - pk)
        if j1 - j0 == 1:  # one column: its only pore is both ends
            break
    return stored, out


def _sweep_rows(
    field: Sweep,
    dt: float,
    vol: np.ndarray,
    p: np.ndarray,
    p_next: np.ndarray,
    partial: np.ndarray,
) -> None:
    """:func:`_sweep_row` over the box's rows (they write disjoint parts of ``p_next``)."""
    box = field.box
    for i in prange(box[0], box[1]):
        r = i - box[0]
        partial[0, r], partial[1, r] = _sweep_row(i, field, dt, vol, p, p_next)


_sweep_rows_serial, _sweep_rows_parallel = serial_and_parallel(_sweep_rows)


@njit
def grid_sweep(
    field: Sweep, dt: float, vol: np.ndarray, p: np.ndarray, p_next: np.ndarray
) -> tuple[float, float]:
    """Canonical n x n grids: forward Euler for every pore of the box ``field.box``, from
    ``p`` into ``p_next`` (throats in canonical order,
    :mod:`porenet.kinds.viscous.kernels.stencil`). A throat touching a drained pore has conductance
    0 and a drained pore an outlet conductance 0, so drained pores keep their value with no test.
    Each pore gathers its own throat fluxes; ``g (p_j - p_i)`` and ``g (p_i - p_j)`` are exact
    negatives in floating point, so what one pore gains its neighbour loses, to the bit. Returns the
    change of stored volume and the outflow rate (from the pressures at the start of the step).

    The interior of each row is one SIMD loop (:func:`_row_interior`); the first and last
    pore of each row, which lack a neighbour inside the box, are done one by one.

    ``field.bounds`` holds the box and bounds the neighbours that count (the box itself but in
    a window of local time steps, :mod:`porenet.kinds.viscous.kernels.multirate`, whose ring of
    pores outside the box is read, not written). Boxes of :data:`porenet.jit.jit.PARALLEL_MIN` pores
    or more are swept by several threads; the sums are taken per row, then over the rows in order,
    so the result does not depend on their number."""
    box = field.box
    rows = box[1] - box[0]
    partial = np.empty((2, max(rows, 0)))
    if THREADS and threaded_box(box):
        _sweep_rows_parallel(field, dt, vol, p, p_next, partial)
    else:
        _sweep_rows_serial(field, dt, vol, p, p_next, partial)
    stored = 0.0
    out = 0.0
    for r in range(rows):
        stored += partial[0, r]
        out += partial[1, r]
    return stored, out


def _copy_rows(n: int, box: np.ndarray, src: np.ndarray, dst: np.ndarray) -> None:
    """``dst = src`` over the box of an n x n grid. (A loop: the slice assignment
    ``dst[a:b] = src[a:b]`` compiles numba's shape-mismatch error message, 16 string
    functions, ~2 s of a first run: docs/performance.md, "First run".)"""
    for i in prange(box[0], box[1]):
        start = i * n
        for j in range(start + box[2], start + box[3]):
            dst[j] = src[j]


_copy_rows_serial, _copy_rows_parallel = serial_and_parallel(_copy_rows)


@njit
def copy_rows(n: int, box: np.ndarray, src: np.ndarray, dst: np.ndarray) -> None:
    """``dst = src`` over the box of an n x n grid (by several threads on a large box)."""
    if THREADS and threaded_box(box):
        _copy_rows_parallel(n, box, src, dst)
    else:
        _copy_rows_serial(n, box, src, dst)


@njit(helper=True)
def grid_largest_rate(
    n: int, box: np.ndarray, dt: float, p: np.ndarray, p_next: np.ndarray
) -> float:
    """Largest ``|dp/dt|`` of the last sweep over the box (``p`` before, ``p_next`` after)."""
    largest = 0.0
    for i in range(box[0], box[1]):
        for k in range(i * n + box[2], i * n + box[3]):
            largest = max(largest, abs(p_next[k] - p[k]))
    return largest / dt


@njit(helper=True)
def grow_box(box: np.ndarray, n: int, i: int, j: int, margin: int) -> None:
    """Extend the box to hold pore (i, j) and ``margin`` pores around it (within the grid)."""
    box[0] = min(box[0], max(i - margin, 0))
    box[1] = max(box[1], min(i + margin + 1, n))
    box[2] = min(box[2], max(j - margin, 0))
    box[3] = max(box[3], min(j + margin + 1, n))


@njit(helper=True)
def spread(
    field: Sweep,
    settled: np.ndarray,
    counters: np.ndarray,
    drained: np.ndarray,
    p: np.ndarray,
    floor: float,
) -> None:
    """Activate the undrained neighbours of active pores whose ``|p|`` exceeds ``floor``
    (on grids: grow the box by one row or column where its edge exceeds it).

    Lists: an active pore whose neighbours are all active or drained afterwards is marked in
    ``settled`` (:attr:`~porenet.kinds.viscous.kernels.state.Front.settled`) and not looked at
    again: pores leave the active set only by draining, so it has nothing left to activate.
    The same pores are activated in the same order as without the mark, at the cost of the
    pressure front's pores instead of every active one (on a cubic lattice of 262 144 pores
    nearly all active, 1.0 ms against 19 ms; ``tests/benchmarks/bench_csr.py``)."""
    if LISTS and field.grid_n == 0:
        act, apos, indptr, nbr = field.pores, field.pore_slot, field.indptr, field.neighbour
        for s in range(field.n_active):
            i = act[s]
            if settled[i] or not abs(p[i]) > floor:
                continue
            for e in range(indptr[i], indptr[i + 1]):
                j = nbr[e]
                if apos[j] < 0 and not drained[j]:
                    activate(j, act, apos, counters)
            settled[i] = True
        return
    grow_where_reached(field.box, field.grid_n, p, floor, 1)


@njit(helper=True)
def grow_where_reached(box: np.ndarray, n: int, p: np.ndarray, floor: float, margin: int) -> bool:
    """Canonical grids: extend the box by ``margin`` rows or columns on each side where a pore
    of its edge has ``|p| > floor`` (within the grid); return whether it changed."""
    i0, i1, j0, j1 = box[0], box[1], box[2], box[3]
    top = bottom = left = right = False
    for j in range(j0, j1):
        top |= abs(p[i0 * n + j]) > floor
        bottom |= abs(p[(i1 - 1) * n + j]) > floor
    for i in range(i0, i1):
        left |= abs(p[i * n + j0]) > floor
        right |= abs(p[i * n + j1 - 1]) > floor
    box[0] = max(i0 - margin, 0) if top else i0
    box[1] = min(i1 + margin, n) if bottom else i1
    box[2] = max(j0 - margin, 0) if left else j0
    box[3] = min(j1 + margin, n) if right else j1
    return box[0] != i0 or box[1] != i1 or box[2] != j0 or box[3] != j1


@njit
def refresh_throats(
    throats: np.ndarray,
    apertures: np.ndarray,
    factors: tuple[float, float, float],
    net: Network,
    cond: Conductances,
    drained: np.ndarray,
) -> float:
    """Recompute the properties of the given throats from their apertures ``r`` (a), in
    ``cond``: area ``A = c_A r^2``, ``A k`` with ``k = c_k r^2``, the conductance ``A k / l``
    between undrained pores (0 for a throat touching a drained pore), the entry pressure
    ``2 / r``; ``factors = (c_A, c_k, l)``.

    Returns
    -------
    float
        The explicit stability limit ``min V / (sum g + g_out)`` over the pores at either end
        of the throats that now conduct more between undrained pores (inf if none: a throat
        that narrowed cannot lower a limit). A limit computed while other throats of the
        list are not refreshed yet is at most too small, never too large.
    """
    area_factor, permeability_factor, meniscus_length = factors
    area, g_num, g_eff, entry = cond.area, cond.meniscus, cond.between, cond.entry_pressure
    throat_pores, indptr, thr, vol, g_out = (net.throat_pores, net.indptr, net.throat,
                                             net.volume, cond.outlet)  # fmt: skip
    limit = np.inf
    for e in range(throats.shape[0]):
        t = throats[e]
        r2 = apertures[t] * apertures[t]
        area[t] = area_factor * r2
        grew = area[t] * permeability_factor * r2 > g_num[t]
        g_num[t] = area[t] * permeability_factor * r2
        i, j = throat_pores[t, 0], throat_pores[t, 1]
        g_eff[t] = 0.0 if (drained[i] or drained[j]) else g_num[t] / meniscus_length
        entry[t] = 2.0 / apertures[t]
        if not (grew and g_eff[t] > 0):
            continue  # only a throat that conducts more can lower a pore's limit
        for i in (throat_pores[t, 0], throat_pores[t, 1]):
            total = g_out[i]
            for k in range(indptr[i], indptr[i + 1]):
                total += g_eff[thr[k]]
            limit = min(limit, vol[i] / total)
    return limit
