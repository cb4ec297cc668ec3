"""Menisci and injection over one step of the viscous model (MODEL.md section 4).

Pure numba helpers on arrays, in scaled units (see :mod:`porenet.kernels.viscous`). Over a
step of length ``dt`` the advancing menisci and the injection reservoir are implicit (backward
Euler): each meniscus pore's new pressure is linear in the new invading pressure, so the
reservoir equation is one scalar equation. :func:`landing_step` finds the first instant a
meniscus reaches length 0.

The helpers of one step take the advancing menisci and the pump as two tuples:
``menisci = (on_t, on_p, p, flux, gsum, vol, g_num, ell, area)`` (the listed menisci's
throats and pores, then the arrays they read) and
``pump = (control, pinv, q_rate, capacity, ramp_rate)`` (see :func:`explicit_advance`).
"""

from __future__ import annotations

import numpy as np

from porenet.kernels._jit import njit

CONTROL_RATE, CONTROL_PRESSURE, CONTROL_RAMP = 0, 1, 2


@njit(helper=True)
def invader_pressure(
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
def pore_after(
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
def meniscus_terms(dt: float, n_on: int, menisci: tuple, pump: tuple, q_out: np.ndarray) -> float:
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
    pnew = invader_pressure(control, pinv, dt, q_rate, capacity, ramp_rate, s0, s1)
    for s in range(n_on):
        i = on_p[s]
        f = on_t[s]
        q_out[s] = g_num[f] / ell[f] * (pnew - pore_after(dt, i, p, flux, gsum, vol, pnew))
    return pnew


@njit(helper=True)
def pressure_rate(n_on: int, menisci: tuple, pump: tuple, ell0: float) -> float:
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
def shortest_remaining(
    dt: float, n_on: int, menisci: tuple, pump: tuple, q_out: np.ndarray
) -> tuple[float, int]:
    """After a step of ``dt``: the smallest remaining meniscus length ``l - q dt / A`` among
    the advancing menisci, and its index in ``on_t`` (``inf, -1`` if none advances)."""
    on_t, ell, area = menisci[0], menisci[7], menisci[8]
    meniscus_terms(dt, n_on, menisci, pump, q_out)
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
def landing_step(
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
    phi_hi, arg = shortest_remaining(dt_hi, n_on, menisci, pump, q_out)
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
        phi_mid, arg_mid = shortest_remaining(mid, n_on, menisci, pump, q_out)
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
