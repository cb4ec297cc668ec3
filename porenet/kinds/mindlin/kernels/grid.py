"""The particles of a square lattice as a grid, for the multigrid solver of the frictional solid
(:mod:`porenet.kinds.mindlin.kernels.multigrid`; docs/model.md, "Frictional solid").

With rotations held, the force balance of axis-aligned contacts with normal stiffness ``K``
and tangential stiffness ``K_t`` splits by component: ``u_x`` is joined along x by the x-springs'
normal stiffness and along y by the y-springs' tangential one, ``u_y`` the other way round.
:func:`find_grid` recognises a lattice whose free particles form a full ``m x m`` grid inside
a fixed ring (the square lattice), :func:`fill_operators` writes the two five-point operators
of an update and :func:`scatter_fields` / :func:`gather_fields` move forces and displacements
between the particles and the two grids.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from porenet.jit.jit import njit
from porenet.kinds.mindlin.kernels.multigrid import Operator


class GridLayout(NamedTuple):
    """Where each particle and spring sits on the grid of free particles.

    Attributes
    ----------
    size : int
        ``m``: free particles per side.
    particle_point : ndarray of int64, shape (n_particles,)
        Flat grid index ``r * m + c`` of each free particle; -1 for a fixed one.
    spring_edge : ndarray of int64, shape (M,)
        Flat index of each spring's edge in the operator's ``across_columns`` ((m, m + 1),
        x-springs) or ``across_rows`` ((m + 1, m), y-springs).
    along_x : ndarray of bool, shape (M,)
        Whether each spring lies along x.
    """

    size: int
    particle_point: np.ndarray
    spring_edge: np.ndarray
    along_x: np.ndarray


def find_grid(
    particle_coords: np.ndarray, spring_particles: np.ndarray, fixed: np.ndarray
) -> GridLayout | None:
    """The grid layout of a lattice whose particles form a full ``(m+2) x (m+2)`` grid with
    every particle of the outer ring fixed and every other one free, and whose springs join
    grid neighbours; None for any other lattice."""
    xy = np.asarray(particle_coords, dtype=np.float64)
    if xy.ndim != 2 or xy.shape[1] != 2 or len(xy) < 9:
        return None
    xs, ys = np.unique(xy[:, 0]), np.unique(xy[:, 1])
    side = len(xs)
    if len(ys) != side or side * side != len(xy):
        return None
    col = np.searchsorted(xs, xy[:, 0])
    row = np.searchsorted(ys, xy[:, 1])
    flat = row * side + col
    if len(np.unique(flat)) != len(xy):
        return None
    ring = (row == 0) | (row == side - 1) | (col == 0) | (col == side - 1)
    if not np.array_equal(np.asarray(fixed, dtype=bool), ring):
        return None
    m = side - 2
    point = np.where(ring, -1, (row - 1) * m + (col - 1)).astype(np.int64)
    sp = np.asarray(spring_particles, dtype=np.int64)
    r0, c0 = row[sp[:, 0]], col[sp[:, 0]]
    r1, c1 = row[sp[:, 1]], col[sp[:, 1]]
    along_x = (r0 == r1) & (np.abs(c1 - c0) == 1)
    along_y = (c0 == c1) & (np.abs(r1 - r0) == 1)
    if not np.all(along_x | along_y):
        return None
    # edge between columns c-1 and c of free row r: across_columns[r, c] (c in 0..m)
    lo_c, lo_r = np.minimum(c0, c1), np.minimum(r0, r1)
    edge_x = (r0 - 1) * (m + 1) + lo_c
    edge_y = lo_r * m + (c0 - 1)
    edge = np.where(along_x, edge_x, edge_y).astype(np.int64)
    keep_x = along_x & (r0 >= 1) & (r0 <= m)
    keep_y = along_y & (c0 >= 1) & (c0 <= m)
    if not np.all(keep_x | keep_y):
        return None  # a spring between two ring particles: not this layout
    for along in (along_x, along_y):
        if len(np.unique(edge[along])) != along.sum():
            return None
    return GridLayout(m, point, edge, along_x)


def operators(m: int) -> tuple[Operator, Operator]:
    """Two empty five-point operators on an ``m x m`` grid (for ``u_x`` and ``u_y``)."""

    def one() -> Operator:
        return Operator(np.zeros((m, m + 1)), np.zeros((m + 1, m)), np.zeros((m, m)))

    return one(), one()


@njit
def fill_operators(
    layout: GridLayout,
    normal_stiffness: np.ndarray,
    shear_stiffness: np.ndarray,
    foundation_stiffness: float,
    op_x: Operator,
    op_y: Operator,
) -> None:
    """The operators of ``u_x`` and ``u_y`` (module docstring) from each spring's normal and
    tangential stiffness in the update, plus the foundation on the diagonal."""
    cols_x, rows_x = op_x.across_columns.ravel(), op_x.across_rows.ravel()
    cols_y, rows_y = op_y.across_columns.ravel(), op_y.across_rows.ravel()
    for s in range(layout.spring_edge.shape[0]):
        e = layout.spring_edge[s]
        if layout.along_x[s]:
            cols_x[e] = normal_stiffness[s]
            cols_y[e] = shear_stiffness[s]
        else:
            rows_y[e] = normal_stiffness[s]
            rows_x[e] = shear_stiffness[s]
    op_x.diagonal[:, :] = foundation_stiffness
    op_y.diagonal[:, :] = foundation_stiffness


@njit
def scatter_fields(
    layout: GridLayout, force: np.ndarray, out_x: np.ndarray, out_y: np.ndarray
) -> None:
    """The free particles' force components ((n_particles, 2)) onto the two grids (m*m)."""
    point = layout.particle_point
    for q in range(point.shape[0]):
        p = point[q]
        if p >= 0:
            out_x[p] = force[q, 0]
            out_y[p] = force[q, 1]


@njit
def gather_fields(
    layout: GridLayout, field_x: np.ndarray, field_y: np.ndarray, out: np.ndarray
) -> None:
    """The two grids' values back onto the particles ((n_particles, 2); 0 for fixed ones)."""
    point = layout.particle_point
    for q in range(point.shape[0]):
        p = point[q]
        if p >= 0:
            out[q, 0] = field_x[p]
            out[q, 1] = field_y[p]
        else:
            out[q, 0] = 0.0
            out[q, 1] = 0.0
