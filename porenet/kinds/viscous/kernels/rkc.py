"""Stabilised explicit time integration of the viscous model: IMEX Runge-Kutta-Chebyshev.

Scaled units and equations as in :mod:`porenet.kinds.viscous.kernels.explicit`. The explicit
integrator's step is bounded by stability, ``dt <= min_i V_i / sum_j g_ij``, so at small Ca it takes
~4/(n Ca) steps per drained pore although the pressures change slowly. A Runge-Kutta-Chebyshev (RKC)
step of length ``h`` sweeps the pores ``m ~ sqrt(1.54 h rho)`` times (``rho`` the spectral radius of
the pore-to-pore operator,
:func:`porenet.kinds.viscous.kernels.chebyshev.spectral_radius`) and is stable for the diffusion
however long ``h`` is: its cost per unit of model time falls like ``1 / sqrt(h)``, and ``h`` is set
by accuracy and by the events, not by stability.

The scheme is the implicit-explicit RKC method of Verwer & Sommeijer (SIAM J. Sci. Comput. 25,
1824, 2004) as the IRKC code of Shampine, Sommeijer & Verwer (J. Comput. Appl. Math. 196, 485,
2006) implements it: second order in the explicit part, damping ``eps = 2/13``, and
unconditionally stable in the implicit part. Here

* the explicit part ``F_E`` is the Darcy flux between undrained pores and to the outlet (one
  stencil sweep per stage, :func:`porenet.kinds.viscous.kernels.chebyshev.sweep`);
* the implicit part ``F_I`` is the menisci, the pores they enter and the injection reservoir:
  exactly the point-implicit problem of the explicit integrator's step
  (:mod:`porenet.kinds.viscous.kernels.menisci`: the sliding closure of the threshold law and the
  pump), solved in every stage over the stage step ``h mu~_1`` (~``3 h / m^2``);

with stages (``W_0 = y_n``)::

    W_1 = W_0 + mu~_1 h F_E(W_0) + mu~_1 h F_I(W_1)
    W_j = (1 - mu_j - nu_j) W_0 + mu_j W_{j-1} + nu_j W_{j-2} + mu~_j h F_E(W_{j-1})
          + g~_j h F_E(W_0) + [g~_j - (1 - mu_j - nu_j) mu~_1] h F_I(W_0)
          - nu_j mu~_1 h F_I(W_{j-2}) + mu~_1 h F_I(W_j),          j = 2 .. m

and ``y_{n+1} = W_m``. The meniscus lengths and the volume totals (drained, outflow) are
components of ``y`` like the pressures and follow the same recursion, so every balance closes
to round-off. Meniscus conductances ``A k / l`` are frozen at the start of a step; ``F_I(y_n)``
is the menisci's flux over one explicit-length step from ``y_n`` (a sliding meniscus has no
flux at a state, only along a trajectory).

Events. No pore drains inside an RKC step: a step ends at :data:`LAND` of the predicted time of
the next landing (from the meniscus fluxes at its start) and is rejected if a meniscus would
pass ``l = 0`` all the same. Once the next landing is nearer than :data:`EXPLICIT_SPAN`
explicit steps, or accuracy asks for so short a step, the explicit integrator
(:func:`porenet.kinds.viscous.kernels.explicit.explicit_advance`) takes over until the landing,
which it locates exactly (``l = 0``, no overshoot), then RKC resumes. A meniscus that starts within
a step is a candidate of the step (its threshold is within reach of the invading pressure) and
switches on inside the stages; a step at whose end a meniscus that was not a candidate is past its
threshold is rejected and halved. Rule "latching": a meniscus not yet latched obeys the threshold
law within the step that latches it (the two laws differ only if it falls back below its entry
pressure in that same step).

Step control: the RKC local error estimate ``0.8 (y_n - y_{n+1}) + 0.4 h (F(y_n) +
F(y_{n+1}))`` (Sommeijer, Shampine & Verwer, J. Comput. Appl. Math. 88, 315, 1997) in the max
norm over the pore pressures and ``p_inv``, against ``tolerance`` times the entry-pressure
spread; the next step from the RKC code's predictive controller (the error's growth over the
last two steps), at most :data:`GROW` times longer. The stage count is ``m = 1 + floor(sqrt(1 +
1.54 h rho))``, at least 3 (stable for the IMEX pair: ``porenet/kinds/viscous/tests/test_rkc.py``).

Length (over the ~500 lines of docs/architecture.md's rule): ``rkc_advance`` is one compiled
loop (steps, events, step control) with the helpers that keep its candidate list; the stages and
error estimate (rkc_step.py) and the Chebyshev coefficients (chebyshev.py) are already apart,
and splitting the loop itself would cut the step control from the events it reacts to.
"""

from __future__ import annotations

from enum import IntEnum
from typing import NamedTuple

import numpy as np

from porenet.jit.jit import THREADS, njit, prange, serial_and_parallel, threaded_box
from porenet.kinds.viscous.kernels.chebyshev import MAX_STAGES, longest_step, stage_count, sweep
from porenet.kinds.viscous.kernels.diffusion import grow_where_reached, spread
from porenet.kinds.viscous.kernels.explicit import _list_meniscus, explicit_advance
from porenet.kinds.viscous.kernels.menisci import invader_pressure, meniscus_fluxes, undrained_pore
from porenet.kinds.viscous.kernels.rkc_step import (
    Stages,
    StepStart,
    imex_stages,
    implicit_rate,
    pump_rate,
    step_error,
)
from porenet.kinds.viscous.kernels.state import (
    LISTS,
    WINDOWS,
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
    Ring,
    Window,
    WindowInt,
    book_shadow,
    cut,
    far_meniscus,
    far_pressure,
    inside,
    ring_increment,
    set_ring,
)


class Slot(IntEnum):
    """Slots of :attr:`Rkc.memory`: the integrator's memory between calls, and its counters."""

    H = 0  #: the next RKC step (0 before the first)
    STAGES = 1  #: stage sweeps of accepted and rejected RKC steps
    RKC_STEPS = 2  #: accepted RKC steps
    REJECTED = 3  #: rejected RKC steps
    EXPLICIT_STEPS = 4  #: steps taken by the explicit integrator (near landings)
    LARGEST_STAGE_COUNT = 5
    LAST_ERROR = 6  #: error of the last accepted step (0: none since the last restart)
    LAST_STEP = 7  #: its length
    REJECTED_EVENTS = 8  #: of the rejected: a meniscus past l = 0, unresolved or unlisted
    REJECTED_STAGES = 9  #: stage sweeps spent on rejected steps
    #: F_E(y_n) between calls, so that where a call ends never changes the run:
    F0_VALID = 10  #: 1: the buffer named by F0_SWAPPED holds F_E(p) (0: recompute it)
    F0_SWAPPED = 11  #: 1: it is ``Rkc.fnew`` (the steps swapped the two buffers)
    OUTFLOW0 = 12  #: the outflow rate of that state


class Rkc(NamedTuple):
    """The RKC integrator's buffers, memory and parameters.

    Attributes
    ----------
    stages : ndarray of float64, shape (3, N)
        Stage buffers (the pores' increments).
    f0, fnew : ndarray of float64, shape (N,)
        ``F_E`` at the start and at the end of a step (the two swap roles at each accepted
        step; :attr:`memory` records which holds ``F_E(p)`` when a call returns, so the next
        call goes on from it: a caller that changes the pressures, the box or the
        conductances between calls clears its ``F0_VALID``).
    zero : ndarray of float64, shape (N,)
        Zeros.
    memory : ndarray of float64, shape (len(Slot),)
        By :class:`Slot`.
    spectral_radius : float
        Of the pore-to-pore operator (sets the stage count).
    dt_stable : float
        The explicit stability limit.
    pressure_scale : float
        The entry-pressure spread: the unit of ``tolerance``.
    tolerance : float
        Local error allowed per step, as a fraction of ``pressure_scale``.
    """

    stages: np.ndarray
    f0: np.ndarray
    fnew: np.ndarray
    zero: np.ndarray
    memory: np.ndarray
    spectral_radius: float
    dt_stable: float
    pressure_scale: float
    tolerance: float


#: An RKC step shorter than this many explicit steps is not worth its stages: the explicit
#: integrator takes over (four times as long when a landing is predicted within it).
EXPLICIT_SPAN = 8.0
#: An RKC step ends at this fraction of the predicted time of the next landing.
LAND = 0.95
#: Largest growth of the step from one accepted step to the next.
GROW = 10.0


@njit
def _list_candidates(
    h: float,
    t: float,
    menisci0: Menisci,
    pump0: Pump,
    net: Network,
    cond: Conductances,
    flow: Flow,
    front: Front,
    scratch: Scratch,
    latching: bool,
    window: Window,
) -> int:
    """The candidate menisci of a step of ``h`` from the state of ``menisci0`` (its pressures,
    and ``F_E`` as its ``flux``), as :func:`porenet.kinds.viscous.kernels.explicit.explicit_advance`
    lists them: at or above their threshold (latched ones with threshold 0), then those the
    invading pressure can bring to it within the step, allowing for the pore's own explicit
    change. Marks them in ``scratch.candidate``; returns their number. In a window only the
    menisci into its pores are listed; one into a pore outside that is at its threshold at
    ``t`` (by the extrapolated pressure) ends the macro step: returns -1."""
    p, f0 = menisci0.pressure, menisci0.flux
    tp, entry, drained, latched = net.throat_pores, cond.entry_pressure, flow.drained, flow.latched
    inv_vol, grid_n = net.inverse_volume, net.grid_n
    cand, near = scratch.candidate, scratch.near
    pinv = pump0.pressure
    rising = pump0.rate / pump0.capacity if pump0.control == Control.RATE else 0.0
    reach = h * max(rising, pump0.ramp_rate)
    windowed = WINDOWS and window.ints[WindowInt.MODE] == Mode.FINE
    if windowed:
        k = far_meniscus(window, pinv, 1e-8, t, entry, tp, drained)
        if k >= 0:
            cut(window, Cut.FAR_MENISCUS, k)
            return -1
    n_on = 0
    n_near = 0
    for s in range(flow.counters[Count.N_FRONT]):
        f = front.throats[s]
        i = undrained_pore(tp, drained, f)
        if windowed and not inside(window.box, grid_n, i):
            d = pinv - far_pressure(window, i, t)
            if (latching and latched[f]) or d > entry[f] * (1.0 - 1e-9):
                _unlist(n_on, menisci0, cand)
                cut(window, Cut.FAR_MENISCUS, i)
                return -1
            continue
        d = pinv - p[i]
        if latching and d > entry[f]:
            latched[f] = True
        if latching and latched[f]:
            n_on = _list_meniscus(f, i, 0.0, n_on, menisci0)
            cand[f] = True
        elif d > entry[f] * (1.0 - 1e-9):
            n_on = _list_meniscus(f, i, entry[f], n_on, menisci0)
            cand[f] = True
        elif d > entry[f] - reach - h * abs(f0[i]) * inv_vol[i]:
            near[n_near] = f
            n_near += 1
    if n_near > 0:
        rise = max(invader_pressure(h, n_on, menisci0, pump0) - pinv, 0.0)
        for r in range(n_near):
            f = near[r]
            i = undrained_pore(tp, drained, f)
            if pinv - p[i] > entry[f] - rise - h * abs(f0[i]) * inv_vol[i]:
                n_on = _list_meniscus(f, i, entry[f], n_on, menisci0)
                cand[f] = True
    return n_on


@njit(helper=True)
def _unlist(n_on: int, menisci: Menisci, cand: np.ndarray) -> None:
    """Clear the per-pore links and marks of the step's candidates."""
    for s in range(n_on):
        menisci.head[menisci.pore[s]] = -1
        cand[menisci.throat[s]] = False


@njit(helper=True)
def _row_add(src: np.ndarray, dst: np.ndarray) -> None:
    """``dst += src`` over aligned views of a run of pores (a SIMD loop)."""
    for j in range(src.size):
        dst[j] += src[j]


def _add_rows(n: int, box: np.ndarray, src: np.ndarray, dst: np.ndarray) -> None:
    """``dst += src`` over the box's rows (:func:`_row_add`)."""
    for i in prange(box[0], box[1]):
        a, b = i * n + box[2], i * n + box[3]
        _row_add(src[a:b], dst[a:b])


_add_rows_serial, _add_rows_parallel = serial_and_parallel(_add_rows)


@njit
def _add_active(field: Sweep, src: np.ndarray, dst: np.ndarray) -> None:
    """``dst += src`` over the active pores (on grids row by row, :func:`_row_add`: the slice
    expression ``dst[a:b] += src[a:b]`` took 3x as long; several threads on a large box)."""
    grid_n, box, na, act = field.grid_n, field.box, field.n_active, field.pores
    if LISTS and grid_n == 0:
        for s in range(na):
            dst[act[s]] += src[act[s]]
    elif THREADS and threaded_box(box):
        _add_rows_parallel(grid_n, box, src, dst)
    else:
        _add_rows_serial(grid_n, box, src, dst)


@njit(helper=True)
def _keep_f0(memory: np.ndarray, stale: bool, out0: float) -> None:
    """Leave F_E(y_n) for the next call: valid unless ``stale``, with its outflow rate."""
    memory[Slot.F0_VALID] = 0.0 if stale else 1.0
    memory[Slot.OUTFLOW0] = out0


@njit
def rkc_advance(
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
    rkc: Rkc,
) -> int:
    """Integrate with IMEX RKC steps until ``stops.max_events`` pores drain or another stop;
    returns a :class:`~porenet.kinds.viscous.kernels.state.Status`.

    Arguments as :func:`porenet.kinds.viscous.kernels.explicit.explicit_advance` (which it calls
    near landings, with ``rules.dt_max`` its step), plus the integrator's buffers, memory and
    parameters ``rkc`` (:class:`Rkc`). In the fine integration of a macro step of local time steps
    (``window`` in mode FINE) the window's box is swept and does not grow, and the integration ends
    early with ``Status.CUT`` when a meniscus outside the window may start or a pore drains near its
    edge.
    """
    indptr, nbr, thr, tp = net.indptr, net.neighbour, net.throat, net.throat_pores
    vol, inv_vol, grid_n = net.volume, net.inverse_volume, net.grid_n
    g_eff, g_num, area, g_out = cond.between, cond.meniscus, cond.area, cond.outlet
    p, drained, ell, totals, counters = (
        flow.pressure,
        flow.drained,
        flow.meniscus_length,
        flow.totals,
        flow.counters,
    )
    act, apos, nbox = front.pores, front.pore_slot, front.box
    on_t, on_p, head = scratch.meniscus_throat, scratch.meniscus_pore, scratch.head
    cand, fi = scratch.candidate, scratch.implicit_flux
    control, q_rate, capacity = injection.control, injection.rate, injection.capacity
    capacity_per_drained, ramp_rate = injection.capacity_per_drained, injection.ramp_rate
    dt_max, latching, floor = rules.dt_max, rules.latching, rules.floor
    ctrl, f0, fnew, zero = rkc.memory, rkc.f0, rkc.fnew, rkc.zero
    rho, dt_stable = rkc.spectral_radius, rkc.dt_stable
    n_pores, n_thr = len(p), len(area)
    events_at_entry, steps_at_entry = counters[Count.EVENTS], counters[Count.STEPS]
    # written before they are read, for the step's candidates only
    q0 = np.empty(n_thr)
    qst, lst = np.empty((3, n_thr)), np.empty((3, n_thr))
    pst, ast = np.zeros(3), np.zeros((3, 2))
    r_ell = np.empty(n_thr)
    moved = np.empty(n_thr, dtype=np.bool_)
    rhs = np.empty(n_pores)  # the stages' right-hand sides at the menisci's pores
    stages = Stages(rkc.stages, rhs, zero, qst, lst, pst, ast, r_ell, moved)
    windowed = WINDOWS and window.ints[WindowInt.MODE] == Mode.FINE
    box = window.box if windowed else nbox  # the pores swept
    # F_E(y_n) as the last call left it, unless the state changed since (F0_VALID cleared by
    # the caller) or this is a window's fine integration (which starts afresh)
    if ctrl[Slot.F0_SWAPPED] != 0.0:
        f0, fnew = fnew, f0
    need_f0 = windowed or ctrl[Slot.F0_VALID] == 0.0
    out0 = ctrl[Slot.OUTFLOW0]
    h_next = ctrl[Slot.H] if ctrl[Slot.H] > 0 else EXPLICIT_SPAN * dt_stable
    no_flux = (0.0, 0.0, 0.0, 0.0)
    while True:
        ctrl[Slot.H] = h_next
        _keep_f0(ctrl, need_f0 or windowed, out0)
        if (
            counters[Count.EVENTS] - events_at_entry >= stops.max_events
            or counters[Count.STEPS] - steps_at_entry >= stops.step_budget
        ):
            return Status.BUDGET
        t, pinv = totals[Total.TIME], totals[Total.INVADING_PRESSURE]
        if t >= stops.t_end:
            return Status.END_TIME
        if counters[Count.STEPS] >= stops.max_steps:
            return Status.STEP_LIMIT
        if counters[Count.N_FRONT] == 0:
            return Status.NO_MENISCUS
        capacity_now = capacity + capacity_per_drained * totals[Total.DRAINED_PORE_VOLUME]
        h = min(h_next, stops.t_end - t, longest_step(MAX_STAGES, rho))
        # a step spreads the pressure by one pore per stage: grow the box by as much
        if windowed:
            set_ring(window, p, t)
        elif grid_n > 0 and grow_where_reached(box, grid_n, p, floor, stage_count(h, rho) + 1):
            need_f0 = True
        field = Sweep(grid_n, box, counters[Count.N_ACTIVE], act, apos, indptr, nbr, thr, g_eff,
                      g_out, inv_vol, fnew, nbox)  # fmt: skip
        if need_f0:
            out0 = sweep(field, p, p, f0, no_flux, f0, True)
            need_f0 = False
        menisci0 = Menisci(on_t, on_p, scratch.threshold, head, scratch.next_candidate, p, f0,
                           vol, g_num, ell, area)  # fmt: skip
        pump0 = Pump(control, pinv, q_rate, capacity_now, ramp_rate)
        n_on = _list_candidates(h, t, menisci0, pump0, net, cond, flow, front, scratch,
                                latching, window)  # fmt: skip
        if n_on < 0:
            _keep_f0(ctrl, need_f0 or windowed, out0)
            return Status.CUT
        # F_I(y_n): the menisci's fluxes over an explicit-length step; the next landing
        meniscus_fluxes(dt_stable, n_on, menisci0, pump0, q0)
        t_land = np.inf
        for s in range(n_on):
            if q0[s] > 0.0:
                t_land = min(t_land, ell[on_t[s]] * area[on_t[s]] / q0[s])
        h = min(h, LAND * t_land)
        if h < EXPLICIT_SPAN * dt_stable:
            # Near a landing, or a fast transient: explicit steps until the event or the span.
            _unlist(n_on, menisci0, cand)
            span = EXPLICIT_SPAN * (4.0 if t_land < EXPLICIT_SPAN * dt_stable else 1.0)
            before = counters[Count.STEPS]
            near_landing = Stops(1, stops.t_end, stops.max_steps, stops.at_breakthrough,
                                 int(span * dt_stable / dt_max) + 2)  # fmt: skip
            status = explicit_advance(net, cond, flow, front, records, scratch, injection, rules,
                                      near_landing, window)  # fmt: skip
            ctrl[Slot.EXPLICIT_STEPS] += counters[Count.STEPS] - before
            ctrl[Slot.LAST_ERROR] = 0.0  # the controller restarts
            need_f0 = True
            h_next = EXPLICIT_SPAN * dt_stable
            if status != Status.BUDGET:
                ctrl[Slot.H] = h_next
                _keep_f0(ctrl, True, out0)
                return status
            continue
        m = stage_count(h, rho)
        h = min(h, longest_step(m, rho))
        start = StepStart(p, f0, out0, q0)
        k = imex_stages(h, m, field, start, n_on, menisci0, pump0, stages, window)
        ds, ps, qs = rkc.stages[k], pst[k], qst[k]
        ctrl[Slot.STAGES] += m
        ctrl[Slot.LARGEST_STAGE_COUNT] = max(ctrl[Slot.LARGEST_STAGE_COUNT], m)
        # rejected outright: a meniscus past l = 0, or one past its threshold unlisted
        reject = 0.0
        for s in range(n_on):
            if lst[k, s] < 0.0:
                reject = 0.5
            elif moved[s] and lst[k, s] > ell[on_t[s]]:
                # the stages' weights of a meniscus that switched on or off inside the step
                # summed to a negative swept volume: the switch is not resolved
                reject = 0.5
        for s in range(counters[Count.N_FRONT] if reject == 0.0 else 0):
            f = front.throats[s]
            i = undrained_pore(tp, drained, f)
            if cand[f]:
                continue
            if windowed and not inside(window.box, grid_n, i):
                past = ps - far_pressure(window, i, t + h) > cond.entry_pressure[f]
            else:
                past = ps - p[i] - ds[i] > cond.entry_pressure[f]
            if past:
                reject = 0.5
                break
        if (
            windowed
            and reject == 0.0
            and far_meniscus(window, ps, 0.0, t + h, cond.entry_pressure, tp, drained) >= 0
        ):
            reject = 0.5  # a meniscus outside the window would start within the step
        for_event = reject > 0.0
        # the error estimate
        qsum0 = qsums = 0.0
        for s in range(n_on):
            qsum0 += q0[s]
            qsums += qs[s]
            i = on_p[s]
            if head[i] == s:
                fi[i] = implicit_rate(i, q0, head, scratch.next_candidate) + implicit_rate(
                    i, qs, head, scratch.next_candidate
                )
        if windowed:
            ring_increment(window, ds, h)
        out_s = sweep(field, ds, ds, f0, no_flux, fnew, True)
        err, stored, largest = step_error(h, field, ds, f0, fnew, fi, vol)
        for s in range(n_on):
            fi[on_p[s]] = 0.0
        fiinv = pump_rate(control, q_rate, capacity_now, ramp_rate, qsum0)
        fiinv += pump_rate(control, q_rate, capacity_now, ramp_rate, qsums)
        err = max(err, abs(0.8 * (pinv - ps) + 0.4 * h * fiinv))
        err /= rkc.tolerance * rkc.pressure_scale
        if not (np.isfinite(err) and np.isfinite(ps) and np.isfinite(stored)):
            _unlist(n_on, menisci0, cand)
            counters[Count.WHERE] = -1
            _keep_f0(ctrl, True, out0)
            return Status.NON_FINITE
        if reject == 0.0 and err > 1.0:
            reject = max(0.2, 0.8 * err ** (-1.0 / 3.0))
        if reject > 0.0:
            ctrl[Slot.REJECTED] += 1
            ctrl[Slot.REJECTED_EVENTS] += 1 if for_event else 0
            ctrl[Slot.REJECTED_STAGES] += m
            h_next = h * reject
            _unlist(n_on, menisci0, cand)
            continue
        # accept
        _add_active(field, ds, p)
        if windowed:
            totals[Total.IN_TRANSIT] += book_shadow(window, m, Ring.FLUX)
            set_ring(window, p, t + h)
        f0, fnew = fnew, f0  # F_E(y_n+1) is the next step's F_E(y_n): swap, do not copy
        ctrl[Slot.F0_SWAPPED] = 1.0 - ctrl[Slot.F0_SWAPPED]
        out0 += out_s
        for s in range(n_on):
            if moved[s]:
                ell[on_t[s]] = lst[k, s]
        _unlist(n_on, menisci0, cand)
        book_step(flow, pump0, h, ast[k, 0], stored, ast[k, 1], ps)
        ctrl[Slot.RKC_STEPS] += 1
        if LISTS and grid_n == 0:
            for _r in range(m):  # (the active pores grow with each spread)
                now = Sweep(grid_n, box, counters[Count.N_ACTIVE], act, apos, indptr, nbr, thr,
                            g_eff, g_out, inv_vol, fnew, nbox)  # fmt: skip
                spread(now, front.settled, counters, drained, p, floor)
            need_f0 = True
        if control == Control.PRESSURE:
            rate = largest / h
            for s in range(n_on):
                rate = max(rate, qs[s] * inv_vol[on_p[s]])
            if rate * dt_max <= floor:
                ctrl[Slot.H] = h
                _keep_f0(ctrl, need_f0 or windowed, out0)
                return Status.STATIONARY
        # the RKC code's predictive controller (Gustafsson): how the error grew with the step
        # over the last two steps, not the asymptotic h^3 law, sets the next step
        e = max(err, 1e-10)
        if ctrl[Slot.LAST_ERROR] > 0.0 and ctrl[Slot.LAST_STEP] > 0.0:
            last_error, last_step = ctrl[Slot.LAST_ERROR], ctrl[Slot.LAST_STEP]
            fac = 0.8 * (h / last_step) * last_error ** (1.0 / 3.0) / e ** (2.0 / 3.0)
        else:
            fac = 0.8 * e ** (-1.0 / 3.0)
        ctrl[Slot.LAST_ERROR], ctrl[Slot.LAST_STEP] = e, h
        h_next = h * max(0.1, min(GROW, fac))


__all__ = ["Rkc", "Slot", "rkc_advance"]
