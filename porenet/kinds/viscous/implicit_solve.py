"""One step of the implicit integrator of the viscous model: the backward-Euler system with
its menisci, solved as a complementarity problem (docs/model.md section 4).

The equations, the three states of a threshold meniscus (OFF, SLIDE, ON) and the two of a
latched one, and the linear algebra (one factorisation of the pore matrix ``K = V/dt + L``
per step length, the menisci and the reservoir through a small dense Schur complement) are
described in :mod:`porenet.kinds.viscous.implicit_steps`, which drives the steps (error
control, events, drainage). Here: :class:`StepProblem`, one step's factorisations and its
active-set iteration (:meth:`StepProblem.solve`), and :func:`switch`, the states whose
conditions fail. Scaled units as in :mod:`porenet.kinds.viscous.kernels.explicit`.

The active-set iteration starts from the previous step's states, solves for them, switches
the menisci whose conditions fail, and repeats; it is capped at ``MAX_ITERATIONS`` (after
``ONE_AT_A_TIME`` iterations, or on a cycle, it switches one meniscus at a time, the most
violating one). The problem minimises a strictly convex function, so its solution is unique.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import splu

from porenet.kinds.viscous.kernels.grid_cholesky import (
    GridFronts,
    grid_cholesky_factor,
    grid_cholesky_solve,
)
from porenet.kinds.viscous.kernels.pore_matrix import fill_diagonal, fill_matrix
from porenet.kinds.viscous.kernels.state import Control

#: Meniscus states (``mstate`` per throat; a latched meniscus is ON or OFF (= ZERO)).
OFF, SLIDE, ON = 0, 1, 2


#: Active-set iterations before a step is given up (retried shorter by the stepper).
MAX_ITERATIONS = 60
#: Iterations after which only the most violating meniscus switches.
ONE_AT_A_TIME = 20


class _GridCholesky:
    """``solve(rhs)`` with the factor of :func:`grid_cholesky_factor` (the SuperLU interface)."""

    def __init__(self, fronts: GridFronts) -> None:
        self.fronts = fronts

    def solve(self, rhs: np.ndarray) -> np.ndarray:
        return grid_cholesky_solve(self.fronts, np.ascontiguousarray(rhs, dtype=np.float64))


class StepProblem:
    """The frontier, right-hand side and factorisations of one step (transient: built at the
    start of a step and dropped at its end).

    ``k`` holds the step's arrays by name (the pore-matrix ``pattern``, ``indptr``, ``thr``,
    ``vol``, ``g_eff``, ``g_out``, the pressures ``p``, and per frontier meniscus ``fpore``,
    ``fthr``, ``G``, ``pe_f``, ``free``, ``latch_f``, ``state0``, ``ell_f``, ``area_f``, with
    ``ell0``, ``control``, ``pinv``, ``capacity``, ``q_rate``, ``ramp_rate`` and ``n``), as
    :func:`porenet.kinds.viscous.implicit_steps.implicit_advance` builds them.
    """

    def __init__(self, k: dict[str, Any], tolerance_iter: float) -> None:
        self.k = k
        self.tol = tolerance_iter
        self.lu: Any = None
        self.lu_dt = -1.0
        self.columns: dict[int, np.ndarray] = {}
        self.solves = 0
        self.factorizations = 0
        self.iterations = 0

    # the factorisation of K(dt) and the columns K^{-1} e_i of the meniscus pores
    def factor(self, dt: float) -> None:
        if dt == self.lu_dt:
            return
        k = self.k
        pat = k["pattern"]
        if "fronts" in pat:  # canonical grid: the multifrontal Cholesky
            fronts = pat["fronts"]
            fill_diagonal(dt, k["indptr"], k["thr"], k["vol"], k["g_eff"], k["g_out"],
                          fronts.diagonal)  # fmt: skip
            grid_cholesky_factor(fronts, k["g_eff"], k["thr"])
            self.lu = _GridCholesky(fronts)
        else:
            fill_matrix(dt, k["indptr"], k["thr"], k["vol"], k["g_eff"], k["g_out"],
                         pat["diag"], pat["off"], pat["data"])  # fmt: skip
            n = pat["n"]
            mat = sp.csc_matrix((pat["data"], pat["indices"], pat["indptr"]), shape=(n, n))
            self.lu = splu(
                mat,
                permc_spec="MMD_AT_PLUS_A",
                diag_pivot_thresh=0.0,
                options={"SymmetricMode": True},
            )
        self.lu_dt = dt
        self.columns = {}
        self.factorizations += 1

    def column(self, i: int) -> np.ndarray:
        col = self.columns.get(i)
        if col is None:
            e = np.zeros(self.k["n"])
            e[i] = 1.0
            col = self.lu.solve(e)
            self.solves += 1
            self.columns[i] = col
        return col

    def solve(self, dt: float) -> dict[str, Any] | None:
        """The consistent end-of-step states and values after a step of ``dt`` (None if the
        active-set iteration does not settle)."""
        k = self.k
        self.factor(dt)
        x0 = self.lu.solve(k["vol"] * k["p"] / dt)
        self.solves += 1
        fpore, g, pe = k["fpore"], k["G"], k["pe_f"]
        free, latch = k["free"], k["latch_f"]
        nf = len(fpore)
        control = k["control"]
        pinv = k["pinv"]
        cap = k["capacity"]
        state = k["state0"].copy()
        one_slide_per_pore(state, free, pe, fpore)
        seen: set[bytes] = set()
        x0f = x0[fpore]
        for it in range(MAX_ITERATIONS):
            on = np.flatnonzero(state != OFF)
            n_on = len(on)
            wf = np.empty((nf, n_on))
            for a, s in enumerate(on):
                wf[:, a] = self.column(int(fpore[s]))[fpore]
            rate_ctl = control == Control.RATE
            size = n_on + (1 if rate_ctl else 0)
            pinv_new = pinv + k["ramp_rate"] * dt if control == Control.RAMP else pinv
            q = np.zeros(nf)
            if size > 0:
                mat = np.zeros((size, size))
                rhs = np.empty(size)
                mat[:n_on, :n_on] = wf[on, :]
                sliding = state[on] == SLIDE
                onon = ~sliding
                idx = np.arange(n_on)
                mat[idx[onon], idx[onon]] += 1.0 / g[on[onon]]
                rhs[:n_on] = -x0f[on]
                rhs[:n_on][sliding] -= pe[on[sliding]]
                if rate_ctl:
                    mat[:n_on, n_on] = -1.0
                    mat[n_on, :n_on] = 1.0
                    mat[n_on, n_on] = cap / dt
                    rhs[n_on] = cap * pinv / dt + k["q_rate"]
                else:
                    rhs[:n_on] += pinv_new
                sol = np.linalg.solve(mat, rhs)
                q[on] = sol[:n_on]
                if rate_ctl:
                    pinv_new = sol[n_on]
            pf = x0f + wf @ q[on] if n_on else x0f.copy()
            delta = pinv_new - pf
            new_state, _, arg = switch(state, free, latch, delta, q, g, pe, fpore, self.tol)
            if arg < 0:
                self.iterations += it + 1
                return {"dt": dt, "x0": x0, "state": state, "q": q, "pinv": pinv_new,
                        "delta": delta, "on": on, "iterations": it + 1}  # fmt: skip
            if it >= ONE_AT_A_TIME:  # switch only the most violating meniscus
                keep = state.copy()
                keep[arg] = new_state[arg]
                one_slide_per_pore(keep, free, pe, fpore)
                new_state = keep
            key = new_state.tobytes()
            if key in seen and it < ONE_AT_A_TIME:
                # a cycle: go on one meniscus at a time from the current states
                keep = state.copy()
                keep[arg] = new_state[arg]
                one_slide_per_pore(keep, free, pe, fpore)
                new_state = keep
            seen.add(key)
            state = new_state
        self.failed_at = int(k["fthr"][int(np.argmax(state != k["state0"]))])
        return None

    def pressures(self, sol: dict[str, Any]) -> np.ndarray:
        """The full end-of-step pressure field of a solution."""
        pnew = sol["x0"].copy()
        fpore, q = self.k["fpore"], sol["q"]
        for s in sol["on"]:
            pnew += q[s] * self.column(int(fpore[s]))
        return pnew

    def events(self, sol: dict[str, Any]) -> tuple[float, float, float]:
        """``h`` (see the module docstring) and its landing and start parts."""
        k = self.k
        dt = sol["dt"]
        q = sol["q"]
        moving = sol["state"] != OFF
        h_land = math.inf
        if moving.any():
            remaining = k["ell_f"][moving] - q[moving] * dt / k["area_f"][moving]
            h_land = float(np.min(remaining)) / k["ell0"]
        h_start = math.inf
        frozen = ~k["free"]
        if frozen.any():
            h_start = float(np.min((k["pe_f"][frozen] - sol["delta"][frozen]) / k["pe_f"][frozen]))
        return min(h_land, h_start), h_land, h_start


def one_slide_per_pore(state: np.ndarray, free: np.ndarray, pe: np.ndarray, fpore: np.ndarray):
    """At most one sliding meniscus per pore: the one with the largest entry pressure slides,
    the others into the same pore are ON."""
    sliding = np.flatnonzero(state == SLIDE)
    if len(sliding) < 2:
        return
    pores = fpore[sliding]
    if len(np.unique(pores)) == len(pores):
        return
    order = np.lexsort((-pe[sliding], pores))
    last = -1
    for s in sliding[order]:
        if fpore[s] == last:
            state[s] = ON
        last = fpore[s]


def switch(
    state: np.ndarray,
    free: np.ndarray,
    latch: np.ndarray,
    delta: np.ndarray,
    q: np.ndarray,
    g: np.ndarray,
    pe: np.ndarray,
    fpore: np.ndarray,
    tol: float,
) -> tuple[np.ndarray, float, int]:
    """The switched states of the free menisci whose conditions fail, the largest violation
    and its meniscus (-1 if every condition holds)."""
    new = state.copy()
    viol = np.zeros(len(state))
    thr = free & ~latch
    # threshold menisci
    on = thr & (state == ON)
    bad = on & (delta < pe - tol)
    viol[bad] = (pe - delta)[bad]
    new[bad] = SLIDE
    sl = thr & (state == SLIDE)
    cap = g * pe
    high = sl & (q > cap + tol * cap)
    low = sl & (q < -tol * cap)
    viol[high] = ((q - cap) / g)[high]
    viol[low] = (-q / g)[low]
    new[high] = ON
    new[low] = OFF
    off = thr & (state == OFF)
    up = off & (delta > pe + tol)
    viol[up] = (delta - pe)[up]
    new[up] = SLIDE
    # latched menisci: ON while D' > 0
    lat = free & latch
    stop = lat & (state == ON) & (delta < -tol)
    go = lat & (state == OFF) & (delta > tol)
    viol[stop] = -delta[stop]
    viol[go] = delta[go]
    new[stop] = OFF
    new[go] = ON
    if not viol.any():
        return new, 0.0, -1
    one_slide_per_pore(new, free, pe, fpore)
    arg = int(np.argmax(viol))
    return new, float(viol[arg]), arg


__all__ = [
    "MAX_ITERATIONS",
    "OFF",
    "ON",
    "ONE_AT_A_TIME",
    "SLIDE",
    "StepProblem",
    "one_slide_per_pore",
    "switch",
]
