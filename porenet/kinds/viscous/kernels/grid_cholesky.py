"""Sparse Cholesky of the pore matrix on canonical square grids: multifrontal, in nested
dissection order (docs/performance.md, "Viscous model: implicit against explicit").

``K = V / dt + L`` on an ``n x n`` grid is symmetric positive definite; nested dissection
splits the grid by separator lines into rectangles down to :data:`LEAF` pores, and each
front eliminates its separator and passes its Schur complement on its border to its parent.
The symbolic analysis (:func:`grid_cholesky_symbolic`, plain Python, once per lattice)
returns the index arrays as a :class:`GridFronts`; :func:`grid_cholesky_factor` and
:func:`grid_cholesky_solve` are numba kernels on it. ``porenet/kinds/viscous/tests/
test_grid_cholesky.py`` checks them against scipy's sparse solver.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from porenet.jit.jit import njit
from porenet.kernels.dense import cholesky_columns


class GridFronts(NamedTuple):
    """The fronts of the multifrontal Cholesky of a pore matrix on an ``n x n`` grid, and
    the storage of its factor (index arrays int64, values float64).

    Attributes
    ----------
    ns, nb : ndarray, shape (F,)
        Per front, in postorder: the pores it eliminates (its separator) and the pores of its
        border (eliminated by later fronts).
    front_ptr, front : ndarray
        Front ``k``'s pores are ``front[front_ptr[k]:front_ptr[k + 1]]``, separator first.
    fac_ptr : ndarray, shape (F + 1,)
        Where front ``k``'s columns of the factor start in :attr:`factor`.
    kid_ptr, kids : ndarray
        Front ``k``'s children are ``kids[kid_ptr[k]:kid_ptr[k + 1]]``.
    map_ptr, maps : ndarray
        Per child (in the order of ``kids``), the places of its border pores in its parent.
    ent_ptr, ent_a, ent_b, ent_e : ndarray
        Front ``k``'s off-diagonal entries ``(a, b)`` between its separator and its pores,
        with their adjacency entry ``e``: ``ent_*[ent_ptr[k]:ent_ptr[k + 1]]``.
    upd_ptr : ndarray, shape (F + 1,)
        Where each front's update (Schur complement on its border) starts in :attr:`update`.
    diagonal : ndarray, shape (N,)
        The matrix's diagonal (filled before each factorisation).
    factor, update : ndarray
        The factor's columns, front by front (``L_SS`` then ``L_BS``, row-major), and the
        fronts' updates.
    """

    ns: np.ndarray
    nb: np.ndarray
    front_ptr: np.ndarray
    front: np.ndarray
    fac_ptr: np.ndarray
    kid_ptr: np.ndarray
    kids: np.ndarray
    map_ptr: np.ndarray
    maps: np.ndarray
    ent_ptr: np.ndarray
    ent_a: np.ndarray
    ent_b: np.ndarray
    ent_e: np.ndarray
    upd_ptr: np.ndarray
    diagonal: np.ndarray
    factor: np.ndarray
    update: np.ndarray


#: Largest rectangle of pores factorised as one dense leaf front.
LEAF = 9


def grid_fronts(n: int, leaf: int = LEAF) -> list[tuple[list[int], list[int], list[int]]]:
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


def grid_cholesky_symbolic(n: int, indptr: np.ndarray, nbr: np.ndarray) -> GridFronts:
    """The fronts of the multifrontal Cholesky of a pore matrix on the ``n x n`` grid
    (adjacency ``indptr``, ``nbr``: the off-diagonal entries)."""
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
    return GridFronts(
        ns=ns, nb=nb, front_ptr=front_ptr, front=front, fac_ptr=fac_ptr, kid_ptr=kid_ptr,
        kids=np.array(kids, dtype=i64), map_ptr=np.array(map_ptr, dtype=i64),
        maps=np.array(maps, dtype=i64), ent_ptr=np.array(ent_ptr, dtype=i64),
        ent_a=np.array(ent_a, dtype=i64), ent_b=np.array(ent_b, dtype=i64),
        ent_e=np.array(ent_e, dtype=i64), upd_ptr=upd_ptr, diagonal=np.empty(n * n),
        factor=np.empty(fac_ptr[-1]), update=np.empty(upd_ptr[-1]),
    )  # fmt: skip


@njit
def grid_cholesky_factor(fronts: GridFronts, conductance: np.ndarray, throat: np.ndarray) -> None:
    """Multifrontal Cholesky ``K = L L^T`` of the pore matrix (diagonal ``fronts.diagonal``,
    off-diagonal ``-conductance`` of each adjacency entry's ``throat``), into
    ``fronts.factor``. Each front holds its separator's columns (``L_SS`` then ``L_BS``,
    row-major) and passes its Schur complement on its border (``fronts.update``) to its
    parent."""
    ns, nb, front_ptr, front = fronts.ns, fronts.nb, fronts.front_ptr, fronts.front
    kid_ptr, kids, map_ptr, maps = fronts.kid_ptr, fronts.kids, fronts.map_ptr, fronts.maps
    ent_ptr, ent_a, ent_b, ent_e = fronts.ent_ptr, fronts.ent_a, fronts.ent_b, fronts.ent_e
    fac_ptr, upd_ptr = fronts.fac_ptr, fronts.upd_ptr
    diag, fac, upd, g_eff, thr = fronts.diagonal, fronts.factor, fronts.update, conductance, throat
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
        cholesky_columns(f, s)  # K is positive definite: every pivot is
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
def grid_cholesky_solve(fronts: GridFronts, rhs: np.ndarray) -> np.ndarray:
    """``K^{-1} rhs`` from :func:`grid_cholesky_factor`."""
    ns, nb, front_ptr, front = fronts.ns, fronts.nb, fronts.front_ptr, fronts.front
    fac_ptr, fac = fronts.fac_ptr, fronts.factor
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
