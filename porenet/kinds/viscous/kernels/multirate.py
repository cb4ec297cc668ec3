"""Local time steps for the viscous model: fine steps in a window, one long step elsewhere.

Pure numba functions on arrays, in scaled units (:mod:`porenet.kinds.viscous.kernels.explicit`); the
macro steps are driven by :class:`porenet.kinds.viscous.local_steps.LocalSteps`.

At small Ca the RKC integrator (:mod:`porenet.kinds.viscous.kernels.rkc`) sweeps the whole box of
active pores ~150 times per drained pore because the few pores next to the newest meniscus need
short steps: after every landing the pressure there relaxes like ``ln t``, and the step can only
grow geometrically. The error of a step is local (``tests/benchmarks/error_locality.py``: every pore
whose error estimate exceeds 5 % of the tolerance in a step of 200 lies within 44 pores of the
landing), so a macro step of length ``H`` does (coarse first, then fine, then reflux: Savcenco,
Hundsdorfer & Verwer, BIT 47, 137, 2007; Berger & Colella, J. Comput. Phys. 82, 64, 1989)

1. **one coarse RKC step** of ``H`` over the whole active box (:func:`coarse_step`), the
   menisci replaced by the injection rate as a source at the pores of the menisci that move
   (no pore drains in it), accepted when its error estimate *outside* a box ``W`` around those
   menisci is within the tolerance;
2. **the fine integration of** ``W``: the explicit and RKC integrators, unchanged, over the
   pores of ``W`` only, with every landing, start and Haines jump as without a window, the
   pores just outside ``W`` (its ring) held to the coarse step's pressures interpolated
   linearly in time (:mod:`porenet.kinds.viscous.kernels.window`); it ends at ``t0 + H`` or earlier,
   at a cut (a meniscus outside ``W`` may start, or a pore drains near its edge);
3. **the far field** (:func:`far_update`): every pore outside ``W`` takes the coarse
   step's pressures interpolated to the time the fine integration reached, and each ring
   pore the difference between the volume the fine integration and the coarse step carried
   across its throat (refluxing), so that volume is conserved exactly.

The ring's pressures come from a step over both sides, so the coupling is as stable as the
coarse step (a Dirichlet value extrapolated from the current state instead is unstable once
``H`` exceeds the exchange time of one throat: a two-pore model amplifies the difference by
``2 g H`` per macro step). What the coarse step gets wrong inside ``W`` reaches the ring only
through its error estimate's blind spot, the source model; the refluxed volumes measure it
after each macro step (:func:`far_update` returns the largest), and the driver shortens ``H``
when they approach the tolerance.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from porenet.jit.jit import njit
from porenet.kinds.viscous.kernels.chebyshev import sweep
from porenet.kinds.viscous.kernels.diffusion import set_add, set_remove
from porenet.kinds.viscous.kernels.menisci import undrained_pore
from porenet.kinds.viscous.kernels.rkc_step import Stages, StepStart, imex_stages
from porenet.kinds.viscous.kernels.state import Count, Front, Menisci, Network, Pump, Sweep
from porenet.kinds.viscous.kernels.window import (
    Mode,
    Ring,
    Window,
    WindowFloat,
    WindowInt,
    book_shadow,
    inside,
)

#: Width (standard deviation, pores) and reach of the Gaussian over which a ring throat's
#: refluxed volume is spread (:func:`_deposit`).
DEPOSIT_WIDTH = 2.0
DEPOSIT_REACH = 6


@njit
def window_ring(n: int, wbox: np.ndarray, nbox: np.ndarray, ring_i: np.ndarray) -> int:
    """List the throats between the box ``wbox`` and the pores just outside it that lie in
    the active box ``nbox`` (the ring): per throat ``ring_i[:, e] = (pore in W, ring pore,
    throat)`` in canonical order (horizontal ``i (n-1) + j``, vertical ``n (n-1) + i n + j``),
    from the first column of ``ring_i`` on. Returns their number (at most ``2 (rows +
    columns)`` of the box)."""
    vertical = n * (n - 1)
    k = 0
    i0, i1, j0, j1 = wbox[0], wbox[1], wbox[2], wbox[3]
    if i0 > nbox[0]:
        for j in range(j0, j1):
            r = (i0 - 1) * n + j
            ring_i[0, k], ring_i[1, k], ring_i[2, k] = r + n, r, vertical + r
            k += 1
    if i1 < nbox[1]:
        for j in range(j0, j1):
            r = i1 * n + j
            ring_i[0, k], ring_i[1, k], ring_i[2, k] = r - n, r, vertical + r - n
            k += 1
    if j0 > nbox[2]:
        for i in range(i0, i1):
            r = i * n + j0 - 1
            ring_i[0, k], ring_i[1, k], ring_i[2, k] = r + 1, r, i * (n - 1) + j0 - 1
            k += 1
    if j1 < nbox[3]:
        for i in range(i0, i1):
            r = i * n + j1
            ring_i[0, k], ring_i[1, k], ring_i[2, k] = r - 1, r, i * (n - 1) + j1 - 1
            k += 1
    return k


@njit(helper=True)
def _add_outlet(k: int, w: int, g_out: np.ndarray, ring_i: np.ndarray) -> int:
    if g_out[w] > 0.0:
        ring_i[0, k], ring_i[1, k], ring_i[2, k] = w, -1, w
        return k + 1
    return k


@njit
def outlet_links(n: int, nbox: np.ndarray, g_out: np.ndarray, ring_i: np.ndarray, k0: int) -> int:
    """List the outlet links of the active box's pores (``g_out > 0``, on the lattice's edge)
    as ``(pore, -1, pore)`` from entry ``k0`` on: in the coarse step their shadow sums give
    each outlet pore's outflow. Returns their number (at most ``4 n``)."""
    k = k0
    for i in range(nbox[0], nbox[1]):
        if i == 0 or i == n - 1:
            for j in range(nbox[2], nbox[3]):
                k = _add_outlet(k, i * n + j, g_out, ring_i)
            continue
        if nbox[2] == 0:
            k = _add_outlet(k, i * n, g_out, ring_i)
        if nbox[3] == n and n > 1:
            k = _add_outlet(k, i * n + n - 1, g_out, ring_i)
    return k - k0


class CoarseStep(NamedTuple):
    """What :func:`coarse_step` reads besides the sweep and the window.

    Attributes
    ----------
    h : float
        The step's length.
    stages : int
        Its stage count.
    sources, rates : ndarray of int64 and float64
        Constant sources (volume per time) at the pores of the menisci that move.
    menisci, pump : Menisci, Pump
        As for :func:`porenet.kinds.viscous.kernels.rkc_step.imex_stages`, with no meniscus listed.
    threshold : float
        Local error above which a pore must lie in the window.
    """

    h: float
    stages: int
    sources: np.ndarray
    rates: np.ndarray
    menisci: Menisci
    pump: Pump
    threshold: float


@njit
def coarse_step(
    field: Sweep,
    p: np.ndarray,
    window: Window,
    step: CoarseStep,
    buffers: np.ndarray,
    f0: np.ndarray,
    fnew: np.ndarray,
    zero: np.ndarray,
    p1: np.ndarray,
    ebox: np.ndarray,
) -> float:
    """One RKC step of ``step.h`` in ``step.stages`` stages over the active box of ``field``
    from ``p``, without menisci, with constant sources ``step.rates`` (volume per time) at the
    pores ``step.sources`` (the menisci that move, in the window); ``buffers`` (3, N), ``f0``,
    ``fnew`` and ``zero`` (N) are the RKC integrator's buffers. Writes the end state into
    ``p1`` (``p`` is not changed); into row ``Ring.COARSE`` of the window's ring values the
    volume each ring throat carried out of the window and each outlet link (listed after the
    ring throats, :func:`outlet_links`) out of its pore; into ``ebox`` the bounding box of the
    pores whose local error estimate exceeds ``step.threshold`` (empty if none). Returns the
    total outflow."""
    h, m = step.h, step.stages
    grid_n, box = field.grid_n, field.box
    inv_vol = field.inverse_volume
    wi, ring_f = window.ints, window.ring_value
    qst, lst = np.zeros((3, 1)), np.zeros((3, 1))
    pst, ast = np.zeros(3), np.zeros((3, 2))
    r_ell, moved, q0 = np.zeros(1), np.zeros(1, dtype=np.bool_), np.zeros(1)
    out0 = sweep(field, p, p, f0, (0.0, 0.0, 0.0, 0.0), f0, True)
    for s in range(len(step.sources)):
        f0[step.sources[s]] += step.rates[s]
    mode = wi[WindowInt.MODE]
    wi[WindowInt.MODE] = Mode.COARSE
    ring_f[Ring.COARSE, : wi[WindowInt.N_RING] + wi[WindowInt.N_OUTLET]] = 0.0
    stages = Stages(buffers, zero, zero, qst, lst, pst, ast, r_ell, moved)
    start = StepStart(p, f0, out0, q0)
    k = imex_stages(h, m, field, start, 0, step.menisci, step.pump, stages, window)
    book_shadow(window, m, Ring.COARSE)
    wi[WindowInt.MODE] = mode
    ds = buffers[k]
    sweep(field, ds, ds, f0, (0.0, 0.0, 0.0, 0.0), fnew, True)
    ebox[0] = ebox[2] = grid_n
    ebox[1] = ebox[3] = 0
    for i in range(box[0], box[1]):
        for c in range(i * grid_n + box[2], i * grid_n + box[3]):
            change = ds[c]
            p1[c] = p[c] + change
            e = abs(-0.8 * change + 0.4 * h * (2.0 * f0[c] + fnew[c]) * inv_vol[c])
            if e > step.threshold:
                j = c - i * grid_n
                ebox[0] = min(ebox[0], i)
                ebox[1] = max(ebox[1], i + 1)
                ebox[2] = min(ebox[2], j)
                ebox[3] = max(ebox[3], j + 1)
    return ast[k, 1]


@njit
def start_fine(
    window: Window, p: np.ndarray, p1: np.ndarray, field: Sweep, t0: float, h: float
) -> None:
    """Before the fine integration of a macro step from ``t0`` of length ``h``: every active
    pore's pressure at ``t0`` and its rate to the coarse step's end ``p1`` (linear in time)
    into the window's ``p0`` and ``rate`` (read for the menisci outside the window), the same
    for the ring pores, and nothing booked yet."""
    ring_i, ring_f, p0, rate = window.ring_index, window.ring_value, window.p0, window.rate
    grid_n, box = field.grid_n, field.box
    window.floats[WindowFloat.T0] = t0
    for i in range(box[0], box[1]):
        for k in range(i * grid_n + box[2], i * grid_n + box[3]):
            p0[k] = p[k]
            rate[k] = (p1[k] - p[k]) / h
    for e in range(window.ints[WindowInt.N_RING]):
        r = ring_i[1, e]
        ring_f[Ring.FLUX, e] = 0.0
        ring_f[Ring.P0, e] = p[r]
        ring_f[Ring.RATE, e] = rate[r]


@njit
def far_update(
    field: Sweep,
    p: np.ndarray,
    p1: np.ndarray,
    vol: np.ndarray,
    drained: np.ndarray,
    window: Window,
    theta: float,
) -> tuple[float, float, float]:
    """The far field after a fine integration that reached ``theta`` of the macro step:
    every active pore outside the window takes ``p + theta (p1 - p)`` (the coarse step's
    pressures interpolated in time), and each ring pore in addition the volume its throat
    carried out of the window in the fine integration less ``theta`` times what it carried in
    the coarse step (refluxing), so that volume is conserved to round-off; each throat's
    refluxed volume is spread over the pores around it, on both sides (:func:`_deposit`).
    ``p`` holds the start values outside the window but at the ring pores, which the fine
    integration overwrote. Returns the stored volume change (the far field's and the
    refluxed volumes), the far field's outflow and the largest refluxed pressure change."""
    grid_n, box, inv_vol = field.grid_n, field.box, field.inverse_volume
    wbox, ring_i, ring_f = window.box, window.ring_index, window.ring_value
    n_ring, n_outlet = window.ints[WindowInt.N_RING], window.ints[WindowInt.N_OUTLET]
    for e in range(n_ring):
        r = ring_i[1, e]
        p[r] = ring_f[Ring.P0, e]  # its value at t0 again
    stored = 0.0
    for i in range(box[0], box[1]):
        inside_rows = wbox[0] <= i < wbox[1]
        for c in range(i * grid_n + box[2], i * grid_n + box[3]):
            j = c - i * grid_n
            if inside_rows and wbox[2] <= j < wbox[3]:
                continue
            dp = theta * (p1[c] - p[c])
            p[c] += dp
            stored += vol[c] * dp
    outflow = 0.0
    for e in range(n_ring, n_ring + n_outlet):
        if not inside(wbox, grid_n, ring_i[0, e]):
            outflow += theta * ring_f[Ring.COARSE, e]
    largest = 0.0
    for e in range(n_ring):
        dv = ring_f[Ring.FLUX, e] - theta * ring_f[Ring.COARSE, e]
        largest = max(largest, abs(dv * inv_vol[ring_i[1, e]]))
        stored += _deposit(grid_n, box, ring_i[0, e], ring_i[1, e], dv, p, vol, drained)
    return stored, outflow, largest


@njit(helper=True)
def _deposit(
    n: int,
    box: np.ndarray,
    w: int,
    r: int,
    dv: float,
    p: np.ndarray,
    vol: np.ndarray,
    drained: np.ndarray,
) -> float:
    """Spread the volume ``dv`` over the undrained active pores around the throat between
    pores ``w`` and ``r``, with Gaussian weights of width :data:`DEPOSIT_WIDTH` pores about
    its midpoint (cut at :data:`DEPOSIT_REACH`): a point deposit would leave a kink that an
    RKC step damps only slowly (its stability polynomial keeps ~0.9 of the stiffest modes),
    and that its error estimate reads as a large error. Returns the volume deposited
    (``dv``, or 0 when no pore can take it)."""
    iw, jw = w // n, w % n
    ir, jr = r // n, r % n
    ci, cj = 0.5 * (iw + ir), 0.5 * (jw + jr)
    total = 0.0
    for i in range(max(ir - DEPOSIT_REACH, box[0]), min(ir + DEPOSIT_REACH + 1, box[1])):
        for j in range(max(jr - DEPOSIT_REACH, box[2]), min(jr + DEPOSIT_REACH + 1, box[3])):
            k = i * n + j
            if not drained[k]:
                d2 = (i - ci) ** 2 + (j - cj) ** 2
                total += vol[k] * np.exp(-0.5 * d2 / DEPOSIT_WIDTH**2)
    if total <= 0.0:
        return 0.0
    scale = dv / total
    for i in range(max(ir - DEPOSIT_REACH, box[0]), min(ir + DEPOSIT_REACH + 1, box[1])):
        for j in range(max(jr - DEPOSIT_REACH, box[2]), min(jr + DEPOSIT_REACH + 1, box[3])):
            k = i * n + j
            if not drained[k]:
                d2 = (i - ci) ** 2 + (j - cj) ** 2
                p[k] += scale * np.exp(-0.5 * d2 / DEPOSIT_WIDTH**2)
    return dv


@njit
def split_front(
    n: int,
    wbox: np.ndarray,
    front: np.ndarray,
    nf: int,
    tp: np.ndarray,
    drained: np.ndarray,
    wfront: np.ndarray,
    wfpos: np.ndarray,
    far: np.ndarray,
) -> tuple[int, int]:
    """Split the frontier throats ``front[:nf]`` into those whose meniscus enters a pore of
    the box ``wbox`` (the window's own front ``wfront``, with ``wfpos`` their slots, -1 for
    every other throat on entry) and the others (``far``). Returns both counts."""
    n_w = n_far = 0
    for s in range(nf):
        f = front[s]
        if inside(wbox, n, undrained_pore(tp, drained, f)):
            wfront[n_w] = f
            wfpos[f] = n_w
            n_w += 1
        else:
            far[n_far] = f
            n_far += 1
    return n_w, n_far


@njit
def far_level(
    far: np.ndarray,
    n_far: int,
    tp: np.ndarray,
    drained: np.ndarray,
    pe: np.ndarray,
    p0: np.ndarray,
    rate: np.ndarray,
    h: float,
) -> float:
    """The least invading pressure at which a meniscus of ``far[:n_far]`` reaches its
    threshold during a macro step of ``h``, its pore's pressure linear in time (``p0``,
    ``rate``): the minimum of ``pe + min(p0, p0 + h rate)`` (inf if none)."""
    level = np.inf
    for s in range(n_far):
        f = far[s]
        i = undrained_pore(tp, drained, f)
        level = min(level, pe[f] + min(p0[i], p0[i] + h * rate[i]))
    return level


@njit
def merge_front(
    net: Network,
    drained: np.ndarray,
    front: Front,
    counters: np.ndarray,
    drained_now: np.ndarray,
    window_throats: np.ndarray,
    window_slots: np.ndarray,
    n_window: int,
) -> None:
    """After a fine integration with the window's own front (its throats ``window_throats
    [:n_window]``, their slots ``window_slots``) that drained the pores ``drained_now``:
    update the global ``front`` and ``counters[N_FRONT]`` as
    :func:`porenet.kinds.viscous.kernels.explicit.drain_pore` would have (a throat joining two
    drained pores leaves it, one from a drained pore to an undrained one joins it), and clear
    the window front's slots."""
    for k in range(drained_now.shape[0]):
        i = drained_now[k]
        for e in range(net.indptr[i], net.indptr[i + 1]):
            t = net.throat[e]
            if drained[net.neighbour[e]]:
                set_remove(t, front.throats, front.throat_slot, counters, Count.N_FRONT)
            else:
                set_add(t, front.throats, front.throat_slot, counters, Count.N_FRONT)
    for s in range(n_window):
        window_slots[window_throats[s]] = -1


__all__ = [
    "coarse_step",
    "far_level",
    "far_update",
    "merge_front",
    "outlet_links",
    "split_front",
    "start_fine",
    "window_ring",
]
