"""The frictional solid's update on any lattice: the stiffness matrix of the free particles'
displacements (and rotations, where they turn) in scipy.sparse, solved by SuperLU
(docs/model.md, "Frictional solid", "Solver").

Exact to round-off, and the only solver when particles rotate (the gear-like coupling of
rotations does not split by component) or when the lattice is not a full square grid. The
matrix's sparsity pattern is fixed by the springs, so it is assembled from a pattern built once
(:func:`pattern`) and each spring's two stiffnesses (:func:`matrix`).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from porenet.kinds.mindlin.kernels.frictional import LEVER


class Pattern(NamedTuple):
    """The sparsity pattern of the stiffness matrix.

    Entry ``k`` is ``normal_coef[k] * K_n[spring[k]] + shear_coef[k] * K_t[spring[k]]`` at
    ``(row[k], col[k])``, plus the foundation on the translational diagonal.

    Attributes
    ----------
    dof : ndarray of int64, shape (n_particles, 3)
        Unknown of each particle's x, y displacement and rotation (-1: fixed or held).
    size : int
        Unknowns.
    row, col, spring : ndarray of int64, shape (E,)
    normal_coef, shear_coef : ndarray of float64, shape (E,)
    translational : ndarray of int64
        The unknowns that are displacements (where the foundation acts).
    """

    dof: np.ndarray
    size: int
    row: np.ndarray
    col: np.ndarray
    spring: np.ndarray
    normal_coef: np.ndarray
    shear_coef: np.ndarray
    translational: np.ndarray


def pattern(
    spring_particles: np.ndarray, axis: np.ndarray, fixed: np.ndarray, rotation: bool
) -> Pattern:
    """The matrix pattern of a spring network (rotations as unknowns if ``rotation``)."""
    n_particles = len(fixed)
    free = np.flatnonzero(~np.asarray(fixed, dtype=bool))
    per = 3 if rotation else 2
    dof = np.full((n_particles, 3), -1, dtype=np.int64)
    dof[free, :per] = np.arange(per * free.size).reshape(-1, per)
    m, n = spring_particles[:, 0], spring_particles[:, 1]
    ex, ey = axis[:, 0], axis[:, 1]
    zero = np.zeros(len(m))
    # B rows: normal  dh-direction  (u_n - u_m) . e
    #         shear   (u_n - u_m) . t - l (theta_m + theta_n),  t = (-e_y, e_x)
    unknowns = [dof[n, 0], dof[n, 1], dof[m, 0], dof[m, 1], dof[m, 2], dof[n, 2]]
    normal = [ex, ey, -ex, -ey, zero, zero]
    lever = np.full(len(m), -LEVER)
    shear = [-ey, ex, ey, -ex, lever, lever]
    rows, cols, springs, ncoef, scoef = [], [], [], [], []
    every = np.arange(len(m))
    for i in range(6):
        for j in range(6):
            rows.append(unknowns[i])
            cols.append(unknowns[j])
            springs.append(every)
            ncoef.append(normal[i] * normal[j])
            scoef.append(shear[i] * shear[j])
    row, col = np.concatenate(rows), np.concatenate(cols)
    nc, sc = np.concatenate(ncoef), np.concatenate(scoef)
    keep = (row >= 0) & (col >= 0) & ((nc != 0) | (sc != 0))
    translational = np.concatenate([dof[free, 0], dof[free, 1]])
    return Pattern(dof, per * free.size, row[keep], col[keep], np.concatenate(springs)[keep],
                   nc[keep], sc[keep], np.sort(translational))  # fmt: skip


def matrix(
    pat: Pattern,
    normal_stiffness: np.ndarray,
    shear_stiffness: np.ndarray,
    foundation_stiffness: float,
):
    """The stiffness matrix (CSC) for the springs' normal and tangential stiffnesses."""
    from scipy.sparse import coo_matrix

    values = (pat.normal_coef * normal_stiffness[pat.spring]
              + pat.shear_coef * shear_stiffness[pat.spring])  # fmt: skip
    row, col = pat.row, pat.col
    if foundation_stiffness > 0.0:
        row = np.concatenate([row, pat.translational])
        col = np.concatenate([col, pat.translational])
        values = np.concatenate([values, np.full(pat.translational.size, foundation_stiffness)])
    return coo_matrix((values, (row, col)), shape=(pat.size, pat.size)).tocsc()


def solve(
    pat: Pattern,
    normal_stiffness: np.ndarray,
    shear_stiffness: np.ndarray,
    foundation_stiffness: float,
    force: np.ndarray,
    torque: np.ndarray,
    du: np.ndarray,
    rotation_increment: np.ndarray,
) -> None:
    """Solve for the increments under the out-of-balance ``force`` ((n_particles, 2)) and
    ``torque`` ((n_particles,)), into ``du`` and ``rotation_increment`` (0 where fixed)."""
    from scipy.sparse.linalg import splu

    rhs = np.zeros(pat.size)
    dof = pat.dof
    has = dof >= 0
    rhs[dof[has[:, 0], 0]] = force[has[:, 0], 0]
    rhs[dof[has[:, 1], 1]] = force[has[:, 1], 1]
    rhs[dof[has[:, 2], 2]] = torque[has[:, 2]]
    x = splu(matrix(pat, normal_stiffness, shear_stiffness, foundation_stiffness)).solve(rhs)
    du[:] = 0.0
    rotation_increment[:] = 0.0
    du[has[:, 0], 0] = x[dof[has[:, 0], 0]]
    du[has[:, 1], 1] = x[dof[has[:, 1], 1]]
    rotation_increment[has[:, 2]] = x[dof[has[:, 2], 2]]
