"""Stabilised explicit time integration of the viscous model: IMEX Runge-Kutta-Chebyshev.

Scaled units and equations as in :mod:`porenet.kernels.viscous.explicit`. The explicit integrator's
step is bounded by stability, ``dt <= min_i V_i / sum_j g_ij``, so at small Ca it takes
~4/(n Ca) steps per drained pore although the pressures change slowly. A Runge-Kutta-Chebyshev
(RKC) step of length ``h`` sweeps the pores ``m ~ sqrt(1.54 h rho)`` times (``rho`` the
spectral radius of the pore-to-pore operator,
:func:`porenet.kernels.viscous.chebyshev.spectral_radius`) and is stable for the diffusion however
long ``h`` is: its cost per unit of model time falls like ``1 / sqrt(h)``, and ``h`` is set by
accuracy and by the events, not by stability.

The scheme is the implicit-explicit RKC method of Verwer & Sommeijer (SIAM J. Sci. Comput. 25,
1824, 2004) as the IRKC code of Shampine, Sommeijer & Verwer (J. Comput. Appl. Math. 196, 485,
2006) implements it: second order in the explicit part, damping ``eps = 2/13``, and
unconditionally stable in the implicit part. Here

* the explicit part ``F_E`` is the Darcy flux between undrained pores and to the outlet (one
  stencil sweep per stage, :func:`porenet.kernels.viscous.chebyshev.sweep`);
* the implicit part ``F_I`` is the menisci, the pores they enter and the injection reservoir:
  exactly the point-implicit problem of the explicit integrator's step
  (:mod:`porenet.kernels.viscous.menisci`: the sliding closure of the threshold law and the pump),
  solved in every stage over the stage step ``h mu~_1`` (~``3 h / m^2``);

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
(:func:`porenet.kernels.viscous.explicit.explicit_advance`) takes over until the landing, which it
locates exactly (``l = 0``, no overshoot), then RKC resumes. A meniscus that starts within a
step is a candidate of the step (its threshold is within reach of the invading pressure) and
switches on inside the stages; a step at whose end a meniscus that was not a candidate is past
its threshold is rejected and halved. Rule "latching": a meniscus not yet latched obeys the
threshold law within the step that latches it (the two laws differ only if it falls back
below its entry pressure in that same step).

Step control: the RKC local error estimate ``0.8 (y_n - y_{n+1}) + 0.4 h (F(y_n) +
F(y_{n+1}))`` (Sommeijer, Shampine & Verwer, J. Comput. Appl. Math. 88, 315, 1997) in the max
norm over the pore pressures and ``p_inv``, against ``tolerance`` times the entry-pressure
spread; the next step from the RKC code's predictive controller (the error's growth over the
last two steps), at most :data:`GROW` times longer. The stage count is ``m = 1 + floor(sqrt(1 +
1.54 h rho))``, at least 3 (stable for the IMEX pair: ``tests/unit/kernels/viscous/test_rkc.py``).
"""

from __future__ import annotations

import numpy as np

from porenet.kernels._jit import njit, prange, serial_and_parallel, threaded_box
from porenet.kernels.viscous.chebyshev import MAX_STAGES, longest_step, stage_count, sweep
from porenet.kernels.viscous.diffusion import grow_where_reached, spread
from porenet.kernels.viscous.explicit import STATUS, _list_meniscus, explicit_advance
from porenet.kernels.viscous.menisci import (
    CONTROL_PRESSURE,
    CONTROL_RATE,
    invader_pressure,
    meniscus_fluxes,
    undrained_pore,
)
from porenet.kernels.viscous.rkc_step import imex_stages, implicit_rate, pump_rate, step_error
from porenet.kernels.viscous.window import (
    CUT,
    CUT_FAR_MENISCUS,
    FINE,
    RING_FLUX,
    book_shadow,
    cut,
    far_meniscus,
    far_pressure,
    inside,
    ring_increment,
    set_ring,
)

#: Slots of the ``ctrl`` array (the integrator's memory between calls, and its counters).
CTRL = {
    "h": 0,  # the next RKC step (0 before the first)
    "stages": 1,  # stage sweeps of accepted and rejected RKC steps
    "rkc_steps": 2,  # accepted RKC steps
    "rejected": 3,  # rejected RKC steps
    "explicit_steps": 4,  # steps taken by the explicit integrator (near landings)
    "largest_stage_count": 5,
    "last_error": 6,  # error of the last accepted step (0: none since the last restart)
    "last_step": 7,  # its length
    "rejected_events": 8,  # of the rejected: a meniscus past l = 0, unresolved or unlisted
    "rejected_stages": 9,  # stage sweeps spent on rejected steps
    # F_E(y_n) between calls, so that where a call ends never changes the run:
    "f0_valid": 10,  # 1: the buffer named by f0_swapped holds F_E(p) (0: recompute it)
    "f0_swapped": 11,  # 1: it is the ``fnew`` argument (the steps swapped the two buffers)
    "outflow0": 12,  # the outflow rate of that state (returned with F_E by the sweep)
}
N_CTRL = 13

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
    menisci0: tuple,
    pump0: tuple,
    front: np.ndarray,
    nf: int,
    tp: np.ndarray,
    drained: np.ndarray,
    pe: np.ndarray,
    latched: np.ndarray,
    latching: bool,
    inv_vol: np.ndarray,
    cand: np.ndarray,
    near: np.ndarray,
    win: tuple,
    grid_n: int,
    t: float,
) -> int:
    """The candidate menisci of a step of ``h`` from the state of ``menisci0`` (its ``p``,
    and ``F_E`` as its ``flux``), as :func:`porenet.kernels.viscous.explicit.explicit_advance` lists
    them: at or above their threshold (latched ones with threshold 0), then those the invading
    pressure can bring to it within the step, allowing for the pore's own explicit change.
    Marks them in ``cand``; returns their number. In a window only the menisci into its pores
    are listed; one into a pore outside that is at its threshold at ``t`` (by the
    extrapolated pressure) ends the macro step: returns -1."""
    on_t, on_p, c_on, head, nxt, p, f0 = menisci0[:7]
    control, pinv, q_rate, capacity, ramp = pump0
    reach = h * max(q_rate / capacity if control == CONTROL_RATE else 0.0, ramp)
    windowed = win[0][0] == FINE
    if windowed:
        k = far_meniscus(win, pinv, 1e-8, t, pe, tp, drained)
        if k >= 0:
            cut(win, CUT_FAR_MENISCUS, k)
            return -1
    n_on = 0
    n_near = 0
    for s in range(nf):
        f = front[s]
        i = undrained_pore(tp, drained, f)
        if windowed and not inside(win[2], grid_n, i):
            d = pinv - far_pressure(win, i, t)
            if (latching and latched[f]) or d > pe[f] * (1.0 - 1e-9):
                _unlist(n_on, on_t, on_p, head, cand)
                cut(win, CUT_FAR_MENISCUS, i)
                return -1
            continue
        d = pinv - p[i]
        if latching and d > pe[f]:
            latched[f] = True
        if latching and latched[f]:
            n_on = _list_meniscus(f, i, 0.0, n_on, on_t, on_p, c_on, head, nxt)
            cand[f] = True
        elif d > pe[f] * (1.0 - 1e-9):
            n_on = _list_meniscus(f, i, pe[f], n_on, on_t, on_p, c_on, head, nxt)
            cand[f] = True
        elif d > pe[f] - reach - h * abs(f0[i]) * inv_vol[i]:
            near[n_near] = f
            n_near += 1
    if n_near > 0:
        rise = max(invader_pressure(h, n_on, menisci0, pump0) - pinv, 0.0)
        for r in range(n_near):
            f = near[r]
            i = undrained_pore(tp, drained, f)
            if pinv - p[i] > pe[f] - rise - h * abs(f0[i]) * inv_vol[i]:
                n_on = _list_meniscus(f, i, pe[f], n_on, on_t, on_p, c_on, head, nxt)
                cand[f] = True
    return n_on


@njit(helper=True)
def _unlist(
    n_on: int, on_t: np.ndarray, on_p: np.ndarray, head: np.ndarray, cand: np.ndarray
) -> None:
    """Clear the per-pore links and marks of the step's candidates."""
    for s in range(n_on):
        head[on_p[s]] = -1
        cand[on_t[s]] = False


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
def _add_active(field: tuple, src: np.ndarray, dst: np.ndarray) -> None:
    """``dst += src`` over the active pores (on grids row by row, :func:`_row_add`: the slice
    expression ``dst[a:b] += src[a:b]`` took 3x as long; several threads on a large box)."""
    grid_n, box, na, act = field[0], field[1], field[2], field[3]
    if grid_n > 0 and threaded_box(box):
        _add_rows_parallel(grid_n, box, src, dst)
    elif grid_n > 0:
        _add_rows_serial(grid_n, box, src, dst)
    else:
        for s in range(na):
            dst[act[s]] += src[act[s]]


@njit(helper=True)
def _keep_f0(ctrl: np.ndarray, stale: bool, out0: float) -> None:
    """Leave F_E(y_n) for the next call: valid unless ``stale``, with its outflow rate."""
    ctrl[10] = 0.0 if stale else 1.0
    ctrl[12] = out0


@njit
def rkc_advance(
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
    ybuf: np.ndarray,
    f0: np.ndarray,
    fnew: np.ndarray,
    zero: np.ndarray,
    ctrl: np.ndarray,
    rho: float,
    dt_stable: float,
    dt_max: float,
    control: int,
    q_rate: float,
    capacity: float,
    capacity_per_drained: float,
    ramp_rate: float,
    latching: bool,
    floor: float,
    pressure_step: float,
    pressure_scale: float,
    tolerance: float,
    ell0: float,
    max_events: int,
    t_end: float,
    max_steps: int,
    stop_at_breakthrough: bool,
    step_budget: int,
    nbox: np.ndarray,
    win: tuple,
    work: tuple,
) -> int:
    """Integrate with IMEX RKC steps until ``max_events`` pores drain or another stop.

    Arguments as :func:`porenet.kernels.viscous.explicit.explicit_advance` (which it calls near
    landings, with ``dt_max`` its step), plus: ``ybuf`` (3, N) stage buffers, ``f0`` and
    ``fnew`` (N) ``F_E`` at the start and end of a step (the two swap roles at each
    accepted step; ``ctrl`` records which of them holds ``F_E(p)`` when a call returns, so the
    next call goes on from it and a run does not depend on where its calls end: a caller
    that changes ``p``, the box or the conductances between calls clears ``ctrl``'s
    ``f0_valid``), ``zero`` (N) zeros, ``ctrl`` (:data:`CTRL`), ``rho`` the spectral radius
    of the pore-to-pore operator, ``dt_stable`` the explicit stability limit,
    ``pressure_scale`` the entry-pressure spread and ``tolerance`` the local error allowed
    per step as a fraction of it. Returns a
    :data:`porenet.kernels.viscous.explicit.STATUS` code.

    ``nbox`` is ``box`` and ``win`` a window that is off (:func:`porenet.kernels.viscous.window.
    no_window`), except for the fine integration of a macro step of local time steps
    (:mod:`porenet.kernels.viscous.multirate`): then ``box`` is the window, which does not grow,
    ``nbox`` the active box, and the integration ends early with
    :data:`porenet.kernels.viscous.window.CUT` when a meniscus outside the window may start or a
    pore drains near its edge.

    ``work = (head, cand, fi)``: scratch of shapes (N,) int, (M,) bool and (N,) float, -1,
    False and 0 everywhere on entry and on return (kept by the caller, so that a call, which
    a macro step of local time steps makes, allocates nothing of size N or M that must be
    filled).
    """
    n_pores, n_thr = len(p), len(pe)
    events_at_entry, steps_at_entry = cnt[0], cnt[1]
    inv_vol = 1.0 / vol
    head, cand = work[0], work[1]
    fi = work[2]  # V (F_I(y_n) + F_I(y_n+1)) at the menisci's pores, for the error
    # written before they are read, for the step's candidates only
    c_on = np.empty(n_thr)
    nxt = np.empty(n_thr, dtype=np.int64)
    near = np.empty(n_thr, dtype=np.int64)
    q0 = np.empty(n_thr)
    qst, lst = np.empty((3, n_thr)), np.empty((3, n_thr))
    pst, ast = np.zeros(3), np.zeros((3, 2))
    r_ell = np.empty(n_thr)
    moved = np.empty(n_thr, dtype=np.bool_)
    rhs = np.empty(n_pores)  # the stages' right-hand sides at the menisci's pores
    windowed = win[0][0] == FINE
    # F_E(y_n) as the last call left it, unless the state changed since (ctrl "f0_valid"
    # cleared by the caller) or this is a window's fine integration (which starts afresh)
    if ctrl[11] != 0.0:
        f0, fnew = fnew, f0
    need_f0 = windowed or ctrl[10] == 0.0
    out0 = ctrl[12]
    h_next = ctrl[0] if ctrl[0] > 0 else EXPLICIT_SPAN * dt_stable
    while True:
        ctrl[0] = h_next
        _keep_f0(ctrl, need_f0 or windowed, out0)
        if cnt[0] - events_at_entry >= max_events or cnt[1] - steps_at_entry >= step_budget:
            return 0
        t, pinv = acc[0], acc[1]
        if t >= t_end:
            return 2
        if cnt[1] >= max_steps:
            return 3
        nf = cnt[2]
        if nf == 0:
            return 5
        capacity_now = capacity + capacity_per_drained * acc[7]
        h = min(h_next, t_end - t, longest_step(MAX_STAGES, rho))
        # a step spreads the pressure by one pore per stage: grow the box by as much
        if windowed:
            set_ring(win, p, t)
        elif grid_n > 0 and grow_where_reached(box, grid_n, p, floor, stage_count(h, rho) + 1):
            need_f0 = True
        field = (grid_n, box, cnt[3], act, apos, indptr, nbr, thr, g_eff, g_out, inv_vol, fnew,
                 nbox)  # fmt: skip
        if need_f0:
            out0 = sweep(field, p, p, f0, (0.0, 0.0, 0.0, 0.0), f0, True)
            need_f0 = False
        menisci0 = (on_t, on_p, c_on, head, nxt, p, f0, vol, g_num, ell, area)
        pump0 = (control, pinv, q_rate, capacity_now, ramp_rate)
        n_on = _list_candidates(h, menisci0, pump0, front, nf, tp, drained, pe, latched,
                                latching, inv_vol, cand, near, win, grid_n, t)  # fmt: skip
        if n_on < 0:
            _keep_f0(ctrl, need_f0 or windowed, out0)
            return CUT
        # F_I(y_n): the menisci's fluxes over an explicit-length step; the next landing
        meniscus_fluxes(dt_stable, n_on, menisci0, pump0, q0)
        t_land = np.inf
        for s in range(n_on):
            if q0[s] > 0.0:
                t_land = min(t_land, ell[on_t[s]] * area[on_t[s]] / q0[s])
        h = min(h, LAND * t_land)
        if h < EXPLICIT_SPAN * dt_stable:
            # Near a landing, or a fast transient: explicit steps until the event or the span.
            _unlist(n_on, on_t, on_p, head, cand)
            span = EXPLICIT_SPAN * (4.0 if t_land < EXPLICIT_SPAN * dt_stable else 1.0)
            before = cnt[1]
            status = explicit_advance(
                indptr, nbr, thr, tp, g_eff, g_num, area, pe, vol, g_out, outlet, grid_n, box,
                p, drained, ell, latched, front, fpos, act, apos, flux, p_next, on_t, on_p,
                landing, acc, cnt, order, via, series, dt_max, control, q_rate, capacity,
                capacity_per_drained, ramp_rate, latching, floor, pressure_step, ell0,
                1, t_end, max_steps, stop_at_breakthrough,
                int(span * dt_stable / dt_max) + 2, nbox, win, head,
            )  # fmt: skip
            ctrl[4] += cnt[1] - before
            ctrl[6] = 0.0  # the controller restarts
            need_f0 = True
            h_next = EXPLICIT_SPAN * dt_stable
            if status != 0:
                ctrl[0] = h_next
                _keep_f0(ctrl, True, out0)
                return status
            continue
        m = stage_count(h, rho)
        h = min(h, longest_step(m, rho))
        k = imex_stages(h, m, field, p, f0, out0, ybuf, rhs, zero, n_on, menisci0, pump0, q0,
                        qst, lst, pst, ast, r_ell, moved, win)  # fmt: skip
        ds, ps, qs = ybuf[k], pst[k], qst[k]
        ctrl[1] += m
        ctrl[5] = max(ctrl[5], m)
        # rejected outright: a meniscus past l = 0, or one past its threshold unlisted
        reject = 0.0
        for s in range(n_on):
            if lst[k, s] < 0.0:
                reject = 0.5
            elif moved[s] and lst[k, s] > ell[on_t[s]]:
                # the stages' weights of a meniscus that switched on or off inside the step
                # summed to a negative swept volume: the switch is not resolved
                reject = 0.5
        for s in range(nf if reject == 0.0 else 0):
            f = front[s]
            i = undrained_pore(tp, drained, f)
            if cand[f]:
                continue
            if windowed and not inside(win[2], grid_n, i):
                past = ps - far_pressure(win, i, t + h) > pe[f]
            else:
                past = ps - p[i] - ds[i] > pe[f]
            if past:
                reject = 0.5
                break
        if windowed and reject == 0.0 and far_meniscus(win, ps, 0.0, t + h, pe, tp, drained) >= 0:
            reject = 0.5  # a meniscus outside the window would start within the step
        for_event = reject > 0.0
        # the error estimate
        qsum0 = qsums = 0.0
        for s in range(n_on):
            qsum0 += q0[s]
            qsums += qs[s]
            i = on_p[s]
            if head[i] == s:
                fi[i] = implicit_rate(i, q0, head, nxt) + implicit_rate(i, qs, head, nxt)
        if windowed:
            ring_increment(win, ds, h)
        out_s = sweep(field, ds, ds, f0, (0.0, 0.0, 0.0, 0.0), fnew, True)
        err, stored, largest = step_error(h, field, ds, f0, fnew, fi, vol)
        for s in range(n_on):
            fi[on_p[s]] = 0.0
        fiinv = pump_rate(control, q_rate, capacity_now, ramp_rate, qsum0)
        fiinv += pump_rate(control, q_rate, capacity_now, ramp_rate, qsums)
        err = max(err, abs(0.8 * (pinv - ps) + 0.4 * h * fiinv)) / (tolerance * pressure_scale)
        if not (np.isfinite(err) and np.isfinite(ps) and np.isfinite(stored)):
            _unlist(n_on, on_t, on_p, head, cand)
            cnt[4] = -1
            _keep_f0(ctrl, True, out0)
            return 4
        if reject == 0.0 and err > 1.0:
            reject = max(0.2, 0.8 * err ** (-1.0 / 3.0))
        if reject > 0.0:
            ctrl[3] += 1
            ctrl[8] += 1 if for_event else 0
            ctrl[9] += m
            h_next = h * reject
            _unlist(n_on, on_t, on_p, head, cand)
            continue
        # accept
        _add_active(field, ds, p)
        if windowed:
            acc[11] += book_shadow(win, m, RING_FLUX)
            set_ring(win, p, t + h)
        f0, fnew = fnew, f0  # F_E(y_n+1) is the next step's F_E(y_n): swap, do not copy
        ctrl[11] = 1.0 - ctrl[11]
        out0 += out_s
        for s in range(n_on):
            if moved[s]:
                ell[on_t[s]] = lst[k, s]
        _unlist(n_on, on_t, on_p, head, cand)
        acc[3] += ast[k, 0]
        acc[4] += stored
        acc[5] += ast[k, 1]
        acc[2] += q_rate * h if control == CONTROL_RATE else ast[k, 0] + capacity_now * (ps - pinv)
        acc[8] += capacity_now * (ps - pinv)
        acc[1] = ps
        acc[0] = t + h
        cnt[1] += 1
        ctrl[2] += 1
        if grid_n == 0:
            for _r in range(m):
                spread(grid_n, box, cnt[3], act, apos, cnt, indptr, nbr, drained, p, floor)
            need_f0 = True
        if control == CONTROL_PRESSURE:
            rate = largest / h
            for s in range(n_on):
                rate = max(rate, qs[s] * inv_vol[on_p[s]])
            if rate * dt_max <= floor:
                ctrl[0] = h
                _keep_f0(ctrl, need_f0 or windowed, out0)
                return 6
        # the RKC code's predictive controller (Gustafsson): how the error grew with the step
        # over the last two steps, not the asymptotic h^3 law, sets the next step
        e = max(err, 1e-10)
        if ctrl[6] > 0.0 and ctrl[7] > 0.0:
            fac = 0.8 * (h / ctrl[7]) * ctrl[6] ** (1.0 / 3.0) / e ** (2.0 / 3.0)
        else:
            fac = 0.8 * e ** (-1.0 / 3.0)
        ctrl[6], ctrl[7] = e, h
        h_next = h * max(0.1, min(GROW, fac))


__all__ = ["CTRL", "N_CTRL", "STATUS", "rkc_advance"]
