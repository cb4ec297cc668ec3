"""How an operator has moved since a multigrid hierarchy was built from an earlier one, for the
frictional solid's solver (``porenet/kinds/mindlin/grid_solver.py``; docs/performance.md,
"Frictional solid" and "Hierarchies of the stuck operator").

:func:`drifted_edges` counts the edges whose weight changed much (contacts that opened or
closed), the trigger of a rebuild; :func:`remember_stuck` keeps the operator a hierarchy is
built from, with every sliding contact stuck. Pure functions on
:class:`porenet.kinds.mindlin.kernels.multigrid.Operator`.
"""

from __future__ import annotations

from porenet.jit.jit import njit
from porenet.kinds.mindlin.kernels.multigrid import Operator


@njit
def drifted_edges(operator: Operator, reference: Operator, threshold: float) -> int:
    """Edges whose weight changed by more than ``threshold`` of itself between ``reference``
    (the operator a hierarchy was built from) and ``operator``: ``|w - w_0| > threshold
    max(w, w_0)``. An edge that is zero in either is not counted: only a contact sliding with
    rotations held has a zero weight (its tangential stiffness), and contacts at Coulomb's
    cap start and stop sliding at nearly every update, which would rebuild the hierarchy
    at nearly every solve (docs/performance.md, "Frictional solid")."""
    count = 0
    for a, b in ((operator.across_columns, reference.across_columns),
                 (operator.across_rows, reference.across_rows)):  # fmt: skip
        flat_a, flat_b = a.ravel(), b.ravel()
        for i in range(flat_a.shape[0]):
            w, w0 = flat_a[i], flat_b[i]
            if w != 0.0 and w0 != 0.0 and abs(w - w0) > threshold * max(w, w0):
                count += 1
    return count


@njit
def remember_stuck(operator: Operator, stuck: Operator) -> int:
    """Bring ``stuck`` up to date with ``operator``, in place: every edge that is not zero in
    ``operator`` takes its weight, an edge that is zero there (only a sliding contact's, with
    rotations held: its tangential stiffness) keeps the weight it had when it last stuck, and
    the diagonal is ``operator``'s. Returns how many edges ``stuck`` holds for such contacts
    (0: ``stuck`` equals ``operator``).

    ``stuck`` is what the frictional solid builds its hierarchies from: the sliding set swings
    by tens of thousands of contacts between updates, and coarse levels built from one
    moment's set precondition the next ones badly in both directions; built with every
    sliding contact stuck they stay one consistent, stiffer picture of the medium, and the
    finest level (:func:`refresh_finest`) carries the current modes (docs/performance.md,
    "Hierarchies of the stuck operator")."""
    held = 0
    for a, b in ((operator.across_columns, stuck.across_columns),
                 (operator.across_rows, stuck.across_rows)):  # fmt: skip
        for i in range(a.shape[0]):
            for j in range(a.shape[1]):
                if a[i, j] != 0.0:
                    b[i, j] = a[i, j]
                elif b[i, j] != 0.0:
                    held += 1
    d, e = operator.diagonal, stuck.diagonal
    for i in range(d.shape[0]):
        for j in range(d.shape[1]):
            e[i, j] = d[i, j]
    return held
