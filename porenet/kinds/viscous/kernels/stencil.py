"""The five-point stencil of a run of pores along one row of a canonical square grid.

The sweeps over the active box (:func:`porenet.kinds.viscous.kernels.diffusion.grid_sweep`,
:func:`porenet.kinds.viscous.kernels.chebyshev.grid_stage`) do the interior of each row, the pores
with both horizontal neighbours in the box, as one loop over views aligned on the run: index
``j`` of every view is pore ``j`` of the run, so each index is the loop counter itself (no
offset, no sign test) and the loop compiles to SIMD instructions. :func:`interior_run`
builds the views; the first and last pore of each row are done one by one.

Canonical throat order (:attr:`porenet.kinds.viscous.kernels.state.Network.grid_n`): horizontal
throat (i, j)-(i, j+1) is ``i (n-1) + j``, vertical (i, j)-(i+1, j) is ``n (n-1) + i n + j``.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from porenet.jit.jit import njit


class Stencil(NamedTuple):
    """Aligned views of a run of pores of one row and of their neighbours.

    Attributes
    ----------
    centre, west, east, up, down : ndarray of float64
        The values at the run's pores and at their west, east, up and down neighbours (``up``
        and ``down`` are any valid views when the row above or below is not in the box).
    g_west, g_east, g_up, g_down : ndarray of float64
        The conductances of the throats to those neighbours.
    g_outlet : ndarray of float64
        The run's pores' conductances to the outlet.
    has_up, has_down : bool
        Whether the row above / below is in the box (its neighbours count).
    on_outlet : bool
        Whether the row is on the lattice's edge (elsewhere ``g_outlet`` is 0 and need not be
        read).
    """

    centre: np.ndarray
    west: np.ndarray
    east: np.ndarray
    up: np.ndarray
    down: np.ndarray
    g_west: np.ndarray
    g_east: np.ndarray
    g_up: np.ndarray
    g_down: np.ndarray
    g_outlet: np.ndarray
    has_up: bool
    has_down: bool
    on_outlet: bool


@njit(helper=True)
def interior_run(
    y: np.ndarray,
    conductance: np.ndarray,
    outlet: np.ndarray,
    n: int,
    first: int,
    stop: int,
    has_up: bool,
    has_down: bool,
) -> Stencil:
    """The stencil of the pores ``[first, stop)`` of one row of the ``n x n`` grid (with both
    horizontal neighbours in the box): values ``y``, throat conductances ``conductance`` (by
    canonical throat), outlet conductances ``outlet`` (by pore).

    Call it only from a helper compiled without reference counting (``@njit(helper=True)``,
    as the sweeps' row functions are): its views carry no reference count of their own, and a
    caller with reference counting releases their parents' memory when it drops them
    (``porenet/kinds/viscous/tests/test_stencil.py``)."""
    i = first // n
    count = stop - first
    vertical = n * (n - 1)
    west = i * (n - 1) + first - i * n - 1  # throat between pores first - 1 and first
    above = vertical + first - n if has_up else vertical + first  # any valid view if unused
    below = vertical + first if has_down else vertical + first - n
    return Stencil(
        y[first:stop],
        y[first - 1 : stop - 1],
        y[first + 1 : stop + 1],
        y[first - n : stop - n] if has_up else y[first:stop],
        y[first + n : stop + n] if has_down else y[first:stop],
        conductance[west : west + count],
        conductance[west + 1 : west + 1 + count],
        conductance[above : above + count],
        conductance[below : below + count],
        outlet[first:stop],
        has_up,
        has_down,
        i == 0 or i == n - 1,
    )
