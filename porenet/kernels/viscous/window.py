"""A window of local time steps: the pores the fine integration sweeps, and its ring.

Pure numba helpers on arrays, in scaled units (:mod:`porenet.kernels.viscous.explicit`), for the
multirate scheme of :mod:`porenet.kernels.viscous.multirate`. During a macro step the explicit and
RKC integrators (:func:`porenet.kernels.viscous.explicit.explicit_advance`,
:func:`porenet.kernels.viscous.rkc.rkc_advance`) sweep only the pores of a box ``W`` of the square
grid around the active menisci. The pores just outside it (the *ring*) are Dirichlet data,
the coarse step's pressures interpolated linearly in time from the start of the macro step,
and every throat between ``W`` and its ring books the volume it carries, which
:func:`porenet.kernels.viscous.multirate.far_update` compares with the coarse step's (refluxing).
The menisci outside ``W`` are not integrated: their pores' pressures are interpolated the
same way, and a macro step ends (status :data:`CUT`) as soon as one of them reaches its
threshold, or a pore drains near an open edge of ``W``.

The window travels as one tuple ``win = (wi, wf, wbox, ring_i, ring_f, p0, rate, far)``:

* ``wi`` (int64, :data:`WI`): the mode, the edge margin, the number of ring throats and of
  outlet links and, after a cut, its reason and pore;
* ``wf`` (float64, :data:`WF`): the start time ``t0`` of the macro step;
* ``wbox`` (int64, 4): rows ``[wbox[0], wbox[1])`` and columns ``[wbox[2], wbox[3])`` of ``W``;
* ``ring_i`` (int64, (3, K)): per ring throat, the pore inside ``W``, the ring pore, the throat
  (after them, per outlet link of the active box: the pore, -1, the pore);
* ``ring_f`` (float64, (:data:`N_RING_F`, K)): see :data:`RING_P0`;
* ``p0``, ``rate`` (float64, N): every pore's pressure at ``t0`` and its rate to the coarse
  step's end (read for the pores outside ``W``);
* ``far`` (int64, M): the frontier throats whose meniscus enters a pore outside ``W``
  (``far[:wi[6]]``), watched by :func:`far_meniscus`. The fine integration is given the
  window's own frontier (the throats of its menisci) as its front, so that its per-step
  loops are over the window's menisci only.

With ``wi[0] == OFF`` every helper is a no-op and the integrators behave as without a window.
In ``COARSE`` mode only the shadow sums run: :func:`porenet.kernels.viscous.multirate.coarse_step`
sweeps the window with everything else and books what crosses its edge.
"""

from __future__ import annotations

import numpy as np

from porenet.kernels._jit import njit
from porenet.kernels.viscous.menisci import undrained_pore

#: Slots of ``wi``: the mode (:data:`OFF`, :data:`FINE`, :data:`COARSE`), the edge margin,
#: the ring throats and the window's outlet links (listed after them), and after a cut its
#: reason and pore.
WI = {"mode": 0, "margin": 1, "n_ring": 2, "cut_reason": 3, "cut_pore": 4, "n_outlet": 5,
      "n_far": 6}  # fmt: skip
N_WI = 7
#: Modes: no window; the fine integration (the ring is Dirichlet data, its throats book what
#: they carry); the coarse step over everything (the ring throats and outlet links only book).
OFF, FINE, COARSE = 0, 1, 2
#: Slots of ``wf``: the start of the macro step, and the least invading pressure at which a
#: meniscus outside the window may reach its threshold during it (:func:`far_meniscus`).
WF = {"t0": 0, "far_level": 1}
N_WF = 2
#: Rows of ``ring_f``: the ring pore's pressure at ``t0`` and ``dp/dt``; the volume carried out
#: of the window by the fine integration so far; three stage buffers of the RKC shadow sum;
#: the volume the coarse step carried out over the whole macro step.
RING_P0, RING_RATE, RING_FLUX, RING_SHADOW, RING_COARSE = 0, 1, 2, 3, 6
N_RING_F = 7

#: Status returned by the integrators when a window's macro step must end early.
CUT = 8
#: Reasons of a cut (``wi[3]``).
CUT_FAR_MENISCUS, CUT_NEAR_EDGE = 1, 2


def window_arrays(mode: int, entries: int, n_pores: int, n_throats: int) -> tuple:
    """The tuple ``win`` in ``mode``, with room for ``entries`` ring throats and outlet links,
    and ``p0``, ``rate`` and ``far`` of ``n_pores``, ``n_pores`` and ``n_throats``."""
    wi = np.zeros(N_WI, dtype=np.int64)
    wi[0] = mode
    return (
        wi,
        np.zeros(N_WF),
        np.zeros(4, dtype=np.int64),
        np.zeros((3, entries), dtype=np.int64),
        np.zeros((N_RING_F, entries)),
        np.zeros(n_pores),
        np.zeros(n_pores),
        np.zeros(n_throats, dtype=np.int64),
    )


def box_area(box: np.ndarray) -> int:
    """The pores of a box of the grid (rows ``[box[0], box[1])``, columns ``[box[2],
    box[3])``); plain Python, for the classes that plan windows and count sweeps."""
    return int((box[1] - box[0]) * (box[3] - box[2]))


def no_window() -> tuple:
    """A window that is off (the integrators then sweep their whole box)."""
    return window_arrays(OFF, 0, 0, 0)


@njit(helper=True)
def inside(wbox: np.ndarray, n: int, k: int) -> bool:
    """Whether pore ``k`` of the n x n grid lies in the box."""
    i = k // n
    j = k - i * n
    return wbox[0] <= i < wbox[1] and wbox[2] <= j < wbox[3]


@njit(helper=True)
def far_pressure(win: tuple, k: int, t: float) -> float:
    """Pore ``k``'s pressure at ``t``, extrapolated from the start of the macro step."""
    wf, p0, rate = win[1], win[5], win[6]
    return p0[k] + (t - wf[0]) * rate[k]


@njit(helper=True)
def set_ring(win: tuple, p: np.ndarray, t: float) -> None:
    """Write the ring pores' pressures at ``t`` into ``p``."""
    wi, wf, ring_i, ring_f = win[0], win[1], win[3], win[4]
    dt = t - wf[0]
    for e in range(wi[2]):
        p[ring_i[1, e]] = ring_f[RING_P0, e] + dt * ring_f[RING_RATE, e]


@njit(helper=True)
def ring_increment(win: tuple, d: np.ndarray, dt: float) -> None:
    """Write the ring pores' increments over ``dt`` into ``d`` (a stage's increments)."""
    wi, ring_i, ring_f = win[0], win[3], win[4]
    for e in range(wi[2]):
        d[ring_i[1, e]] = dt * ring_f[RING_RATE, e]


@njit(helper=True)
def book_explicit(win: tuple, p: np.ndarray, g_eff: np.ndarray, dt: float) -> float:
    """Book the volume each ring throat carries out of ``W`` in a forward Euler step of
    ``dt`` from the pressures ``p`` (those of the step's start); return their sum."""
    wi, ring_i, ring_f = win[0], win[3], win[4]
    total = 0.0
    for e in range(wi[2]):
        w, r, t = ring_i[0, e], ring_i[1, e], ring_i[2, e]
        v = dt * g_eff[t] * (p[w] - p[r])
        ring_f[RING_FLUX, e] += v
        total += v
    return total


@njit(helper=True)
def n_entries(wi: np.ndarray) -> int:
    """Ring entries the shadow sums cover: the ring throats, and in COARSE mode the window's
    outlet links too."""
    return wi[2] + (wi[5] if wi[0] == COARSE else 0)


@njit(helper=True)
def shadow_stage(
    win: tuple,
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
    like the stages': stage ``j`` is row ``RING_SHADOW + (j - 1) % 3``."""
    wi, ring_i, ring_f = win[0], win[3], win[4]
    row = RING_SHADOW + (j - 1) % 3
    prev = RING_SHADOW + (j - 2) % 3
    prev2 = RING_SHADOW + (j - 3) % 3
    for e in range(n_entries(wi)):
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
def book_shadow(win: tuple, m: int, target: int) -> float:
    """Book an accepted RKC step of ``m`` stages: its shadow sum leaves ``W``, into row
    ``target`` of ``ring_f``; return the volume that left."""
    wi, ring_f = win[0], win[4]
    row = RING_SHADOW + (m - 1) % 3
    total = 0.0
    for e in range(n_entries(wi)):
        ring_f[target, e] -= ring_f[row, e]
        total -= ring_f[row, e]
    return total


@njit(helper=True)
def near_open_edge(win: tuple, nbox: np.ndarray, n: int, k: int) -> bool:
    """Whether pore ``k`` lies within the margin of an edge of ``W`` that has a ring (an edge
    that is not also an edge of the active box ``nbox``)."""
    wi, wbox = win[0], win[2]
    margin = wi[1]
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
    win: tuple,
    pinv: float,
    margin: float,
    t: float,
    pe: np.ndarray,
    tp: np.ndarray,
    drained: np.ndarray,
) -> int:
    """The pore of a meniscus outside the window whose pressure difference at ``t``, at
    invading pressure ``pinv``, exceeds its entry pressure less ``margin`` (-1 if none). The
    list is scanned only when ``pinv + margin`` reaches ``wf[1]``, the least level at which
    one may do so in the macro step."""
    wi, wf, far = win[0], win[1], win[7]
    if pinv + margin < wf[1]:
        return -1
    for s in range(wi[6]):
        f = far[s]
        i = undrained_pore(tp, drained, f)
        if pinv - far_pressure(win, i, t) > pe[f] - margin:
            return i
    return -1


@njit(helper=True)
def cut(win: tuple, reason: int, k: int) -> int:
    """Record why the macro step ends and return :data:`CUT`."""
    wi = win[0]
    wi[3] = reason
    wi[4] = k
    return CUT
