"""The menisci and the pump over one step (:mod:`porenet.kinds.viscous.kernels.menisci`) against
slow, obvious references: the end-of-step pressure difference of a pore found by bisection on
its (monotone) balance, the invading pressure by bisection on the reservoir's balance, the
landing step by bisection on the shortest remaining length."""

from __future__ import annotations

import numpy as np
import pytest

from porenet.kinds.viscous.kernels.menisci import (
    invader_pressure,
    landing_step,
    meniscus_fluxes,
    pore_response,
)
from porenet.kinds.viscous.kernels.state import Control, Menisci, Pump


def one_pore(thresholds, conductances, rng):
    """Menisci all into pore 0 (candidates 0..k-1), with the given thresholds and conductances
    (``A k`` with length 1)."""
    k = len(thresholds)
    head = np.array([k - 1], np.int64)
    nxt = np.arange(-1, k - 1, dtype=np.int64)  # k-1 -> k-2 -> ... -> 0 -> -1
    return Menisci(
        throat=np.arange(k, dtype=np.int64),
        pore=np.zeros(k, np.int64),
        threshold=np.asarray(thresholds, float),
        head=head,
        next=nxt,
        pressure=np.array([rng.uniform(0.0, 0.5)]),
        flux=np.array([rng.uniform(-0.5, 0.5)]),
        volume=np.array([rng.uniform(0.5, 2.0)]),
        conductance=np.asarray(conductances, float),
        length=np.ones(k),
        area=np.ones(k),
    )


def flux_law(d, c, g):
    """The threshold law's flux for end difference ``d``, away from the threshold."""
    return g * d if d > c else 0.0


def reference_response(pnew, dt, menisci):
    """``D = p_inv' - p'``: the root of ``vdt (y - D) - sum q(D)``, decreasing in D (a jump
    at a threshold is where a meniscus slides), by bisection."""
    vdt = menisci.volume[0] / dt
    y = pnew - (menisci.pressure[0] + dt * menisci.flux[0] / menisci.volume[0])
    c, g = menisci.threshold, menisci.conductance

    def balance(d):
        return vdt * (y - d) - sum(flux_law(d, c[s], g[s]) for s in range(len(c)))

    lo, hi = min(y, 0.0) - 10.0, max(y, 0.0) + 10.0
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if balance(mid) > 0:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


@pytest.mark.parametrize("seed", range(8))
def test_pore_response_is_the_root_of_the_pore_balance(seed: int) -> None:
    rng = np.random.default_rng(seed)
    k = int(rng.integers(1, 5))
    menisci = one_pore(rng.uniform(0.2, 1.5, k), rng.uniform(0.5, 3.0, k), rng)
    pnew, dt = rng.uniform(0.0, 2.5), rng.uniform(0.01, 0.5)
    q, _slope, d, slider, lam = pore_response(0, pnew, dt, menisci)
    assert d == pytest.approx(reference_response(pnew, dt, menisci), abs=1e-9)
    # the pore's balance closes with the fluxes the kernel reports
    vdt = menisci.volume[0] / dt
    y = pnew - (menisci.pressure[0] + dt * menisci.flux[0] / menisci.volume[0])
    assert q == pytest.approx(vdt * (y - d), rel=1e-12, abs=1e-12)
    if slider >= 0:  # a sliding meniscus sits on its threshold, with a flux in [0, G c]
        assert d == pytest.approx(menisci.threshold[slider], rel=1e-12)
        assert -1e-12 <= lam <= menisci.conductance[slider] * menisci.threshold[slider] + 1e-12


@pytest.mark.parametrize("seed", range(6))
def test_rate_controlled_invader_pressure_balances_the_reservoir(seed: int) -> None:
    rng = np.random.default_rng(10 + seed)
    k = int(rng.integers(1, 4))
    menisci = one_pore(rng.uniform(0.2, 1.0, k), rng.uniform(0.5, 3.0, k), rng)
    dt, capacity, rate = 0.2, rng.uniform(0.1, 2.0), rng.uniform(0.5, 5.0)
    pump = Pump(int(Control.RATE), 0.3, rate, capacity, 0.0)
    q = np.zeros(k)
    pnew = meniscus_fluxes(dt, k, menisci, pump, q)
    assert pnew == pytest.approx(invader_pressure(dt, k, menisci, pump), rel=1e-15)
    # C (p' - p) / dt = Q - sum q, the obvious way
    assert capacity * (pnew - 0.3) / dt == pytest.approx(rate - q.sum(), rel=1e-9, abs=1e-9)
    # pressure control holds it, a ramp raises it linearly
    held = Pump(int(Control.PRESSURE), 0.7, 0.0, capacity, 0.0)
    assert invader_pressure(dt, k, menisci, held) == 0.7
    ramp = Pump(int(Control.RAMP), 0.7, 0.0, capacity, 2.0)
    assert invader_pressure(dt, k, menisci, ramp) == pytest.approx(0.7 + 2.0 * dt)


def test_landing_step_lands_the_first_meniscus_on_zero() -> None:
    """The step at which the shortest meniscus reaches l = 0, against bisection on the
    remaining length of a step of fixed pressures."""
    rng = np.random.default_rng(3)
    menisci = one_pore([0.1, 0.2], [2.0, 1.0], rng)._replace(length=np.array([0.05, 0.3]))
    pump = Pump(int(Control.PRESSURE), 2.0, 0.0, 1.0, 0.0)
    q = np.zeros(2)
    dt, event, _ = landing_step(1.0, 2.0, 2, menisci, pump, q)
    assert event == 0
    remaining = menisci.length[0] - q[0] * dt / menisci.area[0]
    assert abs(remaining) <= 1e-13 * 2.0

    def shortest(step):
        fluxes = np.zeros(2)
        meniscus_fluxes(step, 2, menisci, pump, fluxes)
        return min(menisci.length - fluxes * step / menisci.area)

    lo, hi = 0.0, 1.0
    for _ in range(100):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if shortest(mid) > 0 else (lo, mid)
    assert dt == pytest.approx(0.5 * (lo + hi), rel=1e-10)
