"""Runge-Kutta-Chebyshev numerics (:mod:`porenet.kinds.viscous.kernels.chebyshev`): stability of the
IMEX scheme for the stage counts used, its order, the two sweeps, the spectral radius."""

from __future__ import annotations

import math

import numpy as np
import pytest

from porenet.kinds.viscous.kernels.chebyshev import (
    coefficients,
    csr_stage,
    grid_stage,
    longest_step,
    spectral_radius,
    stage_count,
)
from porenet.kinds.viscous.kernels.state import Sweep


def amplification(z_e: float, z_i: float, m: int) -> float:
    """One IMEX RKC step of ``y' = (z_e + z_i) y`` with ``h = 1`` (z_e explicit, z_i implicit),
    written from the stage formulas of :mod:`porenet.kinds.viscous.kernels.rkc`."""
    mus1, coef = coefficients(m)
    y0 = 1.0
    fe0, fi0 = z_e * y0, z_i * y0
    y1 = (y0 + mus1 * fe0) / (1.0 - mus1 * z_i)
    ym2, ym1, fim2, fim1 = y0, y1, fi0, z_i * y1
    for mu, nu, mus, gam in coef:
        c0 = 1.0 - mu - nu
        rhs = c0 * y0 + mu * ym1 + nu * ym2 + mus * z_e * ym1 + gam * fe0
        rhs += (gam - c0 * mus1) * fi0 - nu * mus1 * fim2
        y = rhs / (1.0 - mus1 * z_i)
        ym2, ym1, fim2, fim1 = ym1, y, fim1, z_i * y
    return ym1


@pytest.mark.parametrize("m", [3, 4, 5, 8, 13, 40, 120])
def test_imex_steps_are_stable_for_the_stage_counts_used(m):
    """For every explicit eigenvalue the stage count admits (h rho <= longest_step(m, 1)) and
    any stiff implicit one, |R| <= 1: the rule of the RKC code, checked on the IMEX pair
    (with the bare bound 0.653 m^2 the m = 4 step would amplify by 1.27)."""
    z_e = -np.linspace(0.0, longest_step(m, 1.0), 201)
    worst = max(
        abs(amplification(ze, zi, m))
        for ze in z_e
        for zi in (0.0, -1e-3, -0.1, -1.0, -10.0, -1e3, -1e6)
    )
    assert worst <= 1.0 + 1e-12


def test_stage_count_and_longest_step_are_inverse():
    for rho in (0.5, 7.7, 11.0):
        for h in (0.01, 1.0, 17.0, 400.0):
            m = stage_count(h, rho)
            assert m >= 3
            assert h <= longest_step(m, rho) * (1 + 1e-12) or m == 400


def test_second_order_in_the_explicit_part():
    """y' = -y to t = 2 with the explicit part only: halving h divides the error by ~4."""
    errors = []
    for h in (0.2, 0.1, 0.05):
        y = 1.0
        for _ in range(round(2 / h)):
            y *= amplification(-h, 0.0, 5)
        errors.append(abs(y - math.exp(-2.0)))
    orders = [math.log2(errors[k] / errors[k + 1]) for k in range(2)]
    assert all(1.9 < o < 2.2 for o in orders), orders


def square_grid(n: int, rng: np.random.Generator):
    """Canonical n x n grid arrays: conductances, outlet links, CSR adjacency."""
    m = 2 * n * (n - 1)
    g = rng.uniform(0.1, 1.4, m)
    g_out = np.zeros(n * n)
    idx = np.arange(n * n).reshape(n, n)
    for edge in (idx[0], idx[-1], idx[:, 0], idx[:, -1]):
        g_out[edge] += 1.0
    a = np.r_[idx[:, :-1].ravel(), idx[:-1, :].ravel()]
    b = np.r_[idx[:, 1:].ravel(), idx[1:, :].ravel()]
    tp = np.stack([a, b], axis=1)
    nbrs = [[] for _ in range(n * n)]
    for t, (i, j) in enumerate(tp):
        nbrs[i].append((j, t))
        nbrs[j].append((i, t))
    indptr = np.cumsum([0] + [len(x) for x in nbrs])
    nbr = np.array([j for x in nbrs for j, _ in x])
    thr = np.array([t for x in nbrs for _, t in x])
    return g, g_out, tp, indptr, nbr, thr


def test_grid_and_list_sweeps_agree():
    """One stage over the whole 7 x 7 grid: the stencil sweep and the list sweep give the same
    values and outflow rate (to round-off: their sums run in different orders), and the stage
    is the combination it documents, ``c1 y1 + c2 y2 + (ce L y1 + cf f0) / V``."""
    rng = np.random.default_rng(3)
    n = 7
    g, g_out, _tp, indptr, nbr, thr = square_grid(n, rng)
    vol = rng.uniform(0.5, 1.5, n * n)
    inv_vol = 1.0 / vol
    y1, y2, f0 = (rng.standard_normal(n * n) for _ in range(3))
    coef = (0.9, -0.2, 0.05, 0.01)
    box = np.array([0, n, 0, n])
    act = np.arange(n * n)
    apos = np.arange(n * n)
    grid = Sweep(n, box, n * n, act, apos, indptr, nbr, thr, g, g_out, inv_vol, np.zeros(n * n),
                 box)  # fmt: skip
    listed = grid._replace(grid_n=0)
    for flux_only in (False, True):
        a, b = np.zeros(n * n), np.zeros(n * n)
        out_a = grid_stage(grid, y1, y2, f0, coef, a, flux_only)
        out_b = csr_stage(listed, y1, y2, f0, coef, b, flux_only)
        np.testing.assert_allclose(a, b, rtol=1e-13, atol=1e-13)
        np.testing.assert_allclose(out_a, out_b, rtol=1e-13)
    # the combination itself, against numpy
    flux = np.zeros(n * n)
    grid_stage(grid, y1, y2, f0, coef, flux, True)
    c1, c2, ce, cf = coef
    expected = c1 * y1 + c2 * y2 + (ce * flux + cf * f0) * inv_vol
    out = np.zeros(n * n)
    grid_stage(grid, y1, y2, f0, coef, out, False)
    np.testing.assert_allclose(out, expected, rtol=1e-13, atol=1e-13)


def test_spectral_radius_matches_a_dense_eigensolve():
    """On a 12 x 12 grid with unequal pore volumes: within 2 % above the largest eigenvalue
    of V^-1 L, and never above the Gershgorin bound."""
    rng = np.random.default_rng(1)
    n = 12
    g, g_out, tp, *_ = square_grid(n, rng)
    vol = rng.uniform(0.5, 1.5, n * n)
    lap = np.diag(g_out.copy())
    for t, (i, j) in enumerate(tp):
        lap[i, i] += g[t]
        lap[j, j] += g[t]
        lap[i, j] -= g[t]
        lap[j, i] -= g[t]
    exact = np.max(np.linalg.eigvals(lap / vol[:, None]).real)
    rho = spectral_radius(tp, g, g_out, vol)
    gershgorin = np.max(2 * np.diag(lap) / vol)
    assert exact <= rho <= min(1.02 * exact * (1 + 1e-3), gershgorin)
    assert rho == spectral_radius(tp, g, g_out, vol)  # reproducible
