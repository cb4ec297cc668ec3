"""Backward Euler for the viscous model, sliding menisci and located events (docs/model.md §4).

Scaled units and equations as in :mod:`porenet.kernels.viscous.explicit`. One step of length ``dt``
solves, for every undrained pore i (drained pores are decoupled rows that keep their value),

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
:mod:`porenet.kernels.viscous.menisci` does for the explicit scheme), on
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
* Stationary (status 6, pressure control only): over a stable step ``dt_min``, no pressure
  changes by more than ``floor`` (at least 1e-15; the rate is ``(p' - p)/dt`` at the end of
  the last step, exact for backward Euler) and no meniscus moves by more than ``floor`` (in
  units of a; a meniscus sliding into a trapped cluster slows to a stop but stays SLIDE).
* Active-set iterations are capped at 60 (the last 40 switch one meniscus at a time, the most
  violating one); a step whose states do not settle is retried at a quarter of the length,
  and below ``1e-9 dt_min`` the run stops with status 7 (:data:`STATUS`).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import splu

from porenet.kernels._jit import njit
from porenet.kernels.viscous.explicit import STATUS as _EXPLICIT_STATUS
from porenet.kernels.viscous.explicit import drain_pore
from porenet.kernels.viscous.menisci import CONTROL_PRESSURE, CONTROL_RAMP, CONTROL_RATE

#: Meniscus states (``mstate`` per throat; a latched meniscus is ON or OFF (= ZERO)).
OFF, SLIDE, ON = 0, 1, 2

#: Status codes of :func:`implicit_advance`: those of the explicit kernel, and one more.
STATUS = {**_EXPLICIT_STATUS, 7: "meniscus states did not settle"}

#: Slots of the ``ctrl`` array (the integrator's memory between calls).
CTRL = {
    "dt": 0,
    "restart": 1,
    "last_rate": 2,
    "solves": 3,
    "rejected": 4,
    "factorizations": 5,
    "located": 6,
    "iterations": 7,
}
N_CTRL = 8

#: Set to a list to record one tuple per trial step (debugging and benchmarks).
TRACE: list | None = None

_MAX_ITER = 60
_ONE_AT_A_TIME = 20
_PREDICT_MARGIN = 1.05
_GROWTH = 5.0


# -- the pore matrix ------------------------------------------------------------------------------


@njit
def _pattern_positions(
    indptr: np.ndarray, nbr: np.ndarray, cptr: np.ndarray, cind: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Positions in the (symmetric, sorted) matrix pattern of each diagonal and each CSR entry."""
    n = len(indptr) - 1
    diag = np.empty(n, dtype=np.int64)
    off = np.empty(len(nbr), dtype=np.int64)
    for i in range(n):
        for k in range(cptr[i], cptr[i + 1]):
            if cind[k] == i:
                diag[i] = k
        for e in range(indptr[i], indptr[i + 1]):
            j = nbr[e]
            for k in range(cptr[i], cptr[i + 1]):
                if cind[k] == j:
                    off[e] = k
    return diag, off


@njit(helper=True)
def _diagonal(
    i: int,
    dt: float,
    indptr: np.ndarray,
    thr: np.ndarray,
    vol: np.ndarray,
    g_eff: np.ndarray,
    g_out: np.ndarray,
) -> float:
    """Diagonal entry of pore ``i`` in ``K = V/dt + L``: ``V_i/dt + g_out,i + sum_j g_ij``."""
    total = vol[i] / dt + g_out[i]
    for e in range(indptr[i], indptr[i + 1]):
        total += g_eff[thr[e]]
    return total


@njit
def _fill_matrix(
    dt: float,
    indptr: np.ndarray,
    thr: np.ndarray,
    vol: np.ndarray,
    g_eff: np.ndarray,
    g_out: np.ndarray,
    diag: np.ndarray,
    off: np.ndarray,
    data: np.ndarray,
) -> None:
    """Values of ``K = V/dt + L`` on the fixed pattern (drained pores: ``V/dt`` alone)."""
    for i in range(len(indptr) - 1):
        for e in range(indptr[i], indptr[i + 1]):
            data[off[e]] = -g_eff[thr[e]]
        data[diag[i]] = _diagonal(i, dt, indptr, thr, vol, g_eff, g_out)


@njit
def _start_rates(
    indptr: np.ndarray,
    nbr: np.ndarray,
    thr: np.ndarray,
    g_eff: np.ndarray,
    g_out: np.ndarray,
    vol: np.ndarray,
    drained: np.ndarray,
    p: np.ndarray,
    fpore: np.ndarray,
    qstart: np.ndarray,
    rate: np.ndarray,
) -> float:
    """``dp_i/dt`` at the start of the step for every pore (0 for drained ones), with the
    meniscus fluxes ``qstart`` into the frontier pores ``fpore``; returns ``max |dp_i/dt|``."""
    n = len(indptr) - 1
    for i in range(n):
        if drained[i]:
            rate[i] = 0.0
            continue
        pi = p[i]
        total = -g_out[i] * pi
        for e in range(indptr[i], indptr[i + 1]):
            total += g_eff[thr[e]] * (p[nbr[e]] - pi)
        rate[i] = total
    for s in range(len(fpore)):
        rate[fpore[s]] += qstart[s]
    largest = 0.0
    for i in range(n):
        if not drained[i]:
            rate[i] /= vol[i]
            largest = max(largest, abs(rate[i]))
    return largest


@njit
def _error_and_storage(
    dt: float,
    drained: np.ndarray,
    vol: np.ndarray,
    g_out: np.ndarray,
    p: np.ndarray,
    pnew: np.ndarray,
    rate: np.ndarray,
) -> tuple[float, float, float, float]:
    """Over undrained pores: ``max |p' - p - dt f|``, the stored volume change
    ``sum V (p' - p)``, the outflow rate ``sum g_out p'`` and ``max |p' - p| / dt``."""
    err = 0.0
    stored = 0.0
    out = 0.0
    largest = 0.0
    for i in range(len(p)):
        if drained[i]:
            continue
        change = pnew[i] - p[i]
        err = max(err, abs(change - dt * rate[i]))
        stored += vol[i] * change
        out += g_out[i] * pnew[i]
        largest = max(largest, abs(change))
    return err, stored, out, largest / dt


def pore_matrix_pattern(indptr: np.ndarray, nbr: np.ndarray) -> dict[str, Any]:
    """The fixed sparsity pattern of the pore matrix (CSC, symmetric, sorted) and the
    positions of its diagonal and of each adjacency entry, for :func:`_fill_matrix`."""
    n = len(indptr) - 1
    adj = sp.csr_matrix((np.ones(len(nbr)), nbr, indptr), shape=(n, n))
    pattern = (adj + sp.identity(n, format="csr")).tocsc()
    pattern.sort_indices()
    cptr = pattern.indptr.astype(np.int64)
    cind = pattern.indices.astype(np.int64)
    diag, off = _pattern_positions(indptr, nbr, cptr, cind)
    return {"indptr": pattern.indptr, "indices": pattern.indices, "diag": diag, "off": off,
            "data": np.zeros(len(cind)), "n": n}  # fmt: skip


# -- sparse Cholesky for canonical square grids (multifrontal, nested dissection) ------------------

#: Largest rectangle of pores factorised as one dense leaf front.
_LEAF = 9


def grid_fronts(n: int, leaf: int = _LEAF) -> list[tuple[list[int], list[int], list[int]]]:
    """Nested dissection of the ``n x n`` grid (pore ``i n + j``): the fronts in postorder,
    each ``(S, B, children)``: the pores it eliminates (a separator line, or a whole leaf
    rectangle), the pores next to its rectangle that later fronts eliminate, its children."""
    nodes: list[tuple[list[int], list[int], list[int]]] = []

    def rec(r0: int, r1: int, c0: int, c1: int) -> int | None:
        h, w = r1 - r0, c1 - c0
        if h <= 0 or w <= 0:
            return None
        if h * w <= leaf:
            sep = [i * n + j for i in range(r0, r1) for j in range(c0, c1)]
            kids: list[int | None] = []
        elif w >= h:
            m = (c0 + c1) // 2
            kids = [rec(r0, r1, c0, m), rec(r0, r1, m + 1, c1)]
            sep = [i * n + m for i in range(r0, r1)]
        else:
            m = (r0 + r1) // 2
            kids = [rec(r0, m, c0, c1), rec(m + 1, r1, c0, c1)]
            sep = [m * n + j for j in range(c0, c1)]
        border = set()
        for i in range(r0, r1):
            for j in (c0 - 1, c1):
                if 0 <= j < n:
                    border.add(i * n + j)
        for j in range(c0, c1):
            for i in (r0 - 1, r1):
                if 0 <= i < n:
                    border.add(i * n + j)
        nodes.append((sep, sorted(border), [k for k in kids if k is not None]))
        return len(nodes) - 1

    rec(0, n, 0, n)
    return nodes


def grid_cholesky_symbolic(n: int, indptr: np.ndarray, nbr: np.ndarray) -> dict[str, Any]:
    """Index arrays of the multifrontal Cholesky of a pore matrix on the ``n x n`` grid."""
    nodes = grid_fronts(n)
    count = len(nodes)
    ns = np.array([len(sep) for sep, _, _ in nodes], dtype=np.int64)
    nb = np.array([len(b) for _, b, _ in nodes], dtype=np.int64)
    front_ptr = np.zeros(count + 1, dtype=np.int64)
    front_ptr[1:] = np.cumsum(ns + nb)
    front = np.concatenate([np.array(sep + b, dtype=np.int64) for sep, b, _ in nodes])
    fac_ptr = np.zeros(count + 1, dtype=np.int64)
    fac_ptr[1:] = np.cumsum((ns + nb) * ns)
    kid_ptr = np.zeros(count + 1, dtype=np.int64)
    kids: list[int] = []
    maps: list[int] = []
    map_ptr = [0]
    ent_ptr = [0]
    ent_a: list[int] = []
    ent_b: list[int] = []
    ent_e: list[int] = []
    for k, (sep, border, children) in enumerate(nodes):
        pos = {g: a for a, g in enumerate(sep + border)}
        for c in children:
            kids.append(c)
            maps.extend(pos[g] for g in nodes[c][1])
            map_ptr.append(len(maps))
        kid_ptr[k + 1] = len(kids)
        for a, g in enumerate(sep):
            for e in range(indptr[g], indptr[g + 1]):
                b = pos.get(int(nbr[e]))
                if b is not None and b > a:
                    ent_a.append(a)
                    ent_b.append(b)
                    ent_e.append(e)
        ent_ptr.append(len(ent_a))
    upd_ptr = np.zeros(count + 1, dtype=np.int64)
    upd_ptr[1:] = np.cumsum(nb * nb)
    i64 = np.int64
    return {
        "ns": ns, "nb": nb, "front_ptr": front_ptr, "front": front, "fac_ptr": fac_ptr,
        "kid_ptr": kid_ptr, "kids": np.array(kids, dtype=i64), "map_ptr": np.array(map_ptr, i64),
        "maps": np.array(maps, dtype=i64), "ent_ptr": np.array(ent_ptr, dtype=i64),
        "ent_a": np.array(ent_a, dtype=i64), "ent_b": np.array(ent_b, dtype=i64),
        "ent_e": np.array(ent_e, dtype=i64), "upd_ptr": upd_ptr,
        "fac": np.empty(fac_ptr[-1]), "upd": np.empty(upd_ptr[-1]), "diag": np.empty(n * n),
    }  # fmt: skip


@njit
def grid_cholesky_factor(
    ns: np.ndarray,
    nb: np.ndarray,
    front_ptr: np.ndarray,
    front: np.ndarray,
    fac_ptr: np.ndarray,
    kid_ptr: np.ndarray,
    kids: np.ndarray,
    map_ptr: np.ndarray,
    maps: np.ndarray,
    ent_ptr: np.ndarray,
    ent_a: np.ndarray,
    ent_b: np.ndarray,
    ent_e: np.ndarray,
    upd_ptr: np.ndarray,
    diag: np.ndarray,
    g_eff: np.ndarray,
    thr: np.ndarray,
    fac: np.ndarray,
    upd: np.ndarray,
) -> None:
    """Multifrontal Cholesky ``K = L L^T`` of the pore matrix (diagonal ``diag``, off-diagonal
    ``-g_eff`` of each adjacency entry's throat). Each front holds its separator's columns
    (``L_SS`` then ``L_BS``, row-major, in ``fac``) and passes its Schur complement on its
    border (``upd``) to its parent."""
    for k in range(len(ns)):
        s = ns[k]
        m = s + nb[k]
        b = nb[k]
        f = np.zeros((m, m))
        f0 = front_ptr[k]
        for a in range(s):
            f[a, a] = diag[front[f0 + a]]
        for x in range(ent_ptr[k], ent_ptr[k + 1]):
            f[ent_b[x], ent_a[x]] -= g_eff[thr[ent_e[x]]]
        for ci in range(kid_ptr[k], kid_ptr[k + 1]):
            c = kids[ci]
            bc = nb[c]
            mp = map_ptr[ci]
            u0 = upd_ptr[c]
            for x in range(bc):
                gx = maps[mp + x]
                for y in range(x + 1):
                    gy = maps[mp + y]
                    if gx >= gy:
                        f[gx, gy] += upd[u0 + x * bc + y]
                    else:
                        f[gy, gx] += upd[u0 + x * bc + y]
        for j in range(s):
            d = f[j, j]
            for t in range(j):
                d -= f[j, t] * f[j, t]
            d = np.sqrt(d)
            f[j, j] = d
            for i in range(j + 1, m):
                v = f[i, j]
                for t in range(j):
                    v -= f[i, t] * f[j, t]
                f[i, j] = v / d
        if b > 0:
            lb = np.ascontiguousarray(f[s:, :s])
            prod = np.dot(lb, lb.T)
            u0 = upd_ptr[k]
            for x in range(b):
                for y in range(x + 1):
                    upd[u0 + x * b + y] = f[s + x, s + y] - prod[x, y]
        p0 = fac_ptr[k]
        for i in range(m):
            for j in range(s):
                fac[p0 + i * s + j] = f[i, j]


@njit
def grid_cholesky_solve(
    ns: np.ndarray,
    nb: np.ndarray,
    front_ptr: np.ndarray,
    front: np.ndarray,
    fac_ptr: np.ndarray,
    fac: np.ndarray,
    rhs: np.ndarray,
) -> np.ndarray:
    """``K^{-1} rhs`` from :func:`grid_cholesky_factor`."""
    x = rhs.copy()
    count = len(ns)
    for k in range(count):
        s = ns[k]
        m = s + nb[k]
        f0 = front_ptr[k]
        p0 = fac_ptr[k]
        for j in range(s):
            v = x[front[f0 + j]]
            for t in range(j):
                v -= fac[p0 + j * s + t] * x[front[f0 + t]]
            x[front[f0 + j]] = v / fac[p0 + j * s + j]
        for i in range(s, m):
            v = 0.0
            for t in range(s):
                v += fac[p0 + i * s + t] * x[front[f0 + t]]
            x[front[f0 + i]] -= v
    for k in range(count - 1, -1, -1):
        s = ns[k]
        m = s + nb[k]
        f0 = front_ptr[k]
        p0 = fac_ptr[k]
        for j in range(s - 1, -1, -1):
            v = x[front[f0 + j]]
            for i in range(j + 1, m):
                v -= fac[p0 + i * s + j] * x[front[f0 + i]]
            x[front[f0 + j]] = v / fac[p0 + j * s + j]
    return x


@njit
def _fill_diagonal(
    dt: float,
    indptr: np.ndarray,
    thr: np.ndarray,
    vol: np.ndarray,
    g_eff: np.ndarray,
    g_out: np.ndarray,
    diag: np.ndarray,
) -> None:
    """The diagonal of ``K = V/dt + L`` (the grid Cholesky reads the off-diagonal from
    ``g_eff``)."""
    for i in range(len(indptr) - 1):
        diag[i] = _diagonal(i, dt, indptr, thr, vol, g_eff, g_out)


class _GridCholesky:
    """``solve(rhs)`` with the factor of :func:`grid_cholesky_factor` (the SuperLU interface)."""

    def __init__(self, sym: dict[str, Any]) -> None:
        self.sym = sym

    def solve(self, rhs: np.ndarray) -> np.ndarray:
        s = self.sym
        rhs = np.ascontiguousarray(rhs, dtype=np.float64)
        return grid_cholesky_solve(
            s["ns"], s["nb"], s["front_ptr"], s["front"], s["fac_ptr"], s["fac"], rhs
        )


# -- one step's problem ---------------------------------------------------------------------------


class _Step:
    """The frontier, right-hand side and factorisations of one step (transient: built at the
    start of a step and dropped at its end)."""

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
            sym = pat["fronts"]
            _fill_diagonal(dt, k["indptr"], k["thr"], k["vol"], k["g_eff"], k["g_out"],
                           sym["diag"])  # fmt: skip
            grid_cholesky_factor(
                sym["ns"], sym["nb"], sym["front_ptr"], sym["front"], sym["fac_ptr"],
                sym["kid_ptr"], sym["kids"], sym["map_ptr"], sym["maps"], sym["ent_ptr"],
                sym["ent_a"], sym["ent_b"], sym["ent_e"], sym["upd_ptr"], sym["diag"],
                k["g_eff"], k["thr"], sym["fac"], sym["upd"],
            )  # fmt: skip
            self.lu = _GridCholesky(sym)
        else:
            _fill_matrix(dt, k["indptr"], k["thr"], k["vol"], k["g_eff"], k["g_out"],
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
        _one_slide_per_pore(state, free, pe, fpore)
        seen: set[bytes] = set()
        x0f = x0[fpore]
        for it in range(_MAX_ITER):
            on = np.flatnonzero(state != OFF)
            n_on = len(on)
            wf = np.empty((nf, n_on))
            for a, s in enumerate(on):
                wf[:, a] = self.column(int(fpore[s]))[fpore]
            rate_ctl = control == CONTROL_RATE
            size = n_on + (1 if rate_ctl else 0)
            pinv_new = pinv + k["ramp_rate"] * dt if control == CONTROL_RAMP else pinv
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
            new_state, _, arg = _switch(state, free, latch, delta, q, g, pe, fpore, self.tol)
            if arg < 0:
                self.iterations += it + 1
                return {"dt": dt, "x0": x0, "state": state, "q": q, "pinv": pinv_new,
                        "delta": delta, "on": on, "iterations": it + 1}  # fmt: skip
            if it >= _ONE_AT_A_TIME:  # switch only the most violating meniscus
                keep = state.copy()
                keep[arg] = new_state[arg]
                _one_slide_per_pore(keep, free, pe, fpore)
                new_state = keep
            key = new_state.tobytes()
            if key in seen and it < _ONE_AT_A_TIME:
                # a cycle: go on one meniscus at a time from the current states
                keep = state.copy()
                keep[arg] = new_state[arg]
                _one_slide_per_pore(keep, free, pe, fpore)
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


def _one_slide_per_pore(state: np.ndarray, free: np.ndarray, pe: np.ndarray, fpore: np.ndarray):
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


def _switch(
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
    _one_slide_per_pore(new, free, pe, fpore)
    arg = int(np.argmax(viol))
    return new, float(viol[arg]), arg


# -- the stepper ----------------------------------------------------------------------------------


def implicit_advance(
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
    mstate: np.ndarray,
    mflux: np.ndarray,
    ctrl: np.ndarray,
    acc: np.ndarray,
    cnt: np.ndarray,
    order: np.ndarray,
    via: np.ndarray,
    series: np.ndarray,
    cache: dict[str, Any],
    control: int,
    q_rate: float,
    capacity: float,
    capacity_per_drained: float,
    ramp_rate: float,
    latching: bool,
    ell0: float,
    dt_min: float,
    pressure_scale: float,
    tolerance: float,
    event_tolerance: float,
    floor: float,
    max_events: int,
    t_end: float,
    max_steps: int,
    stop_at_breakthrough: bool,
    step_budget: int,
) -> int:
    """Integrate with backward Euler until ``max_events`` pores drain or another stop.

    Returns a :data:`STATUS` code. Arguments as in
    :func:`porenet.kernels.viscous.explicit.explicit_advance` (the same state arrays, updated in the
    same way, so both integrators leave the same records), and:

    Parameters
    ----------
    mstate : ndarray of int8, shape (M,)
        State of each frontier meniscus (:data:`OFF`, :data:`SLIDE`, :data:`ON`) at the end of
        the last step (0 on entry for new menisci).
    mflux : ndarray of float, shape (M,)
        Each frontier meniscus' flux over the last step (a sliding meniscus' flux at the
        start of the next step).
    ctrl : ndarray of float, shape (:data:`N_CTRL`,)
        The integrator's memory (:data:`CTRL`): next step, restart flag, last rate, counts of
        solves, rejected steps and factorisations. ``ctrl[0] = 0`` on the first call.
    cache : dict
        Holds the pore-matrix pattern between calls (filled on the first call).
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
    if "pattern" not in cache:
        cache["pattern"] = pore_matrix_pattern(indptr, nbr)
        if grid_n > 0 and cache.get("grid_cholesky", True):
            cache["pattern"]["fronts"] = grid_cholesky_symbolic(grid_n, indptr, nbr)
    n = len(indptr) - 1
    tol_abs = tolerance * pressure_scale
    rate = np.zeros(n)
    events = 0
    steps_at_entry = cnt[1]
    if ctrl[0] <= 0.0:
        ctrl[0] = dt_min
        ctrl[1] = 1.0
        ctrl[2] = math.inf
    stationary_floor = max(floor, 1e-15)
    while True:
        if events >= max_events or cnt[1] - steps_at_entry >= step_budget:
            return 0
        t = acc[0]
        if t >= t_end:
            return 2
        if cnt[1] >= max_steps:
            return 3
        nf = int(cnt[2])
        if nf == 0:
            return 5
        pinv = float(acc[1])
        cap = capacity + capacity_per_drained * acc[7]
        fthr = front[:nf].copy()
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
        largest = _start_rates(indptr, nbr, thr, g_eff, g_out, vol, drained, p, fpore, qstart,
                               rate)  # fmt: skip
        if control == CONTROL_RATE:
            rate_inv = (q_rate - float(qstart.sum())) / cap
        elif control == CONTROL_RAMP:
            rate_inv = ramp_rate
        else:
            rate_inv = 0.0
        if (
            control == CONTROL_PRESSURE
            and ctrl[2] * dt_min <= stationary_floor
            and not (newly | (qstart * dt_min > stationary_floor * area[fthr])).any()
        ):
            return 6
        # the step to try: controller, restart rule, end time, predicted events
        dt_ctrl = float(ctrl[0])
        if ctrl[1] > 0.0:
            fastest = max(largest, abs(rate_inv))
            guess = tol_abs / fastest if fastest > 0.0 else dt_ctrl
            dt_ctrl = max(1e-6 * dt_min, min(dt_ctrl, guess))
            ctrl[1] = 0.0
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
        step = _Step(step_k, 1e-10)
        sol = step.solve(dt_try)
        if sol is None:
            ctrl[0] = 0.25 * dt_try
            _count(ctrl, step, rejected=True)
            if ctrl[0] < 1e-9 * dt_min:
                cnt[4] = step.failed_at
                return 7
            continue
        pnew = step.pressures(sol)
        rate_err = rate
        if late.any():
            rate_err = rate.copy()
            np.add.at(rate_err, fpore[late], sol["q"][late] / vol[fpore[late]])
        err, _, _, _ = _error_and_storage(dt_try, drained, vol, g_out, p, pnew, rate_err)
        rate_inv_err = rate_inv
        if control == CONTROL_RATE and late.any():
            rate_inv_err -= float(sol["q"][late].sum()) / cap
        err = max(err, abs(sol["pinv"] - pinv - dt_try * rate_inv_err))
        err *= 0.5
        if not math.isfinite(err):
            cnt[4] = -1
            return 4
        h, h_land, h_start = step.events(sol)
        if TRACE is not None:
            TRACE.append((float(t), dt_try, dt_ctrl, predicted, err / tol_abs, h_land, h_start,
                          step.factorizations, int(cnt[0])))  # fmt: skip
        if err > tol_abs:
            ctrl[0] = dt_try * max(0.2, 0.9 * math.sqrt(tol_abs / err))
            _count(ctrl, step, rejected=True)
            continue
        grow = _GROWTH if err == 0.0 else min(_GROWTH, 0.9 * math.sqrt(tol_abs / err))
        proposal = dt_try * grow
        if limited:
            proposal = max(proposal, dt_ctrl) if grow >= 1.0 else min(proposal, dt_ctrl)
        ctrl[0] = proposal
        located = h <= 0.0
        if located:
            ctrl[6] += 1
            sol, h = _locate(step, sol, h, event_tolerance)
            if sol is None:
                cnt[4] = step.failed_at
                _count(ctrl, step)
                return 7
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
        pinv_new = pinv + dt * (q_rate - qsum) / cap if control == CONTROL_RATE else sol["pinv"]
        _, stored, out, last_rate = _error_and_storage(dt, drained, vol, g_out, p, pnew, rate)
        out -= out_fix
        und = ~drained
        p[und] = pnew[und]
        new_ell = ell[fthr] - q * dt / area[fthr]
        new_ell[landing] = 0.0
        ell[fthr[moving]] = new_ell[moving]
        acc[3] += qsum * dt
        acc[4] += stored
        acc[5] += out * dt
        if control == CONTROL_RATE:
            acc[2] += q_rate * dt
        else:
            acc[2] += qsum * dt + cap * (pinv_new - pinv)
        acc[8] += cap * (pinv_new - pinv)
        acc[1] = pinv_new
        acc[0] = t + dt
        cnt[1] += 1
        ctrl[2] = last_rate
        if not (math.isfinite(pinv_new) and math.isfinite(stored)):
            cnt[4] = -1
            return 4
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
            drain_pore(
                i, f, indptr, nbr, thr, vol, ell0, g_eff, g_out, grid_n, box, p, drained,
                ell, latched, front, fpos, act, apos, acc, cnt, order, via, series,
            )  # fmt: skip
            for e in range(indptr[i], indptr[i + 1]):
                t2 = thr[e]
                if not drained[nbr[e]]:
                    mstate[t2] = OFF
                    mflux[t2] = 0.0
            events += 1
            if outlet[i]:
                cnt[5] = 1
                if stop_at_breakthrough:
                    ctrl[1] = 1.0
                    return 1
        ctrl[1] = 1.0


def _count(ctrl: np.ndarray, step: _Step, rejected: bool = False) -> None:
    ctrl[3] += step.solves
    ctrl[5] += step.factorizations
    ctrl[7] += step.iterations
    if rejected:
        ctrl[4] += 1


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
    step: _Step, sol_hi: dict[str, Any], h_hi: float, event_tolerance: float
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
