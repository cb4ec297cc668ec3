"""The frictional solid's multigrid solver on the square lattice: two scalar problems per
update, hierarchies reused while they precondition well (docs/model.md, "Frictional solid",
"Solver")."""

from __future__ import annotations

from concurrent.futures import ThreadPoolExecutor

import numpy as np

from porenet.kinds.mindlin.kernels import multigrid as mg
from porenet.kinds.mindlin.kernels import multigrid_drift as drift
from porenet.kinds.mindlin.kernels.grid import (
    GridLayout,
    fill_operators,
    gather_fields,
    operators,
    scatter_fields,
)

#: A hierarchy is rebuilt when a solve takes more than this many iterations more than the
#: first solve after the hierarchy was built (the operator has drifted from it).
REBUILD_MARGIN = 4

#: ... or before a solve, when more than :data:`REBUILD_EDGES` edges' stiffnesses changed by
#: more than this fraction of themselves since the build (contacts that opened or closed):
#: the V-cycle's correction is the solver's estimate of the error left, and it is a good one
#: only while the hierarchy is close to the operator. Fewer changes are left to the finest
#: level, which follows the operator at every solve. Contacts that start or stop sliding
#: (their edge goes to or from zero, at nearly every update with friction) never count: the
#: hierarchy is built with every sliding contact stuck
#: (:func:`porenet.kinds.mindlin.kernels.multigrid_drift.remember_stuck`), and only the finest level
#: sees them.
REBUILD_DRIFT = 0.5
REBUILD_EDGES = 32


_POOL: ThreadPoolExecutor | None = None


def _pool() -> ThreadPoolExecutor:
    """One worker thread, shared by every solver of the process, for the second component."""
    global _POOL
    if _POOL is None:
        _POOL = ThreadPoolExecutor(max_workers=1, thread_name_prefix="porenet-multigrid")
    return _POOL


def _two_threads() -> bool:
    from porenet.jit.threads import thread_setting

    return thread_setting().most >= 2


class GridSolver:
    """Solves ``K du = f`` for the displacement increments of a square lattice's particles
    with rotations held: ``u_x`` and ``u_y`` separately, each by conjugate gradients
    preconditioned by a V-cycle (:mod:`porenet.kinds.mindlin.kernels.multigrid`).

    The hierarchies are built from the operator of one update, with every sliding contact
    at the tangential stiffness it had when it last stuck (the operator "stuck"), and kept
    for later ones (whose stiffnesses have changed a little): the iteration is exact with the
    current operator whatever the preconditioner. The finest level (the smoother, and the
    operator the conjugate gradients apply) is brought up to date before every solve; the
    whole hierarchy is rebuilt when more than :data:`REBUILD_EDGES` edges' stiffnesses (of
    the stuck operator) changed by more than :data:`REBUILD_DRIFT` of themselves since the
    build, and when a solve needs :data:`REBUILD_MARGIN` more iterations than right after it
    was built. Without sliding the stuck operator is the operator.

    Parameters
    ----------
    layout : GridLayout
    deformation_tolerance, force_tolerance : float
        :func:`porenet.kinds.mindlin.kernels.multigrid.solve`'s criteria (a; gamma a).
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
        # the operators with every sliding contact stuck (drift.remember_stuck), and those the
        # hierarchies were built from (stuck, at the build)
        self._stuck = operators(m)
        self._built_from = operators(m)
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
        normal and tangential stiffnesses of this update. ``u_x`` and ``u_y`` are solved at
        the same time on two threads when the run may use two (:func:`porenet.jit.threads.
        thread_setting`): two independent solves of tens of milliseconds, with no barrier
        between them; the result does not depend on it.

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
        if _two_threads():
            other = _pool().submit(self._field, 1)
            results = [self._field(0), other.result()]
        else:
            results = [self._field(0), self._field(1)]
        gather_fields(self.layout, self._x[0], self._x[1], du)
        return (sum(r[0] for r in results), all(r[1] for r in results),
                sum(r[2] for r in results))  # fmt: skip

    def _field(self, axis: int) -> tuple[int, bool, int]:
        """Solve one component: (V-cycles, converged, hierarchies built)."""
        op, stuck = self._operators[axis], self._stuck[axis]
        held = drift.remember_stuck(op, stuck)
        rebuilt = 0
        hierarchy = self._hierarchies[axis]
        reference = self._built_from[axis]
        drifted = hierarchy is not None and (
            drift.drifted_edges(stuck, reference, REBUILD_DRIFT) > REBUILD_EDGES
        )
        if hierarchy is None or drifted:
            rebuilt += self._build(axis, held)
        else:
            mg.refresh_finest(hierarchy, op)
        its = self._run(axis, op)
        converged = its >= 0
        if its < 0 or its > max(self._baseline[axis], 2) + REBUILD_MARGIN:
            # drifted (or failed): rebuild (from the stuck operator) and go on from where it is
            rebuilt += self._build(axis, held)
            more = self._run(axis, op)
            its = (its if its > 0 else self.max_iterations) + abs(more)
            converged = more >= 0
        return its, converged, rebuilt

    def _build(self, axis: int, held: int) -> int:
        """Build ``axis``'s hierarchy from its stuck operator; its finest level then made the
        current operator's when ``held`` edges of sliding contacts differ."""
        stuck = self._stuck[axis]
        hierarchy = mg.build(stuck)
        if held:
            mg.refresh_finest(hierarchy, self._operators[axis])
        reference = self._built_from[axis]
        reference.across_columns[:] = stuck.across_columns
        reference.across_rows[:] = stuck.across_rows
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
