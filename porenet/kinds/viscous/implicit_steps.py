"""The implicit integrator of the viscous model: backward Euler, sliding menisci and located
events (docs/model.md section 4).

Scaled units and equations as in :mod:`porenet.kinds.viscous.kernels.explicit`. One step of length
``dt`` solves, for every undrained pore i (drained pores are decoupled rows that keep their value),

    (V_i/dt + g_out,i + sum_j g_ij) p_i' - sum_j g_ij p_j' = V_i p_i / dt + sum_{m into i} q_m

with the menisci and the injection reservoir implicit too. A threshold meniscus (conductance
``G = A k / l`` at the start of the step, entry pressure ``pe``, ``D' = p_inv' - p_i'``) is, at
the end of the step, in one of three states, a monotone complementarity problem that is the
Filippov (sliding) solution of the discontinuous threshold law, so menisci never chatter:

* OFF: ``q = 0``, requires ``D' <= pe``;
* SLIDE: ``D' = pe`` (a constraint; its flux ``q = lambda`` is a Lagrange multiplier),
  requires ``0 <= lambda <= G pe``;
* ON: ``q = G D'``, requires ``D' >= pe``.

A latched meniscus (rule "latching") is ON (``q = G D'``, ``D' >= 0``) or ZERO (stored as OFF:
``q = 0``, ``D' <= 0``); it never slides (its flux is continuous). Rate control adds the
unknown ``p_inv'`` and ``(C/dt)(p_inv' - p_inv) = Q - sum q``; pressure and ramp control know
``p_inv'``. The problem is the minimisation of a strictly convex function, so it has exactly
one solution; an active-set iteration finds it (solve for a guessed set of states, switch the
menisci whose conditions fail, repeat; start from the previous step's states).

Linear algebra: the pore matrix ``K = V/dt + L`` (all pores, a fixed sparsity pattern; drained
pores are decoupled) is factorised once per step length (SuperLU with ``scipy.sparse``); the
menisci and the reservoir enter through a small dense Schur complement: ``p' = K^{-1} b +
K^{-1} E q``, one extra solve per pore with a non-OFF meniscus. Switching states costs no new
factorisation.

Events, both located by Illinois regula falsi on the step length (as :func:`landing_step` in
:mod:`porenet.kinds.viscous.kernels.menisci` does for the explicit scheme), on
``h(dt) = min(min_m (l_m - q_m dt / A_m) / l0, min_m' (pe_m' - D'_m') / pe_m')``:

* landing: an advancing meniscus' remaining length reaches 0. The pore drains at the end of
  the located step; menisci within the tolerance of 0 (and within ``1e-12 l0``) drain
  together. Each landing meniscus' flux over the step is corrected by the remaining length
  (at most the event tolerance) so that it ends exactly at 0 and the swept volume equals
  the displaced volume; the correction is booked in the pore (which drains at once) and in
  the reservoir, so every balance stays exact.
* start: a meniscus that is OFF at the start of the step (and so held OFF within it) would
  exceed its entry pressure: the step stops at the crossing and the meniscus is armed (it may
  slide or advance from the next step on; under "latching" it latches there).

An event is located when the bracket is below ``event_tolerance`` of the step, or when the
secant estimate of the distance to the root is. Every other meniscus keeps ``l >= 0``.

Decisions (see also docs/stability.md and docs/accuracy.md):

* Which menisci are OFF is decided by the end-of-step values except for those OFF at the
  start of a step: those stay OFF within it and start only at a located crossing, so the
  start time is exact to the event tolerance and not smeared over a step.
* Local error per step: ``err = 0.5 max |x' - x - dt f(x)|`` over the undrained pore
  pressures and ``p_inv`` (``f`` the rates at the start of the step), relative to the
  entry-pressure spread ``pressure_scale``. A meniscus armed at the start of the step that
  starts clearly past its threshold counts as ON in ``f``; one that starts sliding counts
  with its end-of-step flux (the jump of the flux at its start is an event, not an error of
  the step; counting it as 0 made every start cost 2-3 rejected steps). Accept if
  ``err <= tolerance``; next step ``dt min(5, 0.9 sqrt(tol / err))`` (growth cap 5: against
  2 it saved ~15 % of the steps at n = 20), a rejected step shrinks by
  ``max(0.2, 0.9 sqrt(tol / err))``.
* The step after a drainage event restarts from ``tolerance * pressure_scale / max |f|`` (the
  step at which the fastest explicit rate changes a pressure by the tolerance; the explicit
  stability limit was too long after Haines jumps at Ca = 1e-3 and cost 2-3 rejections), at
  least ``1e-6 dt_min`` and at most the step before the event.
* A trial step is cut to 1.05 times the predicted time of the next event (landings from the
  meniscus fluxes at the start of the step, starts from the start-of-step rate of change of
  ``D``), so that the event lies close to the end of the bracket and the secant locates it
  in one or two solves.
* Stationary (``Status.STATIONARY``, pressure control only): over a stable step ``dt_min``,
  no pressure changes by more than ``floor`` (at least 1e-15; the rate is ``(p' - p)/dt`` at
  the end of the last step, exact for backward Euler) and no meniscus moves by more than
  ``floor`` (in units of a; a meniscus sliding into a trapped cluster slows to a stop but
  stays SLIDE).
* Active-set iterations are capped at 60 (the last 40 switch one meniscus at a time, the most
  violating one; one step's problem and its iteration are
  :mod:`porenet.kinds.viscous.implicit_solve`); a step whose states do not settle is
  retried at a quarter of the length, and below ``1e-9 dt_min`` the run stops with
  ``Status.NOT_SETTLED``.

Length (over the ~500 lines of docs/architecture.md's rule): its docstring (the scheme and its
decisions) is ~80 lines; the code is ~440. One step's complementarity problem is apart
(implicit_solve.py).
"""

from __future__ import annotations

import math
from enum import IntEnum
from typing import Any, NamedTuple

import numpy as np

from porenet.kinds.viscous.implicit_solve import OFF, ON, SLIDE, StepProblem
from porenet.kinds.viscous.kernels.explicit import drain_pore
from porenet.kinds.viscous.kernels.grid_cholesky import grid_cholesky_symbolic
from porenet.kinds.viscous.kernels.pore_matrix import (
    error_and_storage,
    pore_matrix_pattern,
    start_rates,
)
from porenet.kinds.viscous.kernels.state import (
    Conductances,
    Control,
    Count,
    Flow,
    Front,
    Injection,
    Network,
    Pump,
    Records,
    Status,
    Stops,
    Total,
    book_step,
)


class Slot(IntEnum):
    """Slots of :attr:`ImplicitSolver.memory`: the integrator's memory between calls, and its
    counters."""

    DT = 0  #: the next step (0 before the first call)
    RESTART = 1  #: 1: the next step restarts (after an event)
    LAST_RATE = 2  #: the largest |dp/dt| of the last step (stationarity)
    SOLVES = 3  #: linear solves
    REJECTED = 4  #: rejected steps
    FACTORIZATIONS = 5
    LOCATED = 6  #: events located
    ITERATIONS = 7  #: active-set iterations


#: Set to a list to record one tuple per trial step (debugging and benchmarks).
TRACE: list | None = None

_PREDICT_MARGIN = 1.05
_GROWTH = 5.0


# -- the stepper ----------------------------------------------------------------------------------


class ImplicitSolver(NamedTuple):
    """The implicit integrator's state between calls and its parameters.

    Attributes
    ----------
    states : ndarray of int8, shape (M,)
        State of each frontier meniscus (:data:`OFF`, :data:`SLIDE`, :data:`ON`) at the end of
        the last step (0 for new menisci).
    fluxes : ndarray of float64, shape (M,)
        Each frontier meniscus' flux over the last step (a sliding meniscus' flux at the start
        of the next step).
    memory : ndarray of float64, shape (len(Slot),)
        By :class:`Slot`: next step, restart flag, last rate, counts of solves, rejected steps
        and factorisations; all 0 before the first call.
    cache : dict
        Holds the pore-matrix pattern between calls (filled on the first call).
    latching : bool
        Meniscus rule "latching".
    new_meniscus : float
        Length of a new meniscus.
    dt_min : float
        The explicit stability limit: the smallest restart step.
    pressure_scale : float
        The entry-pressure spread (gamma/a), the unit of ``tolerance``.
    tolerance, event_tolerance : float
        Local error per step (fraction of ``pressure_scale``) and relative precision of the
        located events in time.
    floor : float
        Stationarity threshold (pressure control): see the module docstring.
    """

    states: np.ndarray
    fluxes: np.ndarray
    memory: np.ndarray
    cache: dict[str, Any]
    latching: bool
    new_meniscus: float
    dt_min: float
    pressure_scale: float
    tolerance: float
    event_tolerance: float
    floor: float


def implicit_advance(
    net: Network,
    cond: Conductances,
    flow: Flow,
    front: Front,
    records: Records,
    injection: Injection,
    stops: Stops,
    solver: ImplicitSolver,
) -> int:
    """Integrate with backward Euler until ``stops.max_events`` pores drain or another stop;
    returns a :class:`~porenet.kinds.viscous.kernels.state.Status`. The same state as
    :func:`porenet.kinds.viscous.kernels.explicit.explicit_advance`, updated in the same way (so
    both integrators leave the same records), and the integrator's own ``solver``.
    """
    indptr, nbr, thr, tp = net.indptr, net.neighbour, net.throat, net.throat_pores
    vol, outlet, grid_n = net.volume, net.outlet, net.grid_n
    g_eff, g_num, area, pe, g_out = cond
    p, drained, ell, latched, acc, cnt = flow
    mstate, mflux, ctrl, cache = solver.states, solver.fluxes, solver.memory, solver.cache
    latching, ell0, dt_min = solver.latching, solver.new_meniscus, solver.dt_min
    control, q_rate, capacity = injection.control, injection.rate, injection.capacity
    capacity_per_drained, ramp_rate = injection.capacity_per_drained, injection.ramp_rate
    max_events, t_end, max_steps = stops.max_events, stops.t_end, stops.max_steps
    stop_at_breakthrough, step_budget = stops.at_breakthrough, stops.step_budget
    tolerance, event_tolerance = solver.tolerance, solver.event_tolerance
    pressure_scale, floor = solver.pressure_scale, solver.floor
    if "pattern" not in cache:
        cache["pattern"] = pore_matrix_pattern(indptr, nbr)
        if grid_n > 0 and cache.get("grid_cholesky", True):
            cache["pattern"]["fronts"] = grid_cholesky_symbolic(grid_n, indptr, nbr)
    n = len(indptr) - 1
    tol_abs = tolerance * pressure_scale
    rate = np.zeros(n)
    events = 0
    steps_at_entry = cnt[Count.STEPS]
    if ctrl[Slot.DT] <= 0.0:
        ctrl[Slot.DT] = dt_min
        ctrl[Slot.RESTART] = 1.0
        ctrl[Slot.LAST_RATE] = math.inf
    stationary_floor = max(floor, 1e-15)
    while True:
        if events >= max_events or cnt[Count.STEPS] - steps_at_entry >= step_budget:
            return Status.BUDGET
        t = acc[Total.TIME]
        if t >= t_end:
            return Status.END_TIME
        if cnt[Count.STEPS] >= max_steps:
            return Status.STEP_LIMIT
        nf = int(cnt[Count.N_FRONT])
        if nf == 0:
            return Status.NO_MENISCUS
        pinv = float(acc[Total.INVADING_PRESSURE])
        cap = capacity + capacity_per_drained * acc[Total.DRAINED_PORE_VOLUME]
        fthr = front.throats[:nf].copy()
        fpore = np.where(drained[tp[fthr, 0]], tp[fthr, 1], tp[fthr, 0])
        pe_f = pe[fthr]
        delta0 = pinv - p[fpore]
        # arm the held menisci already at (or past) their threshold
        st = mstate[fthr]
        if latching:
            newly = ~latched[fthr] & (delta0 > pe_f * (1.0 - 1e-12))
            latched[fthr[newly]] = True
            st[newly] = ON
            latch_f = latched[fthr].copy()
            free = latch_f
        else:
            newly = (st == OFF) & (delta0 > pe_f * (1.0 - 1e-12))
            st[newly] = SLIDE
            latch_f = np.zeros(nf, dtype=bool)
            free = st != OFF
        g_f = g_num[fthr] / ell[fthr]
        # A meniscus armed now or at the end of the last step (flux NaN) starts ON if it is
        # clearly past its threshold, else sliding, with a flux not known yet: the error
        # estimate takes its end-of-step flux (the jump at its start is an event, not an
        # error of the step).
        fresh = newly | ((st != OFF) & np.isnan(mflux[fthr]))
        if not latching:
            st[fresh & (delta0 > pe_f * (1.0 + 1e-9))] = ON
        late = fresh & (st == SLIDE)
        # meniscus fluxes at the start of the step: SLIDE its last flux, ON G D
        qstart = np.where(st == SLIDE, mflux[fthr], 0.0)
        qstart = np.where(st == ON, g_f * np.maximum(delta0, 0.0), qstart)
        qstart[late] = 0.0
        largest = start_rates(net, cond, drained, p, fpore, qstart, rate)
        if control == Control.RATE:
            rate_inv = (q_rate - float(qstart.sum())) / cap
        elif control == Control.RAMP:
            rate_inv = ramp_rate
        else:
            rate_inv = 0.0
        if (
            control == Control.PRESSURE
            and ctrl[Slot.LAST_RATE] * dt_min <= stationary_floor
            and not (newly | (qstart * dt_min > stationary_floor * area[fthr])).any()
        ):
            return Status.STATIONARY
        # the step to try: controller, restart rule, end time, predicted events
        dt_ctrl = float(ctrl[Slot.DT])
        if ctrl[Slot.RESTART] > 0.0:
            fastest = max(largest, abs(rate_inv))
            guess = tol_abs / fastest if fastest > 0.0 else dt_ctrl
            dt_ctrl = max(1e-6 * dt_min, min(dt_ctrl, guess))
            ctrl[Slot.RESTART] = 0.0
        dt_try = min(dt_ctrl, t_end - t)
        predicted = _predict(st, free, qstart, ell[fthr], area[fthr], pe_f, delta0, rate_inv,
                             rate[fpore])  # fmt: skip
        if predicted * _PREDICT_MARGIN < dt_try:
            dt_try = predicted * _PREDICT_MARGIN
        limited = dt_try < dt_ctrl
        step_k = {
            "indptr": indptr, "thr": thr, "vol": vol, "g_eff": g_eff, "g_out": g_out,
            "pattern": cache["pattern"], "p": p, "n": n, "fpore": fpore, "fthr": fthr,
            "G": g_f, "pe_f": pe_f, "free": free, "latch_f": latch_f, "state0": st,
            "control": control, "pinv": pinv, "capacity": cap, "q_rate": q_rate,
            "ramp_rate": ramp_rate, "ell_f": ell[fthr], "area_f": area[fthr], "ell0": ell0,
        }  # fmt: skip
        step = StepProblem(step_k, 1e-10)
        sol = step.solve(dt_try)
        if sol is None:
            ctrl[Slot.DT] = 0.25 * dt_try
            _count(ctrl, step, rejected=True)
            if ctrl[Slot.DT] < 1e-9 * dt_min:
                cnt[Count.WHERE] = step.failed_at
                return Status.NOT_SETTLED
            continue
        pnew = step.pressures(sol)
        rate_err = rate
        if late.any():
            rate_err = rate.copy()
            np.add.at(rate_err, fpore[late], sol["q"][late] / vol[fpore[late]])
        err, _, _, _ = error_and_storage(dt_try, drained, vol, g_out, p, pnew, rate_err)
        rate_inv_err = rate_inv
        if control == Control.RATE and late.any():
            rate_inv_err -= float(sol["q"][late].sum()) / cap
        err = max(err, abs(sol["pinv"] - pinv - dt_try * rate_inv_err))
        err *= 0.5
        if not math.isfinite(err):
            cnt[Count.WHERE] = -1
            return Status.NON_FINITE
        h, h_land, h_start = step.events(sol)
        if TRACE is not None:
            TRACE.append((float(t), dt_try, dt_ctrl, predicted, err / tol_abs, h_land, h_start,
                          step.factorizations, int(cnt[Count.EVENTS])))  # fmt: skip
        if err > tol_abs:
            ctrl[Slot.DT] = dt_try * max(0.2, 0.9 * math.sqrt(tol_abs / err))
            _count(ctrl, step, rejected=True)
            continue
        grow = _GROWTH if err == 0.0 else min(_GROWTH, 0.9 * math.sqrt(tol_abs / err))
        proposal = dt_try * grow
        if limited:
            proposal = max(proposal, dt_ctrl) if grow >= 1.0 else min(proposal, dt_ctrl)
        ctrl[Slot.DT] = proposal
        located = h <= 0.0
        if located:
            ctrl[Slot.LOCATED] += 1
            sol, h = _locate(step, sol, h, event_tolerance)
            if sol is None:
                cnt[Count.WHERE] = step.failed_at
                _count(ctrl, step)
                return Status.NOT_SETTLED
            pnew = step.pressures(sol)
        _count(ctrl, step)
        # -- accept ---------------------------------------------------------------------------
        dt = sol["dt"]
        q = sol["q"].copy()
        state = sol["state"]
        moving = state != OFF
        # located: the events within the tolerance of the located one happen now too
        within = max(h, 0.0) if located else 0.0
        remaining = np.full(nf, math.inf)
        remaining[moving] = ell[fthr[moving]] - q[moving] * dt / area[fthr[moving]]
        landing = moving & (remaining <= max(1e-12, within) * ell0)
        # flux corrections so that landing menisci end exactly at 0 (booked in their pore,
        # which drains now, and in the reservoir)
        correction = np.zeros(nf)
        correction[landing] = remaining[landing] * area[fthr[landing]] / dt
        q += correction
        out_fix = 0.0  # the correction stays in the pore: none of it flows to the outlet
        for s in np.flatnonzero(landing):
            bump = correction[s] * dt / vol[fpore[s]]
            pnew[fpore[s]] += bump
            out_fix += g_out[fpore[s]] * bump
        qsum = float(q.sum())
        pinv_new = pinv + dt * (q_rate - qsum) / cap if control == Control.RATE else sol["pinv"]
        _, stored, out, last_rate = error_and_storage(dt, drained, vol, g_out, p, pnew, rate)
        out -= out_fix
        und = ~drained
        p[und] = pnew[und]
        new_ell = ell[fthr] - q * dt / area[fthr]
        new_ell[landing] = 0.0
        ell[fthr[moving]] = new_ell[moving]
        pump = Pump(control, pinv, q_rate, cap, ramp_rate)
        book_step(flow, pump, dt, qsum * dt, stored, out * dt, pinv_new)
        ctrl[Slot.LAST_RATE] = last_rate
        if not (math.isfinite(pinv_new) and math.isfinite(stored)):
            cnt[Count.WHERE] = -1
            return Status.NON_FINITE
        # states for the next step; menisci that reached their threshold are armed
        final = state.copy()
        frozen = ~free
        crossing = frozen & ((pe_f - (pinv_new - pnew[fpore])) <= max(1e-12, within) * pe_f)
        if latching:
            latched[fthr[crossing]] = True
            final[crossing] = ON
        else:
            final[crossing] = SLIDE
        mstate[fthr] = final
        mflux[fthr] = q
        mflux[fthr[crossing]] = np.nan
        if not landing.any():
            continue
        # drain the landed pores, earliest landing first (ties in throat order)
        sel = np.flatnonzero(landing)
        sel = sel[np.lexsort((fthr[sel], remaining[sel]))]
        for s in sel:
            i, f = int(fpore[s]), int(fthr[s])
            if drained[i]:
                continue
            drain_pore(i, f, net, cond, flow, front, records, ell0)
            for e in range(indptr[i], indptr[i + 1]):
                t2 = thr[e]
                if not drained[nbr[e]]:
                    mstate[t2] = OFF
                    mflux[t2] = 0.0
            events += 1
            if outlet[i]:
                cnt[Count.BREAKTHROUGH] = 1
                if stop_at_breakthrough:
                    ctrl[Slot.RESTART] = 1.0
                    return Status.BREAKTHROUGH
        ctrl[Slot.RESTART] = 1.0


def _count(ctrl: np.ndarray, step: StepProblem, rejected: bool = False) -> None:
    ctrl[Slot.SOLVES] += step.solves
    ctrl[Slot.FACTORIZATIONS] += step.factorizations
    ctrl[Slot.ITERATIONS] += step.iterations
    if rejected:
        ctrl[Slot.REJECTED] += 1


def _predict(
    st: np.ndarray,
    free: np.ndarray,
    qstart: np.ndarray,
    ell_f: np.ndarray,
    area_f: np.ndarray,
    pe_f: np.ndarray,
    delta0: np.ndarray,
    rate_inv: float,
    rate_pore: np.ndarray,
) -> float:
    """Predicted time to the next event: landings at the start-of-step meniscus fluxes, starts
    at the start-of-step rate of change of ``D = p_inv - p_i``."""
    best = math.inf
    moving = (st != OFF) & (qstart > 0.0)
    if moving.any():
        best = float(np.min(ell_f[moving] * area_f[moving] / qstart[moving]))
    frozen = ~free
    if frozen.any():
        slope = rate_inv - rate_pore[frozen]
        gap = pe_f[frozen] - delta0[frozen]
        rising = slope > 0.0
        if rising.any():
            best = min(best, float(np.min(gap[rising] / slope[rising])))
    return best


def _locate(
    step: StepProblem, sol_hi: dict[str, Any], h_hi: float, event_tolerance: float
) -> tuple[dict[str, Any] | None, float]:
    """Regula falsi (Illinois) on the step length for the first event; returns the solution at
    the located instant and its ``h`` (``<= 0``: at or just past the event; a small positive
    value: within the tolerance before it).

    The landing and start parts of ``h`` are followed separately (each is smooth, their
    minimum is not): each iterate is the secant root of the part that changes sign in the
    bracket (the earlier one if both do)."""
    k = step.k
    hi = sol_hi["dt"]
    lo = 0.0
    moving = sol_hi["state"] != OFF
    h0_land = float(np.min(k["ell_f"][moving])) / k["ell0"] if moving.any() else math.inf
    h0_start = math.inf
    frozen = ~k["free"]
    if frozen.any():
        delta0 = k["pinv"] - k["p"][k["fpore"][frozen]]
        h0_start = float(np.min((k["pe_f"][frozen] - delta0) / k["pe_f"][frozen]))
    _, hl, hs = step.events(sol_hi)
    parts_lo = np.array([h0_land, h0_start])
    parts_hi = np.array([hl, hs])
    w_lo, w_hi = parts_lo.copy(), parts_hi.copy()
    side = 0
    best = sol_hi
    for _ in range(200):
        if hi - lo <= event_tolerance * hi or -h_hi <= 1e-14:
            return best, h_hi
        mid = math.inf
        part = 0
        for c in range(2):
            if parts_hi[c] <= 0.0 and math.isfinite(w_lo[c]):
                root = hi - w_hi[c] * (hi - lo) / (w_hi[c] - w_lo[c])
                if root < mid:
                    mid, part = root, c
        if not lo < mid < hi:
            mid = 0.5 * (lo + hi)
        sol = step.solve(mid)
        if sol is None:
            return None, 0.0
        h_mid, hl, hs = step.events(sol)
        parts_mid = np.array([hl, hs])
        # secant estimate of the distance in time from mid to the root of the part followed
        near, p_near = (hi, parts_hi[part]) if parts_mid[part] > 0.0 else (lo, parts_lo[part])
        if math.isfinite(p_near) and near != mid:
            slope = (p_near - parts_mid[part]) / (near - mid)
            close = slope != 0.0 and abs(parts_mid[part] / slope) <= event_tolerance * mid
            if close and (h_mid > 0.0 or parts_mid[1 - part] > 0.0):
                return sol, h_mid
        if h_mid > 0.0:
            lo, parts_lo, w_lo = mid, parts_mid, parts_mid.copy()
            if side == -1:
                w_hi *= 0.5
            side = -1
        else:
            hi, h_hi, parts_hi, w_hi, best = mid, h_mid, parts_mid, parts_mid.copy(), sol
            if side == 1:
                w_lo *= 0.5
            side = 1
    return best, h_hi
