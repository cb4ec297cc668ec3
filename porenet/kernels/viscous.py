"""Kernels of the dynamic viscous drainage model (MODEL.md section 4).

Pure functions on arrays, in scaled units: lengths by ``a``, pressures by ``gamma / a``, times
by ``mu a / gamma``, volumes by ``a**3``. In these units the paper's equations read

* undrained pore i: ``V_i dp_i/dt = sum_j g_ij (p_j - p_i) + sum_m q_m - g_out,i p_i``,
  with ``g_ij = A k / 2`` between undrained pores (``l = 2a``) and ``g_out = A k / 1`` for the
  half throats to the outlet (``c_t = a / gamma`` becomes 1);
* advancing meniscus m from a drained pore into pore i: ``q_m = (A k / l_m) (p_inv - p_i)``,
  ``dl_m/dt = -q_m / A``; pore i drains when ``l_m`` reaches 0;
* injection reservoir of compliance C: ``C dp_inv/dt = Q - sum_m q_m`` (rate control), or
  ``p_inv`` prescribed (pressure control, ramp).

:func:`explicit_advance` integrates them with forward Euler for the fluxes between undrained
pores and to the outlet, and point-implicit (backward Euler) for the meniscus fluxes and the
injection reservoir, which are the stiff terms (a meniscus conductance ``A k / l`` grows without
bound as ``l -> 0``; a small C makes the reservoir stiff). The pore-to-pore part is stable for
``dt <= min_i V_i / (sum_j g_ij + g_out,i)``; the implicit part is unconditionally stable, so the
meniscus and reservoir terms never limit the step. Every flux is computed once and used for both
sides, so the volume balances close to round-off (see :data:`ACC`). A step that would take a
meniscus past ``l = 0`` is shortened so that the first one lands exactly on 0 (a monotone
fixed-point iteration on the step length), and the pore drains at that instant.

Pressure spreads only through the *active* pores: undrained pores next to a meniscus or next to
an active pore whose pressure exceeds ``floor`` in magnitude. Fluxes to inactive pores are
neglected (they are below ``g * floor``), which keeps the cost proportional to the region the
pressure has reached, not to the lattice, and keeps the balances exact.
"""

from __future__ import annotations

import numpy as np

from porenet.kernels._jit import njit

#: The helpers of one step take the advancing menisci and the pump as two tuples:
#: ``menisci = (on_t, on_p, p, flux, gsum, vol, g_num, ell, area)`` (the listed menisci's
#: throats and pores, then the arrays they read) and
#: ``pump = (control, pinv, q_rate, capacity, ramp_rate)`` (see :func:`explicit_advance`).

#: Slots of the ``acc`` array of running totals (scaled units).
ACC = {
    "time": 0,
    "invading_pressure": 1,
    "injected": 2,  # volume delivered by the pump
    "drained": 3,  # defender volume displaced by advancing menisci (the invader's volume)
    "stored_defender": 4,  # sum of V_i p_i over undrained pores (compressibility storage)
    "outflow": 5,  # defender volume through the outlet
    "released": 6,  # storage V_i p_i discarded when pore i drains
    "drained_pore_volume": 7,  # sum of V_i over drained pores
    "stored_reservoir": 8,  # integral of C dp_inv
}
N_ACC = 9

#: Slots of the ``cnt`` array of counters.
CNT = {"events": 0, "steps": 1, "n_front": 2, "n_active": 3, "where": 4, "breakthrough": 5}
N_CNT = 6

#: Columns of the time-series rows written at each drainage event.
SERIES = (
    "time",
    "invading_pressure",
    "injected",
    "drained",
    "stored",
    "outflow",
    "released",
    "n_drained",
)

#: Status codes returned by :func:`explicit_advance`.
STATUS = {
    0: "event budget reached",
    1: "breakthrough",
    2: "end time reached",
    3: "step limit reached",
    4: "non-finite value",
    5: "no meniscus left",
    6: "stationary",
}

CONTROL_RATE, CONTROL_PRESSURE, CONTROL_RAMP = 0, 1, 2


@njit(helper=True)
def _other(tp: np.ndarray, drained: np.ndarray, f: int) -> int:
    """The undrained pore of frontier throat ``f``."""
    a = tp[f, 0]
    return tp[f, 1] if drained[a] else a


@njit(helper=True)
def _set_add(x: int, items: np.ndarray, pos: np.ndarray, cnt: np.ndarray, slot: int) -> None:
    """Add ``x`` to the indexed set ``items[:cnt[slot]]`` (``pos[x]`` its place, -1 if out)."""
    if pos[x] < 0:
        size = cnt[slot]
        items[size] = x
        pos[x] = size
        cnt[slot] = size + 1


@njit(helper=True)
def _set_remove(x: int, items: np.ndarray, pos: np.ndarray, cnt: np.ndarray, slot: int) -> None:
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
def _activate(j: int, act: np.ndarray, apos: np.ndarray, cnt: np.ndarray) -> None:
    _set_add(j, act, apos, cnt, 3)


@njit
def drain_pore(
    i: int,
    f: int,
    indptr: np.ndarray,
    nbr: np.ndarray,
    thr: np.ndarray,
    vol: np.ndarray,
    ell0: float,
    g_eff: np.ndarray,
    g_out: np.ndarray,
    grid_n: int,
    box: np.ndarray,
    p: np.ndarray,
    drained: np.ndarray,
    ell: np.ndarray,
    latched: np.ndarray,
    front: np.ndarray,
    fpos: np.ndarray,
    act: np.ndarray,
    apos: np.ndarray,
    acc: np.ndarray,
    cnt: np.ndarray,
    order: np.ndarray,
    via: np.ndarray,
    rtime: np.ndarray,
    rpress: np.ndarray,
    series: np.ndarray,
) -> None:
    """Drain pore ``i`` through throat ``f`` (-1 for an inlet) at the current time.

    Its stored volume ``V_i p_i`` is released, the menisci entering it vanish, pinned menisci
    of length ``ell0`` appear in its throats to undrained neighbours (which become active), and
    the event is appended to the records and to the time series. Its throats stop
    conducting between pores (``g_eff``) and it stops draining to the outlet (``g_out``).
    """
    drained[i] = True
    released = vol[i] * p[i]
    acc[6] += released
    acc[4] -= released
    acc[7] += vol[i]
    p[i] = acc[1]
    g_out[i] = 0.0
    _set_remove(i, act, apos, cnt, 3)
    if grid_n > 0:
        _grow_box(box, grid_n, i // grid_n, i % grid_n, 1)
    for e in range(indptr[i], indptr[i + 1]):
        j = nbr[e]
        t = thr[e]
        g_eff[t] = 0.0
        if drained[j]:
            _set_remove(t, front, fpos, cnt, 2)
        else:
            ell[t] = ell0
            latched[t] = False
            _set_add(t, front, fpos, cnt, 2)
            _activate(j, act, apos, cnt)
    k = cnt[0]
    order[k] = i
    via[k] = f
    rtime[k] = acc[0]
    rpress[k] = acc[1]
    series[k, 0] = acc[0]
    series[k, 1] = acc[1]
    series[k, 2] = acc[2]
    series[k, 3] = acc[3]
    series[k, 4] = acc[4] + acc[8]
    series[k, 5] = acc[5]
    series[k, 6] = acc[6]
    series[k, 7] = k + 1
    cnt[0] = k + 1


@njit(helper=True)
def _invader_pressure(
    control: int,
    pinv: float,
    dt: float,
    q_rate: float,
    capacity: float,
    ramp_rate: float,
    s0: float,
    s1: float,
) -> float:
    """``p_inv`` at the end of a step of length ``dt`` (backward Euler for the reservoir).

    With the meniscus fluxes ``sum q = s1 p_inv' - s0`` (linear in the new invader pressure),
    rate control solves ``C (p' - p) = dt (Q - sum q)``.
    """
    if control == CONTROL_RATE:
        return (capacity * pinv + dt * (q_rate + s0)) / (capacity + dt * s1)
    if control == CONTROL_RAMP:
        return pinv + ramp_rate * dt
    return pinv


@njit(helper=True)
def _pore_after(
    dt: float,
    i: int,
    p: np.ndarray,
    flux: np.ndarray,
    gsum: np.ndarray,
    vol: np.ndarray,
    pnew: float,
) -> float:
    """Pressure of pore ``i`` after a step: explicit fluxes, implicit menisci."""
    w = dt * gsum[i] / vol[i]
    return (p[i] + dt * flux[i] / vol[i] + w * pnew) / (1.0 + w)


@njit(helper=True)
def _meniscus_terms(dt: float, n_on: int, menisci: tuple, pump: tuple, q_out: np.ndarray) -> float:
    """Solve the invader pressure after a step of ``dt`` and write each advancing meniscus'
    flux into ``q_out[:n_on]``; return the new invader pressure.

    Each meniscus pore's new pressure is linear in the new invader pressure,
    ``p_i' = alpha_i + beta_i p_inv'``, so the reservoir equation is one linear equation.
    """
    on_t, on_p, p, flux, gsum, vol, g_num, ell, _area = menisci
    control, pinv, q_rate, capacity, ramp_rate = pump
    s0 = 0.0
    s1 = 0.0
    for s in range(n_on):
        i = on_p[s]
        w = dt * gsum[i] / vol[i]
        g = g_num[on_t[s]] / ell[on_t[s]]
        s0 += g * (p[i] + dt * flux[i] / vol[i]) / (1.0 + w)
        s1 += g / (1.0 + w)
    pnew = _invader_pressure(control, pinv, dt, q_rate, capacity, ramp_rate, s0, s1)
    for s in range(n_on):
        i = on_p[s]
        f = on_t[s]
        q_out[s] = g_num[f] / ell[f] * (pnew - _pore_after(dt, i, p, flux, gsum, vol, pnew))
    return pnew


@njit(helper=True)
def _pressure_rate(n_on: int, menisci: tuple, pump: tuple, ell0: float) -> float:
    """``|dp_inv/dt| + max |dp_i/dt|`` over the pores behind advancing menisci, from the
    state at the start of a step (explicit estimates, for the accuracy limit of the step).

    A meniscus' push into its pore is estimated with its conductance at full length
    ``A k / l0``: its real conductance ``A k / l`` grows without bound as it lands, which
    would shrink the steps geometrically before every landing (the landing itself is an
    exact event, and the implicit treatment keeps the pore stable)."""
    on_t, on_p, p, flux, _gsum, vol, g_num, ell, _area = menisci
    control, pinv, q_rate, capacity, ramp_rate = pump
    qsum = 0.0
    largest = 0.0
    for s in range(n_on):
        i = on_p[s]
        q = g_num[on_t[s]] / ell[on_t[s]] * (pinv - p[i])
        qsum += q
        largest = max(largest, abs(flux[i] + g_num[on_t[s]] / ell0 * (pinv - p[i])) / vol[i])
    if control == CONTROL_RATE:
        return abs(q_rate - qsum) / capacity + largest
    if control == CONTROL_RAMP:
        return abs(ramp_rate) + largest
    return largest


@njit(helper=True)
def _shortest_remaining(
    dt: float, n_on: int, menisci: tuple, pump: tuple, q_out: np.ndarray
) -> tuple[float, int]:
    """After a step of ``dt``: the smallest remaining meniscus length ``l - q dt / A`` among
    the advancing menisci, and its index in ``on_t`` (``inf, -1`` if none advances)."""
    on_t, ell, area = menisci[0], menisci[7], menisci[8]
    _meniscus_terms(dt, n_on, menisci, pump, q_out)
    shortest = np.inf
    arg = -1
    for s in range(n_on):
        f = on_t[s]
        remaining = ell[f] - q_out[s] * dt / area[f]
        if remaining < shortest:
            shortest = remaining
            arg = s
    return shortest, arg


@njit(helper=True)
def _landing_step(
    dt_hi: float, ell0: float, n_on: int, menisci: tuple, pump: tuple, q_out: np.ndarray
) -> tuple[float, int]:
    """The step: ``dt_hi`` if no advancing meniscus lands within it, else the first landing.

    The smallest remaining length after a step of ``dt``, ``phi(dt)``, is continuous with
    ``phi(0) > 0``; if ``phi(dt_hi) <= 0`` its first root is bracketed and found by regula
    falsi (Illinois variant) to ``1e-14`` relative in the step or ``1e-14 l0`` in the
    length. Returns ``(dt, index in on_t of the landing meniscus or -1)``; at that ``dt``
    the landing meniscus is within ``1e-14 l0`` of 0 (it may be a hair past it, never short).
    """
    on_t, ell = menisci[0], menisci[7]
    phi_hi, arg = _shortest_remaining(dt_hi, n_on, menisci, pump, q_out)
    if phi_hi > 0.0:
        return dt_hi, -1
    lo, phi_lo = 0.0, np.inf
    for s in range(n_on):
        phi_lo = min(phi_lo, ell[on_t[s]])
    hi = dt_hi
    w_lo, w_hi = phi_lo, phi_hi  # secant weights (halved on a repeated side: Illinois)
    side = 0
    for _ in range(200):
        if hi - lo <= 1e-14 * hi or -phi_hi <= 1e-14 * ell0:
            break
        mid = hi - w_hi * (hi - lo) / (w_hi - w_lo)
        if not lo < mid < hi:
            mid = 0.5 * (lo + hi)
        phi_mid, arg_mid = _shortest_remaining(mid, n_on, menisci, pump, q_out)
        if phi_mid > 0.0:
            lo, w_lo = mid, phi_mid
            if side == -1:
                w_hi *= 0.5
            side = -1
        else:
            hi, phi_hi, w_hi, arg = mid, phi_mid, phi_mid, arg_mid
            if side == 1:
                w_lo *= 0.5
            side = 1
    return hi, arg


@njit(helper=True)
def _fluxes(
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
def _update(
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
        pn = _pore_after(dt, i, p, flux, gsum, vol, pnew)
        out += g_out[i] * pi
        stored += vol[i] * (pn - pi)
        largest = max(largest, abs(flux[i]) / vol[i])
        p[i] = pn
    return stored, out, largest


@njit(helper=True)
def _grid_flux(
    n: int, box: np.ndarray, k: int, p: np.ndarray, g_eff: np.ndarray, g_out: np.ndarray
) -> float:
    """Canonical n x n grids: explicit flux into pore ``k`` from its neighbours inside the box
    of active pores (rows ``[box[0], box[1])``, columns ``[box[2], box[3])``) and from the
    outlet; the same terms as :func:`_sweep_grid`."""
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
def _sweep_grid(
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
def _grow_box(box: np.ndarray, n: int, i: int, j: int, margin: int) -> None:
    """Extend the box to hold pore (i, j) and ``margin`` pores around it (within the grid)."""
    box[0] = min(box[0], max(i - margin, 0))
    box[1] = max(box[1], min(i + margin + 1, n))
    box[2] = min(box[2], max(j - margin, 0))
    box[3] = max(box[3], min(j + margin + 1, n))


@njit(helper=True)
def _spread(
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
                        _activate(j, act, apos, cnt)
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


@njit
def explicit_advance(
    indptr: np.ndarray,
    nbr: np.ndarray,
    thr: np.ndarray,
    tp: np.ndarray,
    g_eff: np.ndarray,
    g_num: np.ndarray,
    area: np.ndarray,
    pe: np.ndarray,
    vol: np.ndarray,
    g_out: np.ndarray,
    outlet: np.ndarray,
    grid_n: int,
    box: np.ndarray,
    p: np.ndarray,
    drained: np.ndarray,
    ell: np.ndarray,
    latched: np.ndarray,
    front: np.ndarray,
    fpos: np.ndarray,
    act: np.ndarray,
    apos: np.ndarray,
    flux: np.ndarray,
    gsum: np.ndarray,
    p_next: np.ndarray,
    on_t: np.ndarray,
    on_p: np.ndarray,
    landing: np.ndarray,
    acc: np.ndarray,
    cnt: np.ndarray,
    order: np.ndarray,
    via: np.ndarray,
    rtime: np.ndarray,
    rpress: np.ndarray,
    series: np.ndarray,
    dt_max: float,
    control: int,
    q_rate: float,
    capacity: float,
    capacity_per_drained: float,
    ramp_rate: float,
    latching: bool,
    floor: float,
    pressure_step: float,
    ell0: float,
    max_events: int,
    t_end: float,
    max_steps: int,
    stop_at_breakthrough: bool,
    step_budget: int,
) -> int:
    """Integrate until ``max_events`` pores drain or another stop (returns a :data:`STATUS` code).

    Parameters
    ----------
    indptr, nbr, thr : ndarray of int
        CSR adjacency (neighbour pore and throat of each entry).
    tp : ndarray of int, shape (M, 2)
        Pores of each throat.
    g_eff, g_num, area, pe : ndarray of float, shape (M,)
        Conductance between undrained pores ``A k / 2`` (set to 0 by :func:`drain_pore` for
        throats touching a drained pore), meniscus conductance times length ``A k``, throat
        area ``A`` and entry pressure ``2 / r``.
    vol, g_out : ndarray of float, shape (N,)
        Pore volumes and conductance to the outlet reservoir (0 for inner pores, set to 0
        when a pore drains).
    outlet : ndarray of bool, shape (N,)
        Pores whose drainage is breakthrough.
    grid_n, box : int, ndarray of int (4,)
        ``grid_n > 0`` for an ``n x n`` square grid in canonical throat order (horizontal
        throats row-major, then vertical): the pores of the box of rows ``[box[0], box[1])``
        and columns ``[box[2], box[3])`` are the active ones and are swept as a stencil.
        ``grid_n = 0``: generic lattice, active pores listed in ``act``.
    p, drained, ell, latched : state arrays, updated in place
        Pore pressures (the invader's in drained pores, as of their drainage), drained mask,
        remaining meniscus length and latched flag of each throat (meaningful on the frontier).
    front, fpos, act, apos : index lists, updated in place
        Frontier throats (``front[:cnt[2]]``, ``fpos`` their slots or -1) and active pores
        (``act[:cnt[3]]``, ``apos`` likewise).
    flux, gsum, p_next, on_t, on_p, landing : scratch, shapes (N,), (N,), (N,), (M,), (M,), (M,)
        ``gsum`` (the meniscus conductances into each pore) must be zero on entry and is
        left zero.
    acc, cnt : running totals (:data:`ACC`) and counters (:data:`CNT`), updated in place.
    order, via, rtime, rpress, series : records, appended at ``cnt[0]`` by :func:`drain_pore`.
    dt_max : float
        Largest step (the stability limit times the safety factor).
    control : int
        :data:`CONTROL_RATE`, :data:`CONTROL_PRESSURE` or :data:`CONTROL_RAMP`.
    q_rate, capacity, capacity_per_drained, ramp_rate : float
        Injection rate; reservoir compliance ``C = capacity + capacity_per_drained * V_drained``;
        ``dp_inv/dt`` of a ramp.
    latching : bool
        Meniscus rule: False for "threshold" (advance only while ``p_inv - p_i > p_e``), True
        for "latching" (once started, advance while ``p_inv > p_i``).
    floor : float
        Pressure magnitude above which a pore activates its neighbours.
    pressure_step : float
        Accuracy limit on the step: the invading pressure and the pressures of the pores
        behind advancing menisci may change by about this much per step (estimated from the
        rates at the start of the step), so that menisci start and stop near their
        thresholds. ``inf`` leaves only the stability limit.
    ell0 : float
        Length of a new meniscus (2).
    max_events, t_end, max_steps, stop_at_breakthrough
        Stops.
    step_budget : int
        Return (status 0) after this many steps in this call, so the caller can report
        progress and run observers during long stretches without drainage.
    """
    events = 0
    steps_at_entry = cnt[1]
    last_rate = np.inf  # largest |dp/dt| of the last step (for the stationarity test)
    while True:
        if events >= max_events or cnt[1] - steps_at_entry >= step_budget:
            return 0
        t = acc[0]
        if t >= t_end:
            return 2
        if cnt[1] >= max_steps:
            return 3
        nf = cnt[2]
        if nf == 0:
            return 5
        na = cnt[3]
        pinv = acc[1]
        capacity_now = capacity + capacity_per_drained * acc[7]
        if grid_n == 0:
            _fluxes(na, act, apos, indptr, nbr, thr, g_eff, g_out, p, flux)
        # Which menisci advance (decided at the start of the step): on_t[:n_on], on_p[:n_on].
        n_on = 0
        for s in range(nf):
            f = front[s]
            i = _other(tp, drained, f)
            d = pinv - p[i]
            go = d > pe[f]
            if latching:
                if go:
                    latched[f] = True
                go = latched[f] and d > 0.0
            if go:
                gsum[i] += g_num[f] / ell[f]
                on_t[n_on] = f
                on_p[n_on] = i
                n_on += 1
        if grid_n > 0:  # the grid sweep needs the explicit fluxes of the meniscus pores only
            for s in range(n_on):
                flux[on_p[s]] = _grid_flux(grid_n, box, on_p[s], p, g_eff, g_out)
        if n_on == 0 and control == CONTROL_PRESSURE and last_rate * dt_max <= floor:
            return 6
        # Step length: the stability limit, the end time, and the first meniscus to land on 0.
        # A meniscus that would recede over the step (defending fluid never flows into a
        # drained pore) carries no flux instead: it leaves the list (moved past n_on) and the
        # step is redone, so the list only shrinks.
        # The advancing menisci and the pump, as the step's helpers see them.
        menisci = (on_t, on_p, p, flux, gsum, vol, g_num, ell, area)
        pump = (control, pinv, q_rate, capacity_now, ramp_rate)
        dt_hi = min(dt_max, t_end - t)
        if pressure_step < np.inf:
            rate = _pressure_rate(n_on, menisci, pump, ell0)
            if rate * dt_hi > pressure_step:
                dt_hi = pressure_step / rate
        n_listed = n_on
        while True:
            dt, event = _landing_step(dt_hi, ell0, n_on, menisci, pump, landing)
            pnew = _meniscus_terms(dt, n_on, menisci, pump, landing)
            s = 0
            removed = False
            while s < n_on:
                if landing[s] < 0.0:
                    removed = True
                    n_on -= 1
                    f, i = on_t[s], on_p[s]
                    on_t[s], on_p[s] = on_t[n_on], on_p[n_on]
                    on_t[n_on], on_p[n_on] = f, i
                    landing[s] = landing[n_on]
                    gsum[i] = 0.0  # rebuilt from the menisci still listed
                    for r in range(n_on):
                        if on_p[r] == i:
                            gsum[i] += g_num[on_t[r]] / ell[on_t[r]]
                else:
                    s += 1
            if not removed:
                break
        # Apply the step: landing[s] now holds each advancing meniscus' flux.
        qsum = 0.0
        for s in range(n_on):
            f = on_t[s]
            q = landing[s]
            qsum += q
            ell[f] = 0.0 if s == event else ell[f] - q * dt / area[f]
        if grid_n == 0:
            stored, out, last_rate = _update(na, act, dt, pnew, p, flux, gsum, vol, g_out)
        else:
            stored, out, last_rate = _sweep_grid(grid_n, box, dt, g_eff, g_out, vol, p, p_next)
            for s in range(n_on):  # meniscus pores: implicit in the meniscus fluxes
                i = on_p[s]
                implicit = _pore_after(dt, i, p, flux, gsum, vol, pnew)
                stored += vol[i] * (implicit - p_next[i])
                p_next[i] = implicit
            for i in range(box[0], box[1]):
                start = i * grid_n
                p[start + box[2] : start + box[3]] = p_next[start + box[2] : start + box[3]]
        for s in range(n_listed):
            gsum[on_p[s]] = 0.0
        _spread(grid_n, box, na, act, apos, cnt, indptr, nbr, drained, p, floor)
        acc[3] += qsum * dt
        acc[4] += stored
        acc[5] += out * dt
        if control == CONTROL_RATE:
            acc[2] += q_rate * dt
        else:
            acc[2] += qsum * dt + capacity_now * (pnew - pinv)
        acc[8] += capacity_now * (pnew - pinv)
        acc[1] = pnew
        acc[0] = t + dt
        cnt[1] += 1
        if not (np.isfinite(pnew) and np.isfinite(stored)):
            cnt[4] = -1
            return 4
        # Drain the pore(s) whose meniscus landed on 0 (ties within round-off drain together).
        if event >= 0:
            f = on_t[event]
            i = on_p[event]
            completing = [(i, f)]
            tol = 1e-12 * ell0
            for s in range(n_on):
                f2 = on_t[s]
                if f2 != f and ell[f2] <= tol:
                    completing.append((on_p[s], f2))
            for i, f in completing:
                if drained[i]:
                    continue
                drain_pore(
                    i, f, indptr, nbr, thr, vol, ell0, g_eff, g_out, grid_n, box, p, drained,
                    ell, latched, front, fpos, act, apos, acc, cnt, order, via, rtime, rpress,
                    series,
                )  # fmt: skip
                events += 1
                if outlet[i]:
                    cnt[5] = 1
                    if stop_at_breakthrough:
                        return 1
