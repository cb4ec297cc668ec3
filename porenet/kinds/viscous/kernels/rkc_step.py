"""One IMEX Runge-Kutta-Chebyshev step of the viscous model, and its error estimate.

The stages and the local error estimate of the stabilised integrator; the scheme, the events
and the step control are described in :mod:`porenet.kinds.viscous.kernels.rkc`, which drives these
functions. Pure numba functions on arrays, in scaled units
(:mod:`porenet.kinds.viscous.kernels.explicit`).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from porenet.jit.jit import THREADS, njit, prange, serial_and_parallel, threaded_box
from porenet.kinds.viscous.kernels.chebyshev import coefficients, sweep
from porenet.kinds.viscous.kernels.menisci import meniscus_fluxes, pore_after
from porenet.kinds.viscous.kernels.state import LISTS, WINDOWS, Control, Menisci, Pump, Sweep
from porenet.kinds.viscous.kernels.window import (
    Mode,
    Window,
    WindowInt,
    ring_increment,
    shadow_stage,
)


class StepStart(NamedTuple):
    """The state ``y_n`` an RKC step starts from (besides the menisci's lengths).

    Attributes
    ----------
    pressure : ndarray of float64, shape (N,)
    flux : ndarray of float64, shape (N,)
        ``F_E(y_n)``, the explicit (Darcy) flux into each pore.
    outflow : float
        Its outflow rate.
    meniscus_flux : ndarray of float64, shape (M,)
        ``F_I(y_n)``: each candidate's flux over one explicit-length step from ``y_n``.
    """

    pressure: np.ndarray
    flux: np.ndarray
    outflow: float
    meniscus_flux: np.ndarray


class Stages(NamedTuple):
    """The stage buffers of an RKC step; stage ``j`` is row ``(j - 1) % 3``.

    Attributes
    ----------
    increments : ndarray of float64, shape (3, N)
        The pores' increments ``W_j - y_n``.
    rhs : ndarray of float64, shape (N,)
        The stages' right-hand sides at the menisci's pores.
    zero : ndarray of float64, shape (N,)
        Zeros (the menisci's explicit flux inside a stage).
    flux, length : ndarray of float64, shape (3, M)
        Each candidate's flux and meniscus length.
    invading_pressure : ndarray of float64, shape (3,)
    volumes : ndarray of float64, shape (3, 2)
        The drained and the outflow volume since ``y_n``.
    length_rhs : ndarray of float64, shape (M,)
        Right-hand sides of the meniscus lengths.
    moved : ndarray of bool, shape (M,)
        Whether candidate ``s`` flowed in any stage.
    """

    increments: np.ndarray
    rhs: np.ndarray
    zero: np.ndarray
    flux: np.ndarray
    length: np.ndarray
    invading_pressure: np.ndarray
    volumes: np.ndarray
    length_rhs: np.ndarray
    moved: np.ndarray


@njit(helper=True)
def implicit_rate(i: int, q: np.ndarray, head: np.ndarray, nxt: np.ndarray) -> float:
    """Volumetric meniscus flux into pore ``i`` (its listed menisci, fluxes ``q``)."""
    total = 0.0
    s = head[i]
    while s >= 0:
        total += q[s]
        s = nxt[s]
    return total


@njit(helper=True)
def pump_rate(control: int, q_rate: float, capacity: float, ramp: float, qsum: float) -> float:
    """``dp_inv/dt`` given the total meniscus flux."""
    if control == Control.RATE:
        return (q_rate - qsum) / capacity
    if control == Control.RAMP:
        return ramp
    return 0.0


@njit
def stage_solve(
    dt_i: float,
    n_on: int,
    menisci: Menisci,
    pump: Pump,
    q_out: np.ndarray,
    p: np.ndarray,
    d: np.ndarray,
) -> float:
    """The implicit part of a stage. ``d`` holds the stage's increment without it; the pores'
    right-hand sides ``p + d`` go into ``p`` of ``menisci`` (its ``flux`` is zero). Solve over
    ``dt_i``, write the menisci's pores' increments into ``d`` and the meniscus fluxes into
    ``q_out``; return the stage's ``p_inv``."""
    on_p, head, rhs = menisci.pore, menisci.head, menisci.pressure
    for s in range(n_on):
        i = on_p[s]
        rhs[i] = p[i] + d[i]
    pnew = meniscus_fluxes(dt_i, n_on, menisci, pump, q_out)
    for s in range(n_on):
        i = on_p[s]
        if head[i] == s:
            d[i] = pore_after(i, pnew, dt_i, menisci) - p[i]
    return pnew


@njit(helper=True)
def _row_scaled(f: np.ndarray, inv_vol: np.ndarray, dt: float, out: np.ndarray) -> None:
    """``out = dt f / V`` over aligned views of a run of pores: the index is the loop
    counter, so no sign test and the loop compiles to SIMD instructions (indexing the full
    arrays with ``i * n + j`` does not, and took as long as a stage sweep at n = 400)."""
    for j in range(f.size):
        out[j] = dt * f[j] * inv_vol[j]


def _scaled_rows(
    n: int, box: np.ndarray, f: np.ndarray, inv_vol: np.ndarray, dt: float, out: np.ndarray
) -> None:
    """``out = dt f / V`` over the box's rows (:func:`_row_scaled`)."""
    for i in prange(box[0], box[1]):
        a, b = i * n + box[2], i * n + box[3]
        _row_scaled(f[a:b], inv_vol[a:b], dt, out[a:b])


_scaled_rows_serial, _scaled_rows_parallel = serial_and_parallel(_scaled_rows)


@njit
def _scaled_rate(field: Sweep, f: np.ndarray, dt: float, out: np.ndarray) -> None:
    """``out = dt f / V`` over the active pores of ``field`` (the first stage's increment)."""
    grid_n, box, na, act = field.grid_n, field.box, field.n_active, field.pores
    inv_vol = field.inverse_volume
    if LISTS and grid_n == 0:
        for s in range(na):
            k = act[s]
            out[k] = dt * f[k] * inv_vol[k]
    elif THREADS and threaded_box(box):
        _scaled_rows_parallel(grid_n, box, f, inv_vol, dt, out)
    else:
        _scaled_rows_serial(grid_n, box, f, inv_vol, dt, out)


@njit
def imex_stages(
    h: float,
    m: int,
    field: Sweep,
    start: StepStart,
    n_on: int,
    menisci0: Menisci,
    pump0: Pump,
    stages: Stages,
    window: Window,
) -> int:
    """The ``m`` stages of an RKC step of ``h`` from ``y_n`` (``start``, and the menisci's
    lengths and ``p_inv`` in ``menisci0`` and ``pump0``) into ``stages`` (:class:`Stages`).
    Returns the buffer of ``y_{n+1}``.

    In a window's fine integration (:mod:`porenet.kinds.viscous.kernels.window`) the ring pores'
    increments at each stage's time ``c_j h`` are written into the stage buffers before they are
    swept; in it and in the coarse step over everything the volume each ring throat carries follows
    the stages (:func:`porenet.kinds.viscous.kernels.window.shadow_stage`).
    """
    p, f0, out0, q0 = start.pressure, start.flux, start.outflow, start.meniscus_flux
    ybuf, rhs, zero = stages.increments, stages.rhs, stages.zero
    qst, lst, pst, ast = stages.flux, stages.length, stages.invading_pressure, stages.volumes
    r_ell, moved = stages.length_rhs, stages.moved
    on_t, on_p, head, nxt = menisci0.throat, menisci0.pore, menisci0.head, menisci0.next
    ell, area = menisci0.length, menisci0.area
    control, pinv, q_rate = pump0.control, pump0.pressure, pump0.rate
    capacity, ramp = pump0.capacity, pump0.ramp_rate
    inv_vol, g_eff, g_out = field.inverse_volume, field.between, field.outlet
    mode = window.ints[WindowInt.MODE]
    windowed = WINDOWS and mode != Mode.OFF
    dirichlet = mode == Mode.FINE
    mus1, coef = coefficients(m)
    dt_i = h * mus1
    if windowed:
        shadow_stage(window, 1, p, g_eff, g_out, p, 0.0, 0.0, 0.0, dt_i)
    c_prev, c_prev2 = mus1, 0.0  # the stage times of W_{j-1} and W_{j-2} (fractions of h)
    qsum0 = 0.0
    for s in range(n_on):
        qsum0 += q0[s]
    fiinv0 = pump_rate(control, q_rate, capacity, ramp, qsum0)
    # the stages' implicit problems: right-hand sides for pressures, no explicit flux
    menisci = Menisci(on_t, on_p, menisci0.threshold, head, nxt, rhs, zero, menisci0.volume,
                      menisci0.conductance, ell, area)  # fmt: skip
    # stage 1: W_1 = y_n + dt_i F_E(y_n) + dt_i F_I(W_1), no stencil needed
    d1 = ybuf[0]
    _scaled_rate(field, f0, dt_i, d1)
    pst[0] = stage_solve(dt_i, n_on, menisci, pump0, qst[0], p, d1)
    qs = 0.0
    for s in range(n_on):
        lst[0, s] = ell[on_t[s]] - dt_i * qst[0, s] / area[on_t[s]]
        moved[s] = q0[s] > 0.0 or qst[0, s] > 0.0
        qs += qst[0, s]
    ast[0, 0] = dt_i * qs
    ast[0, 1] = dt_i * out0
    k = 0
    for j in range(2, m + 1):
        mu, nu, mus, gam = coef[j - 2, 0], coef[j - 2, 1], coef[j - 2, 2], coef[j - 2, 3]
        c0 = 1.0 - mu - nu
        prev, k, prev2 = (j - 2) % 3, (j - 1) % 3, (j - 3) % 3
        dout = ybuf[k]
        # d_j = mu d_{j-1} + nu d_{j-2} + h mu~ L d_{j-1} + h (mu~ + g~) F_E(y_n)  (d_0 = 0)
        coef_j = (mu, 0.0 if j == 2 else nu, h * mus, h * (mus + gam))
        d2buf = ybuf[prev] if j == 2 else ybuf[prev2]  # (its weight is 0 at j = 2)
        if dirichlet:
            ring_increment(window, ybuf[prev], c_prev * h)
        if windowed:
            shadow_stage(window, j, ybuf[prev], g_eff, g_out, p, mu, nu, h * mus, h * (mus + gam))
        c_prev, c_prev2 = mu * c_prev + nu * c_prev2 + mus + gam, c_prev
        out_prev = out0 + sweep(field, ybuf[prev], d2buf, f0, coef_j, dout, False)
        w0i = h * (gam - c0 * mus1)  # weight of F_I(y_n)
        w2i = -h * nu * mus1  # weight of F_I(W_{j-2})
        q2 = q0 if j == 2 else qst[prev2]
        qsum2 = 0.0
        for s in range(n_on):
            qsum2 += q2[s]
        # right-hand sides of the implicit part: pores, reservoir, meniscus lengths
        for s in range(n_on):
            i = on_p[s]
            if head[i] == s:
                dout[i] += (w0i * implicit_rate(i, q0, head, nxt)
                            + w2i * implicit_rate(i, q2, head, nxt)) * inv_vol[i]  # fmt: skip
        for s in range(n_on):
            f = on_t[s]
            l2 = ell[f] if j == 2 else lst[prev2, s]
            swept = (w0i * q0[s] + w2i * q2[s]) / area[f]
            r_ell[s] = c0 * ell[f] + mu * lst[prev, s] + nu * l2 - swept
        r_inv = pinv
        if control != Control.PRESSURE:
            pinv2 = pinv if j == 2 else pst[prev2]
            r_inv = c0 * pinv + mu * pst[prev] + nu * pinv2 + w0i * fiinv0
            r_inv += w2i * pump_rate(control, q_rate, capacity, ramp, qsum2)
        pump = Pump(control, r_inv, q_rate, capacity, ramp)
        pst[k] = stage_solve(dt_i, n_on, menisci, pump, qst[k], p, dout)
        qs = 0.0
        for s in range(n_on):
            lst[k, s] = r_ell[s] - dt_i * qst[k, s] / area[on_t[s]]
            moved[s] |= qst[k, s] > 0.0
            qs += qst[k, s]
        d2 = 0.0 if j == 2 else ast[prev2, 0]
        o2 = 0.0 if j == 2 else ast[prev2, 1]
        ast[k, 0] = mu * ast[prev, 0] + nu * d2 + w0i * qsum0 + w2i * qsum2 + dt_i * qs
        ast[k, 1] = mu * ast[prev, 1] + nu * o2 + h * mus * out_prev + h * gam * out0
    return k


@njit(helper=True)
def _error_run(
    lo: int,
    hi: int,
    h: float,
    ds: np.ndarray,
    f0: np.ndarray,
    fnew: np.ndarray,
    fi: np.ndarray,
    vol: np.ndarray,
    inv_vol: np.ndarray,
) -> tuple[float, float, float]:
    """:func:`step_error` over the pores ``[lo, hi)``: (max error, stored volume, max |ds|)."""
    err = 0.0
    stored = 0.0
    largest = 0.0
    for k in range(lo, hi):
        fnew[k] += f0[k]
        change = ds[k]
        e = abs(-0.8 * change + 0.4 * h * (f0[k] + fnew[k] + fi[k]) * inv_vol[k])
        err = max(err, e)
        stored += vol[k] * change
        largest = max(largest, abs(change))
    return err, stored, largest


def _error_rows(
    h: float,
    field: Sweep,
    count: int,
    ds: np.ndarray,
    f0: np.ndarray,
    fnew: np.ndarray,
    fi: np.ndarray,
    vol: np.ndarray,
    partial: np.ndarray,
) -> None:
    """:func:`_error_run` over the box's rows (grids) or over the ``count`` listed active
    pores, into ``partial[:, r]``."""
    n, box, act, inv_vol = field.grid_n, field.box, field.pores, field.inverse_volume
    for r in prange(count):
        if n > 0:
            lo = (box[0] + r) * n + box[2]
            hi = lo + box[3] - box[2]
        else:
            lo = act[r]
            hi = lo + 1
        partial[0, r], partial[1, r], partial[2, r] = _error_run(
            lo, hi, h, ds, f0, fnew, fi, vol, inv_vol
        )


_error_rows_serial, _error_rows_parallel = serial_and_parallel(_error_rows)


@njit
def step_error(
    h: float,
    field: Sweep,
    ds: np.ndarray,
    f0: np.ndarray,
    fnew: np.ndarray,
    fi: np.ndarray,
    vol: np.ndarray,
) -> tuple[float, float, float]:
    """Over the active pores, with ``ds = y_n+1 - y_n`` and ``fnew = L ds`` on entry (turned
    into ``F_E(y_n+1) = f0 + L ds``): ``max |-0.8 ds + 0.4 h (F(y_n) + F(y_n+1)) / V|`` (``F``
    is ``F_E`` plus ``fi`` at the menisci's pores), the stored volume change ``sum V ds`` and
    ``max |ds|``. On grids the sums are taken per row, then over the rows in order (by
    several threads on large boxes: the same bits on any number of them)."""
    grid_n, box, na = field.grid_n, field.box, field.n_active
    count = (box[1] - box[0]) if grid_n > 0 else na
    partial = np.empty((3, max(count, 0)))
    args = (h, field, count, ds, f0, fnew, fi, vol, partial)
    if THREADS and grid_n > 0 and threaded_box(box):
        _error_rows_parallel(*args)
    else:
        _error_rows_serial(*args)
    err = 0.0
    stored = 0.0
    largest = 0.0
    for r in range(count):
        err = max(err, partial[0, r])
        stored += partial[1, r]
        largest = max(largest, partial[2, r])
    return err, stored, largest
