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
(:mod:`porenet.kinds.viscous.kernels.menisci`). The pore-to-pore part is stable for
``dt <= min_i V_i / (sum_j g_ij + g_out,i)``; the implicit part is unconditionally stable, so the
meniscus and reservoir terms never limit the step. Every flux is computed once and used for both
sides, so the volume balances close to round-off (see
:class:`~porenet.kinds.viscous.kernels.state.Total`). A step that would take a meniscus past ``l =
0`` is shortened so that the first one lands exactly on 0 (bracketed regula falsi on the step
length), and the pore drains at that instant.

Pressure spreads only through the *active* pores: undrained pores next to a meniscus or next to
an active pore whose pressure exceeds ``floor`` in magnitude. Fluxes to inactive pores are
neglected (they are below ``g * floor``), which keeps the cost proportional to the region the
pressure has reached, not to the lattice, and keeps the balances exact.

This module holds the step loop, the drainage events and the bookkeeping; the menisci and the
pump over one step are in :mod:`porenet.kinds.viscous.kernels.menisci`, the pressure diffusion over
the active pores in :mod:`porenet.kinds.viscous.kernels.diffusion`.
"""

from __future__ import annotations

import numpy as np

from porenet.jit.jit import njit
from porenet.kinds.viscous.kernels.diffusion import (
    activate,
    copy_rows,
    csr_copy,
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
from porenet.kinds.viscous.kernels.menisci import (
    invader_pressure,
    landing_step,
    pore_after,
    step_change,
    undrained_pore,
)
from porenet.kinds.viscous.kernels.state import (
    LISTS,
    WINDOWS,
    Column,
    Conductances,
    Control,
    Count,
    Flow,
    Front,
    Injection,
    Menisci,
    Network,
    Pump,
    Records,
    Scratch,
    Status,
    StepRules,
    Stops,
    Sweep,
    Total,
    book_step,
)
from porenet.kinds.viscous.kernels.window import (
    Cut,
    Mode,
    Window,
    WindowInt,
    book_explicit,
    cut,
    far_meniscus,
    far_pressure,
    inside,
    near_open_edge,
    set_ring,
)

#: The integrators' status codes, the slots of the totals and counters and the records'
#: columns are named in :mod:`porenet.kinds.viscous.kernels.state`.


@njit(helper=True)
def _unlink(n_on: int, on_p: np.ndarray, head: np.ndarray) -> None:
    """Clear the per-pore links of a step's ``n_on`` candidate menisci (``head`` is -1
    everywhere between steps and calls)."""
    for s in range(n_on):
        head[on_p[s]] = -1


@njit(helper=True)
def _list_meniscus(f: int, i: int, c: float, n_on: int, menisci: Menisci) -> int:
    """Append meniscus ``f`` into pore ``i`` with threshold ``c`` to the step's candidates
    (and to pore ``i``'s links); return the new count."""
    menisci.throat[n_on] = f
    menisci.pore[n_on] = i
    menisci.threshold[n_on] = c
    menisci.next[n_on] = menisci.head[i]
    menisci.head[i] = n_on
    return n_on + 1


@njit
def drain_pore(
    pore: int,
    via: int,
    net: Network,
    cond: Conductances,
    flow: Flow,
    front: Front,
    records: Records,
    new_meniscus: float,
) -> None:
    """Drain ``pore`` through throat ``via`` (-1 for an inlet) at the current time.

    Its stored volume ``V_i p_i`` is released, the menisci entering it vanish, menisci of
    length ``new_meniscus`` appear in its throats to undrained neighbours (which become
    active), and the event is appended to the records. Its throats stop conducting between
    pores (:attr:`Conductances.between`) and it stops draining to the outlet. On grids the
    active box grows to hold it and its neighbours.
    """
    p, totals, counters = flow.pressure, flow.totals, flow.counters
    flow.drained[pore] = True
    released = net.volume[pore] * p[pore]
    totals[Total.RELEASED] += released
    totals[Total.STORED_DEFENDER] -= released
    totals[Total.DRAINED_PORE_VOLUME] += net.volume[pore]
    p[pore] = totals[Total.INVADING_PRESSURE]
    cond.outlet[pore] = 0.0
    set_remove(pore, front.pores, front.pore_slot, counters, Count.N_ACTIVE)
    n = net.grid_n
    if n > 0:
        grow_box(front.box, n, pore // n, pore % n, 1)
    for e in range(net.indptr[pore], net.indptr[pore + 1]):
        j = net.neighbour[e]
        t = net.throat[e]
        cond.between[t] = 0.0
        if flow.drained[j]:
            set_remove(t, front.throats, front.throat_slot, counters, Count.N_FRONT)
        else:
            flow.meniscus_length[t] = new_meniscus
            flow.latched[t] = False
            set_add(t, front.throats, front.throat_slot, counters, Count.N_FRONT)
            activate(j, front.pores, front.pore_slot, counters)
    k = counters[Count.EVENTS]
    records.order[k] = pore
    records.via[k] = via
    row = records.series[k]
    row[Column.TIME] = totals[Total.TIME]
    row[Column.INVADING_PRESSURE] = totals[Total.INVADING_PRESSURE]
    row[Column.INJECTED] = totals[Total.INJECTED]
    row[Column.DRAINED] = totals[Total.DRAINED]
    row[Column.STORED] = (
        totals[Total.STORED_DEFENDER] + totals[Total.STORED_RESERVOIR] + totals[Total.IN_TRANSIT]
    )
    row[Column.OUTFLOW] = totals[Total.OUTFLOW]
    row[Column.RELEASED] = totals[Total.RELEASED]
    row[Column.N_DRAINED] = k + 1
    counters[Count.EVENTS] = k + 1


@njit
def drain_inlets(
    inlets: np.ndarray,
    net: Network,
    cond: Conductances,
    flow: Flow,
    front: Front,
    records: Records,
    new_meniscus: float,
) -> None:
    """Drain the ``inlets`` (int64), in their order, at the start of a run: each as
    :func:`drain_pore` with no throat. (A kernel of its own, so that a first run compiles
    :func:`drain_pore` once, as the integrators call it, and not a second time for Python.)"""
    for pore in inlets:
        drain_pore(pore, -1, net, cond, flow, front, records, new_meniscus)


@njit
def explicit_advance(
    net: Network,
    cond: Conductances,
    flow: Flow,
    front: Front,
    records: Records,
    scratch: Scratch,
    injection: Injection,
    rules: StepRules,
    stops: Stops,
    window: Window,
) -> int:
    """Integrate until ``stops.max_events`` pores drain or another stop; returns a
    :class:`~porenet.kinds.viscous.kernels.state.Status`.

    Reads ``net`` and ``injection``, ``rules`` and ``stops`` (:mod:`porenet.kinds.viscous.kernels.
    state`); advances ``flow`` (pressures, menisci, totals, counters), ``front`` (frontier,
    active pores and box), ``cond`` (a drained pore's throats stop conducting) and appends to
    ``records``; ``scratch`` is work space, left clean.

    The pores swept are the active box (grids) or the listed active pores, except in the fine
    integration of a macro step of local time steps (``window`` in mode FINE,
    :mod:`porenet.kinds.viscous.kernels.window`): then only the window's box is swept, the ring
    around it is read at each step's start and books the volume it receives, and the call
    ends with ``Status.CUT`` when a meniscus outside the window may start or a pore drains
    near its edge. ``window`` is off (:func:`porenet.kinds.viscous.kernels.window.no_window`)
    otherwise.
    """
    indptr, nbr, thr, tp = net.indptr, net.neighbour, net.throat, net.throat_pores
    vol, inv_vol, outlet, grid_n = net.volume, net.inverse_volume, net.outlet, net.grid_n
    g_eff, g_num, area, entry, g_out = cond
    p, drained, ell, latched, totals, counters = flow
    act, apos, nbox = front.pores, front.pore_slot, front.box
    flux, p_next = scratch.flux, scratch.next_pressure
    on_t, on_p, head = scratch.meniscus_throat, scratch.meniscus_pore, scratch.head
    landing = scratch.meniscus_flux  # each candidate's flux over the step
    control, q_rate, capacity, capacity_per_drained, ramp_rate = injection
    dt_max, latching, floor, pressure_step, ell0 = rules
    events = 0
    steps_at_entry = counters[Count.STEPS]
    # The candidate menisci of a step: thresholds, and per-pore links (head[i] -> nxt ...).
    c_on = scratch.threshold
    nxt = scratch.next_candidate
    near = scratch.near  # slots in front of menisci near their threshold
    last_rate = totals[Total.LAST_RATE]  # largest |dp/dt| of the last step (stationarity)
    dt_next = totals[Total.DT_NEXT]  # the step the accuracy limit predicts
    windowed = WINDOWS and window.ints[WindowInt.MODE] == Mode.FINE
    box = window.box if windowed else nbox  # the pores swept
    while True:
        totals[Total.DT_NEXT] = dt_next
        totals[Total.LAST_RATE] = last_rate
        if (
            events >= stops.max_events
            or counters[Count.STEPS] - steps_at_entry >= stops.step_budget
        ):
            return Status.BUDGET
        t = totals[Total.TIME]
        if t >= stops.t_end:
            return Status.END_TIME
        if counters[Count.STEPS] >= stops.max_steps:
            return Status.STEP_LIMIT
        nf = counters[Count.N_FRONT]
        if nf == 0:
            return Status.NO_MENISCUS
        na = counters[Count.N_ACTIVE]
        pinv = totals[Total.INVADING_PRESSURE]
        capacity_now = capacity + capacity_per_drained * totals[Total.DRAINED_PORE_VOLUME]
        dt_hi = min(dt_max, stops.t_end - t)
        if windowed:
            set_ring(window, p, t)
        # the pores swept (the box, or the listed active pores) and what the sweep reads
        field = Sweep(grid_n, box, na, act, apos, indptr, nbr, thr, g_eff, g_out, inv_vol, flux,
                      nbox)  # fmt: skip
        if LISTS and grid_n == 0:
            csr_fluxes(field, p, flux)
        # The candidate menisci of the step, on_t[:n_on] into pores on_p[:n_on] with
        # thresholds c_on: those that may flow by its end (menisci.py: each one flows, slides
        # on its threshold or stops, by the end-of-step pressures). Rule "latching": a
        # meniscus that has ever exceeded its entry pressure, with threshold 0 from then on.
        # Rule "threshold": first those at or above their entry pressure (a sliding one sits
        # on it); then those within reach of it as the invading pressure rises over the step
        # (to what it would reach with the first ones alone).
        menisci = Menisci(on_t, on_p, c_on, head, nxt, p, flux, vol, g_num, ell, area)
        pump = Pump(control, pinv, q_rate, capacity_now, ramp_rate)
        # the most the invading pressure can rise in the step (the pump alone)
        reach = dt_hi * max(q_rate / capacity_now if control == Control.RATE else 0.0, ramp_rate)
        if windowed:  # the macro step ends before a meniscus outside the window may start
            k = far_meniscus(window, pinv, reach, t, entry, tp, drained)
            if k >= 0:
                return cut(window, Cut.FAR_MENISCUS, k)
        n_on = 0
        n_near = 0  # below their threshold by less than reach: near[:n_near]
        for s in range(nf):
            f = front.throats[s]
            i = undrained_pore(tp, drained, f)
            if windowed and not inside(window.box, grid_n, i):
                # outside the window: the macro step ends before this meniscus may start
                d = pinv - far_pressure(window, i, t)
                if (latching and latched[f]) or d > entry[f] - reach:
                    _unlink(n_on, on_p, head)
                    return cut(window, Cut.FAR_MENISCUS, i)
                continue
            d = pinv - p[i]
            if latching:
                if d > entry[f]:
                    latched[f] = True
                if latched[f]:
                    n_on = _list_meniscus(f, i, 0.0, n_on, menisci)
            elif d > entry[f] * (1.0 - 1e-9):
                n_on = _list_meniscus(f, i, entry[f], n_on, menisci)
            elif d > entry[f] - reach:
                near[n_near] = s
                n_near += 1
        n_sure = n_on
        if grid_n > 0:  # the grid sweep needs the explicit fluxes of the meniscus pores only
            for s in range(n_on):
                flux[on_p[s]] = grid_flux(grid_n, nbox, on_p[s], p, g_eff, g_out)
        if n_near > 0:
            rise = invader_pressure(dt_hi, n_on, menisci, pump) - pinv
            for r in range(n_near):
                f = front.throats[near[r]]
                i = undrained_pore(tp, drained, f)
                if pinv - p[i] > entry[f] - rise:
                    n_on = _list_meniscus(f, i, entry[f], n_on, menisci)
            if grid_n > 0:
                for s in range(n_sure, n_on):
                    flux[on_p[s]] = grid_flux(grid_n, nbox, on_p[s], p, g_eff, g_out)
        if control == Control.PRESSURE and last_rate * dt_max <= floor:
            _unlink(n_on, on_p, head)
            return Status.STATIONARY
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
        if LISTS and grid_n == 0:
            stored, out, largest = csr_update(field, dt, p, p_next, vol)
        else:
            stored, out = grid_sweep(field, dt, vol, p, p_next)
            largest = 0.0
            if windowed:
                totals[Total.IN_TRANSIT] += book_explicit(window, p, g_eff, dt)
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
        if control == Control.PRESSURE:
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
        if LISTS and grid_n == 0:
            csr_copy(field, p_next, p)
        else:
            copy_rows(grid_n, box, p_next, p)
        _unlink(n_on, on_p, head)
        if not windowed:
            spread(field, front.settled, counters, drained, p, floor)
        book_step(flow, pump, dt, qsum * dt, stored, out * dt, pnew)
        if not (np.isfinite(pnew) and np.isfinite(stored)):
            counters[Count.WHERE] = -1
            return Status.NON_FINITE
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
                drain_pore(i, f, net, cond, flow, front, records, ell0)
                events += 1
                if outlet[i]:
                    counters[Count.BREAKTHROUGH] = 1
                    if stops.at_breakthrough:
                        return Status.BREAKTHROUGH
                if windowed and near_open_edge(window, nbox, grid_n, i):
                    edge = i
            if edge >= 0:
                return cut(window, Cut.NEAR_EDGE, edge)
