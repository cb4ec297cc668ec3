"""Menisci and injection over one step of the viscous model (docs/model.md section 4).

Pure numba helpers on arrays, in scaled units (see :mod:`porenet.kinds.viscous.kernels.explicit`).

Over a step of length ``dt`` the menisci listed as candidates, the pores they enter and the
injection reservoir are implicit (backward Euler); the other fluxes of those pores are
explicit. A candidate meniscus ``m`` into pore ``i`` obeys a flux law in the pressure
difference ``D = p_inv' - p_i'`` at the end of the step:

* ``q = 0`` if ``D < c``,
* ``q = G D`` if ``D > c`` (``G = A k / l``, its conductance at the start of the step),
* ``0 <= q <= G c`` if ``D = c``: the meniscus **slides** on its threshold,

with ``c`` the entry pressure ``2 / r`` (rule "threshold") or 0 (a latched meniscus, rule
"latching"). The law is the convex closure of the paper's discontinuous one (a Filippov
solution): at small Ca a meniscus neither jumps on with the full flux ``G c`` nor stops, it
advances at the pace the pump sets with ``p_inv - p_i`` held at the entry pressure, and
an explicit decision on/off at the start of each step would make it chatter about its
threshold. The law is monotone in ``D``, so the step's equations have one solution:

* per pore (:func:`pore_response`): given ``p_inv'``, the pore's end pressure and the flux of
  each of its menisci (menisci into one pore are linked through ``head``/``nxt``);
* for the pump (:func:`meniscus_fluxes`): ``C (p_inv' - p_inv) = dt (Q - sum q(p_inv'))`` is
  one scalar equation, continuous, piecewise linear and increasing in ``p_inv'``, solved by
  Newton's method inside a bracket (exact once it lands on the right linear piece).

:func:`landing_step` finds the first instant a meniscus reaches length 0.

The helpers of one step take the candidate menisci and the pump as two named tuples,
:class:`~porenet.kinds.viscous.kernels.state.Menisci` (the listed menisci's throats, pores and
thresholds, the per-pore links, then the arrays they read) and
:class:`~porenet.kinds.viscous.kernels.state.Pump`.
"""

from __future__ import annotations

import numpy as np

from porenet.jit.jit import njit
from porenet.kinds.viscous.kernels.state import Control, Menisci, Pump


@njit(helper=True)
def undrained_pore(tp: np.ndarray, drained: np.ndarray, f: int) -> int:
    """The undrained pore of frontier throat ``f`` (the pore its meniscus enters)."""
    a = tp[f, 0]
    return tp[f, 1] if drained[a] else a


@njit(helper=True)
def pore_response(
    i: int, pnew: float, dt: float, menisci: Menisci
) -> tuple[float, float, float, int, float]:
    """Pore ``i`` over a step of ``dt`` that ends at invading pressure ``pnew``.

    Solves ``V (p_i' - pi_i) / dt = sum_m q_m(p_inv' - p_i')`` over the pore's listed
    menisci, ``pi_i = p_i + dt flux_i / V`` its explicit end pressure. Returns ``(Q, slope,
    D, slider, lam)``: the total meniscus flux into the pore, ``dQ / dp_inv'``, the end
    pressure difference ``D = p_inv' - p_i'``, the listed index of the meniscus that slides
    (-1 if none) and its flux. Every other meniscus carries ``G D`` if its threshold is below
    ``D``, else 0.
    """
    on_t, c_on, nxt = menisci.throat, menisci.threshold, menisci.next
    g_num, ell, vol = menisci.conductance, menisci.length, menisci.volume
    head, p, flux = menisci.head, menisci.pressure, menisci.flux
    vdt = vol[i] / dt
    y = pnew - (p[i] + dt * flux[i] / vol[i])  # D if no meniscus flows
    # Menisci whose threshold is below y flow, slide or stop; they are tried in decreasing
    # order of (threshold, index): (c_stop, s_stop) is the last one stopped.
    total_g = 0.0
    n_in = 0
    s = head[i]
    while s >= 0:
        if c_on[s] < y:
            total_g += g_num[on_t[s]] / ell[on_t[s]]
            n_in += 1
        s = nxt[s]
    c_stop, s_stop = np.inf, 0
    while n_in > 0:
        top, c_top = -1, -np.inf
        s = head[i]
        while s >= 0:
            c = c_on[s]
            below_stop = c < c_stop or (c == c_stop and s < s_stop)
            if c < y and below_stop and (c > c_top or (c == c_top and s > top)):
                top, c_top = s, c
            s = nxt[s]
        d = vdt * y / (vdt + total_g)
        if d > c_top:  # all of them flow
            return total_g * d, vdt * total_g / (vdt + total_g), d, -1, 0.0
        g_top = g_num[on_t[top]] / ell[on_t[top]]
        lam = vdt * (y - c_top) - (total_g - g_top) * c_top
        if lam >= 0.0:  # the top one slides at D = c_top (lam <= g_top c_top since d <= c_top)
            return vdt * (y - c_top), vdt, c_top, top, lam
        total_g -= g_top  # the top one stops
        n_in -= 1
        c_stop, s_stop = c_top, top
    return 0.0, 0.0, y, -1, 0.0


@njit(helper=True)
def meniscus_flux(s: int, d: float, slider: int, lam: float, menisci: Menisci) -> float:
    """Flux of listed meniscus ``s`` once its pore's response ``(D, slider, lam)`` is known."""
    on_t, c_on, g_num, ell = menisci.throat, menisci.threshold, menisci.conductance, menisci.length
    if s == slider:
        return lam
    if c_on[s] < d:
        return g_num[on_t[s]] / ell[on_t[s]] * d
    return 0.0


@njit(helper=True)
def _pump_residual(
    pnew: float, dt: float, n_on: int, menisci: Menisci, pump: Pump
) -> tuple[float, float]:
    """``C (p' - p_inv) / dt + sum q(p') - Q`` of rate control and its slope in ``p'``."""
    on_p, head = menisci.pore, menisci.head
    residual = pump.capacity * (pnew - pump.pressure) / dt - pump.rate
    slope = pump.capacity / dt
    for s in range(n_on):
        i = on_p[s]
        if head[i] == s:  # each pore once
            q, dq, _d, _slider, _lam = pore_response(i, pnew, dt, menisci)
            residual += q
            slope += dq
    return residual, slope


@njit(helper=True)
def invader_pressure(dt: float, n_on: int, menisci: Menisci, pump: Pump) -> float:
    """``p_inv`` at the end of a step of ``dt``: prescribed (pressure control, ramp) or the
    root of the rate-controlled reservoir equation.

    The residual is continuous, piecewise linear and increasing; it is negative where every
    meniscus is stopped (below every pore's ``pi_i + c``) and non-negative at the pressure
    the pump alone would reach. Newton's method from the upper end, kept inside the bracket
    (bisection when a step would leave it), ends exactly once it reaches the linear piece of
    the root. It stops when its correction is below one ulp, tested before the bracket: at
    the root an iterate is an end of the bracket, and sending that "outside" step to
    bisection cost ~35 needless halvings per solve (docs/performance.md). An Illinois
    secant in place of bisection was tried and took more iterations."""
    on_p, c_on = menisci.pore, menisci.threshold
    p, flux, vol = menisci.pressure, menisci.flux, menisci.volume
    if pump.control == Control.PRESSURE:
        return pump.pressure
    if pump.control == Control.RAMP:
        return pump.pressure + pump.ramp_rate * dt
    hi = pump.pressure + dt * pump.rate / pump.capacity
    lo = hi
    for s in range(n_on):
        i = on_p[s]
        lo = min(lo, p[i] + dt * flux[i] / vol[i] + c_on[s])
    if lo >= hi:
        return hi
    x = hi
    for _ in range(200):
        residual, slope = _pump_residual(x, dt, n_on, menisci, pump)
        if residual == 0.0:
            return x
        if residual > 0.0:
            hi = x
        else:
            lo = x
        nxt_x = x - residual / slope
        if nxt_x == x:
            return x
        if not lo < nxt_x < hi:
            nxt_x = 0.5 * (lo + hi)
        if hi - lo <= 1e-15 * max(abs(hi), abs(lo)):
            return x
        x = nxt_x
    return x


@njit(helper=True)
def meniscus_fluxes(dt: float, n_on: int, menisci: Menisci, pump: Pump, q_out: np.ndarray) -> float:
    """Solve a step of ``dt``: write each listed meniscus' flux into ``q_out[:n_on]`` and
    return the invading pressure at its end."""
    on_p, head, nxt = menisci.pore, menisci.head, menisci.next
    pnew = invader_pressure(dt, n_on, menisci, pump)
    for s in range(n_on):
        i = on_p[s]
        if head[i] == s:  # each pore once, then each of its menisci
            _q, _dq, d, slider, lam = pore_response(i, pnew, dt, menisci)
            r = s
            while r >= 0:
                q_out[r] = meniscus_flux(r, d, slider, lam, menisci)
                r = nxt[r]
    return pnew


@njit(helper=True)
def pore_after(i: int, pnew: float, dt: float, menisci: Menisci) -> float:
    """Pressure of pore ``i`` at the end of the step (explicit fluxes, implicit menisci)."""
    p, flux, vol = menisci.pressure, menisci.flux, menisci.volume
    q, _dq, _d, _slider, _lam = pore_response(i, pnew, dt, menisci)
    return p[i] + dt * (flux[i] + q) / vol[i]


@njit(helper=True)
def step_change(dt: float, pnew: float, n_on: int, menisci: Menisci, pinv: float) -> float:
    """Largest change over a solved step of the invading pressure and of the pressure
    difference across a candidate meniscus, ``|D' - D|`` (what decides when menisci start
    and stop; the accuracy limit ``pressure_step`` bounds it)."""
    on_p, head, p = menisci.pore, menisci.head, menisci.pressure
    change = abs(pnew - pinv)
    for s in range(n_on):
        i = on_p[s]
        if head[i] == s:
            change = max(change, abs(pnew - pore_after(i, pnew, dt, menisci) - (pinv - p[i])))
    return change


@njit(helper=True)
def shortest_remaining(
    dt: float, n_on: int, menisci: Menisci, pump: Pump, q_out: np.ndarray
) -> tuple[float, int, float]:
    """Solve a step of ``dt`` (fluxes into ``q_out``): the smallest remaining meniscus length
    ``l - q dt / A`` among the listed menisci that flow, its index in ``on_t`` (``inf, -1``
    if none flows) and the invading pressure at the end of the step."""
    on_t, ell, area = menisci.throat, menisci.length, menisci.area
    pnew = meniscus_fluxes(dt, n_on, menisci, pump, q_out)
    shortest = np.inf
    arg = -1
    for s in range(n_on):
        if q_out[s] > 0.0:
            f = on_t[s]
            remaining = ell[f] - q_out[s] * dt / area[f]
            if remaining < shortest:
                shortest = remaining
                arg = s
    return shortest, arg, pnew


@njit(helper=True)
def landing_step(
    dt_hi: float, ell0: float, n_on: int, menisci: Menisci, pump: Pump, q_out: np.ndarray
) -> tuple[float, int, float]:
    """The step: ``dt_hi`` if no meniscus lands within it, else the first landing.

    The smallest remaining length after a step of ``dt``, ``phi(dt)``, is continuous with
    ``phi(0) > 0``; if ``phi(dt_hi) <= 0`` its first root is bracketed and found by regula
    falsi (Illinois variant) to ``1e-14`` relative in the step or ``1e-14 l0`` in the
    length. Returns ``(dt, index in on_t of the landing meniscus or -1, p_inv at the end)``
    with ``q_out`` holding the fluxes of that step; the landing meniscus is within
    ``1e-14 l0`` of 0 (it may be a hair past it, never short).
    """
    on_t, ell = menisci.throat, menisci.length
    phi_hi, arg, p_hi = shortest_remaining(dt_hi, n_on, menisci, pump, q_out)
    if phi_hi > 0.0:
        return dt_hi, -1, p_hi
    lo, phi_lo = 0.0, np.inf
    for s in range(n_on):
        phi_lo = min(phi_lo, ell[on_t[s]])
    hi = dt_hi
    w_lo, w_hi = phi_lo, phi_hi  # secant weights (halved on a repeated side: Illinois)
    side = 0
    last_at_hi = True  # q_out holds the fluxes of the step hi
    for _ in range(200):
        if hi - lo <= 1e-14 * hi or -phi_hi <= 1e-14 * ell0:
            break
        mid = hi - w_hi * (hi - lo) / (w_hi - w_lo)
        if not lo < mid < hi:
            mid = 0.5 * (lo + hi)
        phi_mid, arg_mid, p_mid = shortest_remaining(mid, n_on, menisci, pump, q_out)
        if phi_mid > 0.0:
            lo, w_lo = mid, phi_mid
            last_at_hi = False
            if side == -1:
                w_hi *= 0.5
            side = -1
        else:
            hi, phi_hi, w_hi, arg, p_hi = mid, phi_mid, phi_mid, arg_mid, p_mid
            last_at_hi = True
            if side == 1:
                w_lo *= 0.5
            side = 1
    if not last_at_hi:
        p_hi = meniscus_fluxes(hi, n_on, menisci, pump, q_out)
    return hi, arg, p_hi
