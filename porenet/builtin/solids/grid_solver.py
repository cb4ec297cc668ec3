"""The frictional solid's multigrid solver on the square lattice: two scalar problems per
update, hierarchies reused while they precondition well (docs/model.md, "Frictional solid",
"Solver")."""

from __future__ import annotations

import numpy as np

from porenet.kernels.mechanics import multigrid as mg
from porenet.kernels.mechanics.grid import (
    GridLayout,
    fill_operators,
    gather_fields,
    operators,
    scatter_fields,
)

#: A hierarchy is rebuilt when a solve takes more than this many iterations more than the
#: first solve after the hierarchy was built (the operator has drifted from it).
REBUILD_MARGIN = 4

#: ... or before a solve, when an edge's stiffness changed by more than this fraction since the
#: build (a contact opened, closed, started or stopped sliding): the V-cycle's correction is
#: the solver's estimate of the error left, and it is a good one only while the hierarchy
#: is close to the operator.
REBUILD_DRIFT = 0.5


class GridSolver:
    """Solves ``K du = f`` for the displacement increments of a square lattice's particles
    with rotations held: ``u_x`` and ``u_y`` separately, each by conjugate gradients
    preconditioned by a V-cycle (:mod:`porenet.kernels.mechanics.multigrid`).

    The hierarchies are built from the operator of one update and kept for later ones (whose
    stiffnesses have changed a little): the iteration is exact with the current operator
    whatever the preconditioner; a hierarchy is rebuilt when an edge's stiffness changed by
    more than :data:`REBUILD_DRIFT` of itself since the build, and when its solve needs
    :data:`REBUILD_MARGIN` more iterations than right after it was built.

    Parameters
    ----------
    layout : GridLayout
    deformation_tolerance, force_tolerance : float
        :func:`porenet.kernels.mechanics.multigrid.solve`'s criteria (a; gamma a).
    max_iterations : int
    """

    def __init__(
        self, layout: GridLayout, deformation_tolerance: float, force_tolerance: float,
        max_iterations: int,
    ) -> None:  # fmt: skip
        self.layout = layout
        self.deformation_tolerance = deformation_tolerance
        self.force_tolerance = force_tolerance
        self.max_iterations = max_iterations
        m = layout.size
        self._operators = operators(m)
        self._hierarchies: list[mg.Hierarchy | None] = [None, None]
        self._built_from = operators(m)  # the operators the hierarchies were built from
        self._workspaces: list[mg.Workspace | None] = [None, None]
        self._baseline = [0, 0]
        self._rhs = np.zeros((2, m * m))
        self._x = np.zeros((2, m * m))

    def solve(
        self, normal_stiffness: np.ndarray, shear_stiffness: np.ndarray,
        foundation_stiffness: float, force: np.ndarray, du: np.ndarray,
    ) -> tuple[int, bool, int]:  # fmt: skip
        """Solve for ``du`` ((n_particles, 2), in/out: its value on entry is the first
        guess) under the out-of-balance ``force`` ((n_particles, 2)) with the springs'
        normal and tangential stiffnesses of this update.

        Returns
        -------
        iterations : int
            V-cycles over both components.
        converged : bool
        rebuilt : int
            Hierarchies built for this solve.
        """
        op_x, op_y = self._operators
        fill_operators(self.layout, normal_stiffness, shear_stiffness, foundation_stiffness,
                       op_x, op_y)  # fmt: skip
        scatter_fields(self.layout, force, self._rhs[0], self._rhs[1])
        scatter_fields(self.layout, du, self._x[0], self._x[1])
        total, converged, rebuilt = 0, True, 0
        for axis, op in enumerate(self._operators):
            if (self._hierarchies[axis] is None
                    or mg.largest_drift(op, self._built_from[axis]) > REBUILD_DRIFT):  # fmt: skip
                rebuilt += self._build(axis, op)
            its = self._run(axis, op)
            if its < 0 or its > max(self._baseline[axis], 2) + REBUILD_MARGIN:
                # drifted (or failed): rebuild from this operator and go on from where it is
                rebuilt += self._build(axis, op)
                more = self._run(axis, op)
                its = (abs(its) if its > 0 else self.max_iterations) + abs(more)
                if more < 0:
                    converged = False
            total += its
        gather_fields(self.layout, self._x[0], self._x[1], du)
        return total, converged, rebuilt

    def _build(self, axis: int, op: mg.Operator) -> int:
        hierarchy = mg.build(op)
        reference = self._built_from[axis]
        reference.across_columns[:] = op.across_columns
        reference.across_rows[:] = op.across_rows
        self._hierarchies[axis] = hierarchy
        self._workspaces[axis] = mg.workspace(hierarchy)
        self._baseline[axis] = -1  # set by the next solve
        return 1

    def _run(self, axis: int, op: mg.Operator) -> int:
        hierarchy, work = self._hierarchies[axis], self._workspaces[axis]
        assert hierarchy is not None and work is not None
        its = mg.solve(op, hierarchy, work, self._rhs[axis], self._x[axis],
                       self.deformation_tolerance, self.force_tolerance,
                       self.max_iterations)  # fmt: skip
        if self._baseline[axis] < 0 and its >= 1:
            self._baseline[axis] = its
        return its
