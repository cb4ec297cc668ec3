"""Kernels of the dynamic viscous drainage model (docs/model.md section 4).

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
pores and to the outlet, and point-implicit (backward Euler) for the meniscus fluxes, the pores
they enter and the injection reservoir, which are the stiff terms (a meniscus conductance
``A k / l`` grows without bound as ``l -> 0``; a small C makes the reservoir stiff). The
threshold law is used in its convex closure, so a meniscus at its threshold slides
(:mod:`porenet.kernels.viscous.menisci`). The pore-to-pore part is stable for
``dt <= min_i V_i / (sum_j g_ij + g_out,i)``; the implicit part is unconditionally stable, so the
meniscus and reservoir terms never limit the step. Every flux is computed once and used for both
sides, so the volume balances close to round-off (see :data:`ACC`). A step that would take a
meniscus past ``l = 0`` is shortened so that the first one lands exactly on 0 (bracketed
regula falsi on the step length), and the pore drains at that instant.

Pressure spreads only through the *active* pores: undrained pores next to a meniscus or next to
an active pore whose pressure exceeds ``floor`` in magnitude. Fluxes to inactive pores are
neglected (they are below ``g * floor``), which keeps the cost proportional to the region the
pressure has reached, not to the lattice, and keeps the balances exact.

This module holds the step loop, the drainage events and the bookkeeping; the menisci and the
pump over one step are in :mod:`porenet.kernels.viscous.menisci`, the pressure diffusion over the
active pores in :mod:`porenet.kernels.viscous.diffusion`.
"""

from __future__ import annotations

import numpy as np

from porenet.kernels._jit import njit
from porenet.kernels.viscous.diffusion import (
    activate,
    copy_rows,
    csr_fluxes,
    csr_update,
    grid_flux,
    grid_largest_rate,
    grid_sweep,
    grow_box,
    set_add,
    set_remove,
    spread,
)
from porenet.kernels.viscous.menisci import (
    CONTROL_PRESSURE,
    CONTROL_RATE,
    invader_pressure,
    landing_step,
    pore_after,
    step_change,
    undrained_pore,
)
from porenet.kernels.viscous.window import (
    CUT_FAR_MENISCUS,
    CUT_NEAR_EDGE,
    FINE,
    book_explicit,
    cut,
    far_meniscus,
    far_pressure,
    inside,
    near_open_edge,
    set_ring,
)

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
    # carried from one call to the next, so that a run does not depend on how it is chunked
    "dt_next": 9,  # the step the accuracy limit predicts (inf before the first step)
    "last_rate": 10,  # largest |dp/dt| of the last step (pressure control; inf at first)
    # local time steps: volume carried out of the window in the current macro step, which
    # the far field receives (as stored volume or outflow) at its end
    "in_transit": 11,
}
N_ACC = 12

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


@njit(helper=True)
def _unlink(n_on: int, on_p: np.ndarray, head: np.ndarray) -> None:
    """Clear the per-pore links of a step's ``n_on`` candidate menisci (``head`` is -1
    everywhere between steps and calls)."""
    for s in range(n_on):
        head[on_p[s]] = -1


@njit(helper=True)
def _list_meniscus(
    f: int,
    i: int,
    c: float,
    n_on: int,
    on_t: np.ndarray,
    on_p: np.ndarray,
    c_on: np.ndarray,
    head: np.ndarray,
    nxt: np.ndarray,
) -> int:
    """Append meniscus ``f`` into pore ``i`` with threshold ``c`` to the step's candidates
    (and to pore ``i``'s links); return the new count."""
    on_t[n_on] = f
    on_p[n_on] = i
    c_on[n_on] = c
    nxt[n_on] = head[i]
    head[i] = n_on
    return n_on + 1


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
    set_remove(i, act, apos, cnt, 3)
    if grid_n > 0:
        grow_box(box, grid_n, i // grid_n, i % grid_n, 1)
    for e in range(indptr[i], indptr[i + 1]):
        j = nbr[e]
        t = thr[e]
        g_eff[t] = 0.0
        if drained[j]:
            set_remove(t, front, fpos, cnt, 2)
        else:
            ell[t] = ell0
            latched[t] = False
            set_add(t, front, fpos, cnt, 2)
            activate(j, act, apos, cnt)
    k = cnt[0]
    order[k] = i
    via[k] = f
    series[k, 0] = acc[0]
    series[k, 1] = acc[1]
    series[k, 2] = acc[2]
    series[k, 3] = acc[3]
    series[k, 4] = acc[4] + acc[8] + acc[11]
    series[k, 5] = acc[5]
    series[k, 6] = acc[6]
    series[k, 7] = k + 1
    cnt[0] = k + 1


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
    p_next: np.ndarray,
    on_t: np.ndarray,
    on_p: np.ndarray,
    landing: np.ndarray,
    acc: np.ndarray,
    cnt: np.ndarray,
    order: np.ndarray,
    via: np.ndarray,
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
    nbox: np.ndarray,
    win: tuple,
    head: np.ndarray,
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
    flux, p_next, on_t, on_p, landing : scratch, shapes (N,), (N,), (M,), (M,), (M,)
    acc, cnt : running totals (:data:`ACC`) and counters (:data:`CNT`), updated in place.
    order, via, series : records, appended at ``cnt[0]`` by :func:`drain_pore` (the drainage
        time and invading pressure of each event are ``series[:, 0]`` and ``series[:, 1]``).
    dt_max : float
        Largest step (the stability limit times the safety factor).
    control : int
        ``CONTROL_RATE``, ``_PRESSURE`` or ``_RAMP`` of :mod:`porenet.kernels.viscous.menisci`.
    q_rate, capacity, capacity_per_drained, ramp_rate : float
        Injection rate; reservoir compliance ``C = capacity + capacity_per_drained * V_drained``;
        ``dp_inv/dt`` of a ramp.
    latching : bool
        Meniscus rule: False for "threshold" (advance only while ``p_inv - p_i > p_e``), True
        for "latching" (once started, advance while ``p_inv > p_i``).
    floor : float
        Pressure magnitude above which a pore activates its neighbours.
    pressure_step : float
        Accuracy limit on the step: the invading pressure and the pressure difference across
        each candidate meniscus change by at most this much per step (checked on the solved
        step, which is redone shorter if needed), so that menisci start near their
        thresholds. ``inf`` leaves only the stability limit.
    ell0 : float
        Length of a new meniscus (2).
    max_events, t_end, max_steps, stop_at_breakthrough
        Stops.
    step_budget : int
        Return (status 0) after this many steps in this call, so the caller can report
        progress and run observers during long stretches without drainage.
    nbox, win : ndarray of int (4,), tuple
        ``box`` itself and a window that is off (:func:`porenet.kernels.viscous.window.no_window`),
        except in the fine integration of a macro step of local time steps
        (:mod:`porenet.kernels.viscous.multirate`): then ``box`` is the window (it does not grow),
        ``nbox`` the active box, the ring around the window is read at each step's start
        and books the volume it receives, and the call ends with
        :data:`porenet.kernels.viscous.window.CUT` when a meniscus outside the window may start or a
        pore drains near its edge.
    head : ndarray of int, shape (N,)
        Scratch, -1 everywhere on entry and on return (the per-pore links of a step's
        candidates; kept by the caller so that a call allocates nothing of size N).
    """
    events = 0
    steps_at_entry = cnt[1]
    inv_vol = 1.0 / vol  # the grid sweep multiplies (a division per pore would dominate it)
    # The candidate menisci of a step: thresholds, and per-pore links (head[i] -> nxt ...).
    c_on = np.empty(len(on_t))
    nxt = np.empty(len(on_t), dtype=np.int64)
    near = np.empty(len(on_t), dtype=np.int64)  # slots in front of menisci near threshold
    last_rate = acc[10]  # largest |dp/dt| of the last step (for the stationarity test)
    dt_next = acc[9]  # the step the accuracy limit predicts
    windowed = win[0][0] == FINE
    while True:
        acc[9] = dt_next
        acc[10] = last_rate
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
        dt_hi = min(dt_max, t_end - t)
        if windowed:
            set_ring(win, p, t)
        if grid_n == 0:
            csr_fluxes(na, act, apos, indptr, nbr, thr, g_eff, g_out, p, flux)
        # The candidate menisci of the step, on_t[:n_on] into pores on_p[:n_on] with
        # thresholds c_on: those that may flow by its end (menisci.py: each one flows, slides
        # on its threshold or stops, by the end-of-step pressures). Rule "latching": a
        # meniscus that has ever exceeded its entry pressure, with threshold 0 from then on.
        # Rule "threshold": first those at or above their entry pressure (a sliding one sits
        # on it); then those within reach of it as the invading pressure rises over the step
        # (to what it would reach with the first ones alone).
        menisci = (on_t, on_p, c_on, head, nxt, p, flux, vol, g_num, ell, area)
        pump = (control, pinv, q_rate, capacity_now, ramp_rate)
        # the most the invading pressure can rise in the step (the pump alone)
        reach = dt_hi * max(q_rate / capacity_now if control == CONTROL_RATE else 0.0, ramp_rate)
        if windowed:  # the macro step ends before a meniscus outside the window may start
            k = far_meniscus(win, pinv, reach, t, pe, tp, drained)
            if k >= 0:
                return cut(win, CUT_FAR_MENISCUS, k)
        n_on = 0
        n_near = 0  # below their threshold by less than reach: near[:n_near]
        for s in range(nf):
            f = front[s]
            i = undrained_pore(tp, drained, f)
            if windowed and not inside(win[2], grid_n, i):
                # outside the window: the macro step ends before this meniscus may start
                d = pinv - far_pressure(win, i, t)
                if (latching and latched[f]) or d > pe[f] - reach:
                    _unlink(n_on, on_p, head)
                    return cut(win, CUT_FAR_MENISCUS, i)
                continue
            d = pinv - p[i]
            if latching:
                if d > pe[f]:
                    latched[f] = True
                if latched[f]:
                    n_on = _list_meniscus(f, i, 0.0, n_on, on_t, on_p, c_on, head, nxt)
            elif d > pe[f] * (1.0 - 1e-9):
                n_on = _list_meniscus(f, i, pe[f], n_on, on_t, on_p, c_on, head, nxt)
            elif d > pe[f] - reach:
                near[n_near] = s
                n_near += 1
        n_sure = n_on
        if grid_n > 0:  # the grid sweep needs the explicit fluxes of the meniscus pores only
            for s in range(n_on):
                flux[on_p[s]] = grid_flux(grid_n, nbox, on_p[s], p, g_eff, g_out)
        if n_near > 0:
            rise = invader_pressure(dt_hi, n_on, menisci, pump) - pinv
            for r in range(n_near):
                f = front[near[r]]
                i = undrained_pore(tp, drained, f)
                if pinv - p[i] > pe[f] - rise:
                    n_on = _list_meniscus(f, i, pe[f], n_on, on_t, on_p, c_on, head, nxt)
            if grid_n > 0:
                for s in range(n_sure, n_on):
                    flux[on_p[s]] = grid_flux(grid_n, nbox, on_p[s], p, g_eff, g_out)
        if control == CONTROL_PRESSURE and last_rate * dt_max <= floor:
            _unlink(n_on, on_p, head)
            return 6
        # Step length: the stability limit, the end time, the accuracy limit, and the first
        # meniscus to land on 0.
        # The accuracy limit is checked on the solved step, before the pressures are swept:
        # a step that changes the invading pressure or a pressure difference across a
        # candidate meniscus by more than pressure_step is redone shorter; the next step is
        # predicted from the last one's rate of change.
        dt_hi = min(dt_hi, dt_next)
        while True:
            dt, event, pnew = landing_step(dt_hi, ell0, n_on, menisci, pump, landing)
            change = step_change(dt, pnew, n_on, menisci, pinv)
            if not change > pressure_step:  # (a NaN ends the loop; it is reported below)
                break
            dt_hi = 0.9 * dt * pressure_step / change
        dt_next = dt_max if change == 0.0 else max(dt, 0.9 * dt * pressure_step / change)
        if grid_n == 0:
            stored, out, largest = csr_update(na, act, dt, p, p_next, flux, vol, g_out)
        else:
            stored, out = grid_sweep(grid_n, box, nbox, dt, g_eff, g_out, vol, inv_vol, p, p_next)
            largest = 0.0
            if windowed:
                acc[11] += book_explicit(win, p, g_eff, dt)
        for s in range(n_on):  # meniscus pores: implicit in the meniscus fluxes
            i = on_p[s]
            if head[i] == s:  # each pore once
                implicit = pore_after(i, pnew, dt, menisci)
                stored += vol[i] * (implicit - p_next[i])
                p_next[i] = implicit
        # A pressure-controlled run is stationary once no pressure changes and no meniscus
        # moves by more than the floor per step (the largest |dp/dt| and meniscus flux per
        # pore volume); not needed otherwise, and on grids it costs a pass over the box.
        last_rate = np.inf
        if control == CONTROL_PRESSURE:
            if grid_n > 0:
                largest = grid_largest_rate(grid_n, box, dt, p, p_next)
            for s in range(n_on):
                i = on_p[s]
                largest = max(largest, abs(p_next[i] - p[i]) / dt, landing[s] / vol[i])
            last_rate = largest
        # Advance the menisci: landing[s] holds each candidate's flux (0 if stopped).
        qsum = 0.0
        for s in range(n_on):
            f = on_t[s]
            q = landing[s]
            qsum += q
            if s == event:
                ell[f] = 0.0
            elif q > 0.0:
                ell[f] -= q * dt / area[f]
        if grid_n == 0:
            for s in range(na):
                p[act[s]] = p_next[act[s]]
        else:
            copy_rows(grid_n, box, p_next, p)
        _unlink(n_on, on_p, head)
        if not windowed:
            spread(grid_n, box, na, act, apos, cnt, indptr, nbr, drained, p, floor)
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
            edge = -1
            for i, f in completing:
                if drained[i]:
                    continue
                drain_pore(
                    i, f, indptr, nbr, thr, vol, ell0, g_eff, g_out, grid_n, nbox, p, drained,
                    ell, latched, front, fpos, act, apos, acc, cnt, order, via, series,
                )  # fmt: skip
                events += 1
                if outlet[i]:
                    cnt[5] = 1
                    if stop_at_breakthrough:
                        return 1
                if windowed and near_open_edge(win, nbox, grid_n, i):
                    edge = i
            if edge >= 0:
                return cut(win, CUT_NEAR_EDGE, edge)
