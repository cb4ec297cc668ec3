"""A window of local time steps: the pores the fine integration sweeps, and its ring.

Pure numba helpers on arrays, in scaled units (:mod:`porenet.kinds.viscous.kernels.explicit`), for
the multirate scheme of :mod:`porenet.kinds.viscous.kernels.multirate`. During a macro step the
explicit and RKC integrators (:func:`porenet.kinds.viscous.kernels.explicit.explicit_advance`,
:func:`porenet.kinds.viscous.kernels.rkc.rkc_advance`) sweep only the pores of a box ``W`` of the
square grid around the active menisci. The pores just outside it (the *ring*) are Dirichlet data,
the coarse step's pressures interpolated linearly in time from the start of the macro step, and
every throat between ``W`` and its ring books the volume it carries, which
:func:`porenet.kinds.viscous.kernels.multirate.far_update` compares with the coarse step's
(refluxing). The menisci outside ``W`` are not integrated: their pores' pressures are interpolated
the same way, and a macro step ends (status :data:`CUT`) as soon as one of them reaches its
threshold, or a pore drains near an open edge of ``W``.

The window travels as one :class:`Window` (a named tuple of arrays). The fine integration is
given the window's own frontier (the throats of its menisci) as its front, so that its
per-step loops are over the window's menisci only.

With mode ``Mode.OFF`` every helper is a no-op and the integrators behave as without a window.
In ``Mode.COARSE`` only the shadow sums run:
:func:`porenet.kinds.viscous.kernels.multirate.coarse_step` sweeps the window with everything else
and books what crosses its edge.
"""

from __future__ import annotations

from enum import IntEnum
from typing import NamedTuple

import numpy as np

from porenet.jit.jit import njit
from porenet.kinds.viscous.kernels.menisci import undrained_pore
from porenet.kinds.viscous.kernels.state import Status


class WindowInt(IntEnum):
    """Slots of :attr:`Window.ints`."""

    MODE = 0  #: a :class:`Mode`
    MARGIN = 1  #: pores from an open edge within which a drainage ends the macro step
    N_RING = 2  #: ring throats (the first entries of the ring arrays)
    CUT_REASON = 3  #: after a cut: a :class:`Cut`
    CUT_PORE = 4  #: after a cut: the pore that caused it
    N_OUTLET = 5  #: outlet links of the active box, listed after the ring throats
    N_FAR = 6  #: frontier throats outside the window, :attr:`Window.far` [:N_FAR]


class WindowFloat(IntEnum):
    """Slots of :attr:`Window.floats`."""

    T0 = 0  #: the start of the macro step
    #: the least invading pressure at which a meniscus outside the window may reach its
    #: threshold during the macro step (:func:`far_meniscus`)
    FAR_LEVEL = 1


class Mode(IntEnum):
    """What a window does."""

    OFF = 0  #: no window: the integrators sweep their whole box
    FINE = 1  #: the fine integration: the ring is Dirichlet data, its throats book what they carry
    COARSE = 2  #: the coarse step over everything: the ring throats and outlet links only book


class Ring(IntEnum):
    """Rows of :attr:`Window.ring_value`."""

    P0 = 0  #: the ring pore's pressure at the start of the macro step
    RATE = 1  #: and its rate of change to the coarse step's end
    FLUX = 2  #: the volume carried out of the window by the fine integration so far
    SHADOW = 3  #: three stage buffers of the RKC shadow sum (rows 3, 4, 5)
    COARSE = 6  #: the volume the coarse step carried out over the whole macro step


N_RING_VALUES = 7


class Cut(IntEnum):
    """Why a macro step ended early (``Status.CUT``)."""

    FAR_MENISCUS = 1  #: a meniscus outside the window may start
    NEAR_EDGE = 2  #: a pore drained near an open edge of the window


class Window(NamedTuple):
    """A window of local time steps.

    Attributes
    ----------
    ints : ndarray of int64, shape (len(WindowInt),)
        By :class:`WindowInt`.
    floats : ndarray of float64, shape (len(WindowFloat),)
        By :class:`WindowFloat`.
    box : ndarray of int64, shape (4,)
        Rows ``[box[0], box[1])`` and columns ``[box[2], box[3])`` of the window ``W``.
    ring_index : ndarray of int64, shape (3, K)
        Per ring throat: the pore inside ``W``, the ring pore, the throat (after them, per
        outlet link of the active box: the pore, -1, the pore).
    ring_value : ndarray of float64, shape (N_RING_VALUES, K)
        By :class:`Ring`.
    p0, rate : ndarray of float64, shape (N,)
        Every pore's pressure at the start of the macro step and its rate to the coarse
        step's end (read for the pores outside ``W``).
    far : ndarray of int64, shape (M,)
        The frontier throats whose meniscus enters a pore outside ``W``, watched by
        :func:`far_meniscus`.
    """

    ints: np.ndarray
    floats: np.ndarray
    box: np.ndarray
    ring_index: np.ndarray
    ring_value: np.ndarray
    p0: np.ndarray
    rate: np.ndarray
    far: np.ndarray


def window_arrays(mode: int, entries: int, n_pores: int, n_throats: int) -> Window:
    """A :class:`Window` in ``mode``, with room for ``entries`` ring throats and outlet links,
    and ``p0``, ``rate`` and ``far`` of ``n_pores``, ``n_pores`` and ``n_throats``."""
    ints = np.zeros(len(WindowInt), dtype=np.int64)
    ints[WindowInt.MODE] = mode
    return Window(
        ints=ints,
        floats=np.zeros(len(WindowFloat)),
        box=np.zeros(4, dtype=np.int64),
        ring_index=np.zeros((3, entries), dtype=np.int64),
        ring_value=np.zeros((N_RING_VALUES, entries)),
        p0=np.zeros(n_pores),
        rate=np.zeros(n_pores),
        far=np.zeros(n_throats, dtype=np.int64),
    )


def box_area(box: np.ndarray) -> int:
    """The pores of a box of the grid (rows ``[box[0], box[1])``, columns ``[box[2],
    box[3])``); plain Python, for the classes that plan windows and count sweeps."""
    return int((box[1] - box[0]) * (box[3] - box[2]))


def no_window() -> Window:
    """A window that is off (the integrators then sweep their whole box)."""
    return window_arrays(Mode.OFF, 0, 0, 0)


@njit(helper=True)
def inside(wbox: np.ndarray, n: int, k: int) -> bool:
    """Whether pore ``k`` of the n x n grid lies in the box."""
    i = k // n
    j = k - i * n
    return wbox[0] <= i < wbox[1] and wbox[2] <= j < wbox[3]


@njit(helper=True)
def far_pressure(window: Window, k: int, t: float) -> float:
    """Pore ``k``'s pressure at ``t``, extrapolated from the start of the macro step."""
    return window.p0[k] + (t - window.floats[WindowFloat.T0]) * window.rate[k]


@njit(helper=True)
def set_ring(window: Window, p: np.ndarray, t: float) -> None:
    """Write the ring pores' pressures at ``t`` into ``p``."""
    ring_i, ring_f = window.ring_index, window.ring_value
    dt = t - window.floats[WindowFloat.T0]
    for e in range(window.ints[WindowInt.N_RING]):
        p[ring_i[1, e]] = ring_f[Ring.P0, e] + dt * ring_f[Ring.RATE, e]


@njit(helper=True)
def ring_increment(window: Window, d: np.ndarray, dt: float) -> None:
    """Write the ring pores' increments over ``dt`` into ``d`` (a stage's increments)."""
    ring_i, ring_f = window.ring_index, window.ring_value
    for e in range(window.ints[WindowInt.N_RING]):
        d[ring_i[1, e]] = dt * ring_f[Ring.RATE, e]


@njit(helper=True)
def book_explicit(window: Window, p: np.ndarray, g_eff: np.ndarray, dt: float) -> float:
    """Book the volume each ring throat carries out of ``W`` in a forward Euler step of
    ``dt`` from the pressures ``p`` (those of the step's start); return their sum."""
    ring_i, ring_f = window.ring_index, window.ring_value
    total = 0.0
    for e in range(window.ints[WindowInt.N_RING]):
        w, r, t = ring_i[0, e], ring_i[1, e], ring_i[2, e]
        v = dt * g_eff[t] * (p[w] - p[r])
        ring_f[Ring.FLUX, e] += v
        total += v
    return total


@njit(helper=True)
def n_entries(ints: np.ndarray) -> int:
    """Ring entries the shadow sums cover (``ints`` is :attr:`Window.ints`): the ring
    throats, and in COARSE mode the window's outlet links too."""
    coarse = ints[WindowInt.MODE] == Mode.COARSE
    return ints[WindowInt.N_RING] + (ints[WindowInt.N_OUTLET] if coarse else 0)


@njit(helper=True)
def shadow_stage(
    window: Window,
    j: int,
    d_prev: np.ndarray,
    g_eff: np.ndarray,
    g_out: np.ndarray,
    p: np.ndarray,
    mu: float,
    nu: float,
    c_flux: float,
    c_f0: float,
) -> None:
    """Stage ``j`` of the RKC shadow sum: the volume each ring throat has carried into its
    window pore, by the same recursion as the pores' increments, ``S_j = mu S_{j-1} + nu
    S_{j-2} + c_flux g (d_r - d_w) + c_f0 g (p_r - p_w)`` (``d_prev`` the increments of stage
    ``j - 1``, ``p`` the step's start; ``S_0 = 0``, and stage 1 is ``c_f0`` times the start
    flux); an outlet link's ring pore is the outlet, at 0, with ``g = g_out``. Buffers rotate
    like the stages': stage ``j`` is row ``Ring.SHADOW + (j - 1) % 3``."""
    ring_i, ring_f = window.ring_index, window.ring_value
    row = Ring.SHADOW + (j - 1) % 3
    prev = Ring.SHADOW + (j - 2) % 3
    prev2 = Ring.SHADOW + (j - 3) % 3
    for e in range(n_entries(window.ints)):
        w, r, t = ring_i[0, e], ring_i[1, e], ring_i[2, e]
        if r >= 0:
            g = g_eff[t]
            s = c_f0 * g * (p[r] - p[w])
            if j >= 2:
                s += c_flux * g * (d_prev[r] - d_prev[w])
        else:
            g = g_out[w]
            s = -c_f0 * g * p[w]
            if j >= 2:
                s -= c_flux * g * d_prev[w]
        if j >= 2:
            s += mu * ring_f[prev, e]
        if j >= 3:
            s += nu * ring_f[prev2, e]
        ring_f[row, e] = s


@njit(helper=True)
def book_shadow(window: Window, m: int, target: int) -> float:
    """Book an accepted RKC step of ``m`` stages: its shadow sum leaves ``W``, into row
    ``target`` (a :class:`Ring`) of the ring values; return the volume that left."""
    ring_f = window.ring_value
    row = Ring.SHADOW + (m - 1) % 3
    total = 0.0
    for e in range(n_entries(window.ints)):
        ring_f[target, e] -= ring_f[row, e]
        total -= ring_f[row, e]
    return total


@njit(helper=True)
def near_open_edge(window: Window, nbox: np.ndarray, n: int, k: int) -> bool:
    """Whether pore ``k`` lies within the margin of an edge of ``W`` that has a ring (an edge
    that is not also an edge of the active box ``nbox``)."""
    wbox = window.box
    margin = window.ints[WindowInt.MARGIN]
    i = k // n
    j = k - i * n
    return (
        (wbox[0] > nbox[0] and i - wbox[0] < margin)
        or (wbox[1] < nbox[1] and wbox[1] - 1 - i < margin)
        or (wbox[2] > nbox[2] and j - wbox[2] < margin)
        or (wbox[3] < nbox[3] and wbox[3] - 1 - j < margin)
    )


@njit(helper=True)
def far_meniscus(
    window: Window,
    pinv: float,
    margin: float,
    t: float,
    entry: np.ndarray,
    tp: np.ndarray,
    drained: np.ndarray,
) -> int:
    """The pore of a meniscus outside the window whose pressure difference at ``t``, at
    invading pressure ``pinv``, exceeds its entry pressure less ``margin`` (-1 if none). The
    list is scanned only when ``pinv + margin`` reaches ``floats[FAR_LEVEL]``, the least level at
    which one may do so in the macro step."""
    if pinv + margin < window.floats[WindowFloat.FAR_LEVEL]:
        return -1
    for s in range(window.ints[WindowInt.N_FAR]):
        f = window.far[s]
        i = undrained_pore(tp, drained, f)
        if pinv - far_pressure(window, i, t) > entry[f] - margin:
            return i
    return -1


@njit(helper=True)
def cut(window: Window, reason: int, k: int) -> int:
    """Record why the macro step ends (a :class:`Cut`) and return ``Status.CUT``."""
    window.ints[WindowInt.CUT_REASON] = reason
    window.ints[WindowInt.CUT_PORE] = k
    return Status.CUT
