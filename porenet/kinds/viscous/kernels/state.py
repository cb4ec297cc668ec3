"""The named state of the viscous model's kernels: what each array means, in one place.

The kernels (:mod:`porenet.kinds.viscous.kernels.explicit`,
:mod:`~porenet.kinds.viscous.kernels.rkc`,
:mod:`porenet.kinds.viscous.implicit_steps` and their helpers) are pure functions; the state they
read and write travels in a few named tuples of arrays, which numba compiles to the same code
as the arrays passed one by one (an attribute of a named tuple is a constant index):

* :class:`Network`: the pores and throats, fixed during a run;
* :class:`Conductances`: what a throat conducts; changed when a pore drains and when a
  deformable solid moves;
* :class:`Flow`: the integrated state (pressures, drained pores, menisci) and its running
  totals (:class:`Total`) and counters (:class:`Count`);
* :class:`Front`: the frontier throats and the active pores (indexed sets) and the active box;
* :class:`Records`: one row per drainage event (:class:`Column`);
* :class:`Scratch`: work arrays the integrators keep clean between calls;
* :class:`Injection`, :class:`StepRules` and :class:`Stops`: the parameters of a call;

and, inside a step, :class:`Menisci` and :class:`Pump` (the candidate menisci and the
injection, :mod:`porenet.kinds.viscous.kernels.menisci`), :class:`Sweep` (what a stencil sweep over
the active pores reads) and :class:`Window` (local time steps,
:mod:`porenet.kinds.viscous.kernels.window`).

Slots of the counter and total arrays, columns of the records and status codes are
:class:`enum.IntEnum` members, which numba compiles as constants and Python prints by name.

Scaled units throughout (docs/model.md section 4): lengths by ``a``, pressures by
``gamma / a``, times by ``mu a / gamma``, volumes by ``a**3``.

Length (over the ~500 lines of docs/architecture.md's rule): by design: every named structure of
the viscous kernels and what each array means, in one place (see above); splitting it would send
a reader to several files to learn one state.
"""

from __future__ import annotations

from enum import IntEnum
from typing import NamedTuple

import numpy as np

from porenet.jit.jit import njit


class Total(IntEnum):
    """Slots of :attr:`Flow.totals`, the running totals (float64, scaled units). They close
    the volume balances to round-off (``injected = drained + stored_reservoir`` and
    ``drained = stored_defender + outflow + released``)."""

    TIME = 0
    INVADING_PRESSURE = 1
    INJECTED = 2  #: volume delivered by the pump
    DRAINED = 3  #: defender volume displaced by advancing menisci (the invader's volume)
    STORED_DEFENDER = 4  #: sum of V_i p_i over undrained pores (compressibility storage)
    OUTFLOW = 5  #: defender volume through the outlet
    RELEASED = 6  #: storage V_i p_i discarded when pore i drains
    DRAINED_PORE_VOLUME = 7  #: sum of V_i over drained pores
    STORED_RESERVOIR = 8  #: integral of C dp_inv
    #: carried from one call to the next, so that a run does not depend on where calls end:
    DT_NEXT = 9  #: the step the accuracy limit predicts (inf before the first step)
    LAST_RATE = 10  #: largest |dp/dt| of the last step (pressure control; inf at first)
    #: local time steps: volume carried out of the window in the current macro step, which
    #: the far field receives (as stored volume or outflow) at its end
    IN_TRANSIT = 11


class Count(IntEnum):
    """Slots of :attr:`Flow.counters` (int64)."""

    EVENTS = 0  #: pores drained so far (inlets included): the next row of the records
    STEPS = 1  #: time steps taken
    N_FRONT = 2  #: size of the frontier set, :attr:`Front.throats` [:N_FRONT]
    N_ACTIVE = 3  #: size of the active set, :attr:`Front.pores` [:N_ACTIVE]
    WHERE = 4  #: after a failure: the throat or pore where it happened (-1: none named)
    BREAKTHROUGH = 5  #: 1 once an outlet pore has drained


class Column(IntEnum):
    """Columns of :attr:`Records.series`, one row per drainage event (scaled units)."""

    TIME = 0
    INVADING_PRESSURE = 1
    INJECTED = 2
    DRAINED = 3
    STORED = 4  #: defender storage + reservoir storage + volume in transit
    OUTFLOW = 5
    RELEASED = 6
    N_DRAINED = 7


class Status(IntEnum):
    """What ended a call of an integrator."""

    BUDGET = 0  #: the event or step budget of the call is used up
    BREAKTHROUGH = 1
    END_TIME = 2
    STEP_LIMIT = 3  #: ``fluid.max_steps`` reached
    NON_FINITE = 4  #: a non-finite pressure or volume
    NO_MENISCUS = 5  #: nothing left to invade
    STATIONARY = 6  #: pressure control: nothing changes any more
    NOT_SETTLED = 7  #: implicit integrator: meniscus states did not settle
    CUT = 8  #: local time steps: the window's macro step must end early

    def describe(self) -> str:
        """A few words for error messages."""
        return _STATUS_TEXT[self]


_STATUS_TEXT = {
    Status.BUDGET: "event budget reached",
    Status.BREAKTHROUGH: "breakthrough",
    Status.END_TIME: "end time reached",
    Status.STEP_LIMIT: "step limit reached",
    Status.NON_FINITE: "non-finite value",
    Status.NO_MENISCUS: "no meniscus left",
    Status.STATIONARY: "stationary",
    Status.NOT_SETTLED: "meniscus states did not settle",
    Status.CUT: "window cut",
}


#: Capability switches of the kernels (:func:`porenet.jit.jit.variant`): code for
#: lattices swept as lists of active pores (every lattice but the square grid) sits under
#: ``if LISTS and grid_n == 0``, and code for the fine integration of a macro step of local
#: time steps under ``windowed = WINDOWS and ...``. Both True here: the kernels as imported
#: can do everything; a run that cannot need one calls a variant with it off, which a first
#: run compiles without that code.
LISTS = True
WINDOWS = True


class Control(IntEnum):
    """How the injection is driven (``fluid.control``)."""

    RATE = 0  #: a fixed rate Q into a reservoir of compliance C
    PRESSURE = 1  #: the invading pressure held
    RAMP = 2  #: the invading pressure raised at a fixed rate


# -- the structures ---------------------------------------------------------------------------


class Network(NamedTuple):
    """The pores and throats as the kernels read them; fixed during a run.

    Attributes
    ----------
    indptr, neighbour, throat : ndarray of int64, shapes (N + 1,), (2M,), (2M,)
        CSR adjacency: pore ``i``'s neighbours are ``neighbour[indptr[i]:indptr[i + 1]]``,
        joined by the throats ``throat[...]``.
    throat_pores : ndarray of int64, shape (M, 2)
    volume, inverse_volume : ndarray of float64, shape (N,)
        Pore volumes ``V`` and ``1 / V`` (the sweeps multiply: a division per pore would
        dominate them).
    outlet : ndarray of bool, shape (N,)
        Pores whose drainage is breakthrough.
    grid_n : int
        ``n`` for an ``n x n`` square grid in canonical throat order (horizontal throats
        row-major, then vertical), swept as a stencil over a box of active pores; 0 for any
        other lattice, whose active pores are listed.
    """

    indptr: np.ndarray
    neighbour: np.ndarray
    throat: np.ndarray
    throat_pores: np.ndarray
    volume: np.ndarray
    inverse_volume: np.ndarray
    outlet: np.ndarray
    grid_n: int


class Conductances(NamedTuple):
    """What each throat conducts (float64).

    Attributes
    ----------
    between : ndarray, shape (M,)
        ``A k / 2``, the conductance between two undrained pores; 0 once either drains.
    meniscus : ndarray, shape (M,)
        ``A k``: a meniscus of length ``l`` in the throat conducts ``A k / l``.
    area : ndarray, shape (M,)
        Throat cross-section ``A``.
    entry_pressure : ndarray, shape (M,)
        Capillary entry pressure ``2 / r``.
    outlet : ndarray, shape (N,)
        Conductance of each pore to the outlet reservoir (0 for inner pores and once the
        pore drains).
    """

    between: np.ndarray
    meniscus: np.ndarray
    area: np.ndarray
    entry_pressure: np.ndarray
    outlet: np.ndarray


class Flow(NamedTuple):
    """The state the integrators advance.

    Attributes
    ----------
    pressure : ndarray of float64, shape (N,)
        Defender pressure of undrained pores; the invader's, as of their drainage, in drained
        ones.
    drained : ndarray of bool, shape (N,)
    meniscus_length : ndarray of float64, shape (M,)
        Remaining length of each frontier throat's meniscus (2 when it appears, 0 when its
        pore drains).
    latched : ndarray of bool, shape (M,)
        Meniscus rule "latching": whether the throat's meniscus has ever passed its entry
        pressure.
    totals : ndarray of float64, shape (len(Total),)
        Running totals, by :class:`Total`.
    counters : ndarray of int64, shape (len(Count),)
        Counters, by :class:`Count`.
    """

    pressure: np.ndarray
    drained: np.ndarray
    meniscus_length: np.ndarray
    latched: np.ndarray
    totals: np.ndarray
    counters: np.ndarray


class Front(NamedTuple):
    """The frontier throats and the active pores, as indexed sets, and the active box.

    Attributes
    ----------
    throats, throat_slot : ndarray of int64, shape (M,)
        Frontier throats (between a drained and an undrained pore) ``throats[:counters[
        N_FRONT]]`` and each throat's place in it (-1 if not there).
    pores, pore_slot : ndarray of int64, shape (N,)
        Active pores (lists only on lattices other than grids) ``pores[:counters[N_ACTIVE]]``
        and each pore's place (-1).
    box : ndarray of int64, shape (4,)
        Grids: the active pores are rows ``[box[0], box[1])`` and columns ``[box[2],
        box[3])``; it grows as the pressure spreads.
    settled : ndarray of bool, shape (N,)
        Lists: active pores whose neighbours are all active or drained, which the pressure's
        spread (:func:`porenet.kinds.viscous.kernels.diffusion.spread`) no longer looks at.
    """

    throats: np.ndarray
    throat_slot: np.ndarray
    pores: np.ndarray
    pore_slot: np.ndarray
    box: np.ndarray
    settled: np.ndarray


class Records(NamedTuple):
    """One row per drainage event (row ``counters[EVENTS]`` is the next).

    Attributes
    ----------
    order : ndarray of int64, shape (N,)
        The pores in order of drainage.
    via : ndarray of int64, shape (N,)
        The throat each was entered through (-1 for an inlet).
    series : ndarray of float64, shape (N, len(Column))
        The totals at each event, by :class:`Column`.
    """

    order: np.ndarray
    via: np.ndarray
    series: np.ndarray


class Scratch(NamedTuple):
    """Work arrays kept by the caller (so that a call allocates nothing of size N or M that
    must be filled); ``head`` is -1, ``candidate`` False and ``implicit_flux`` 0 everywhere
    between calls.

    Attributes
    ----------
    flux, next_pressure : ndarray of float64, shape (N,)
        Explicit fluxes into the pores; their pressures at the end of a step.
    meniscus_throat, meniscus_pore : ndarray of int64, shape (M,)
        A step's candidate menisci: their throats and the pores they enter.
    meniscus_flux : ndarray of float64, shape (M,)
        The candidates' fluxes over the step.
    threshold, next_candidate : ndarray, shape (M,), float64 and int64
        The candidates' thresholds and their links (:class:`Menisci`).
    near : ndarray of int64, shape (M,)
        Frontier slots of menisci below their threshold but within reach of it in the step.
    head : ndarray of int64, shape (N,)
        Per pore, its first candidate meniscus (-1: none); the rest are linked by
        :attr:`Menisci.next`.
    candidate : ndarray of bool, shape (M,)
        RKC: whether a frontier throat is a candidate of the step.
    implicit_flux : ndarray of float64, shape (N,)
        RKC: ``V (F_I(y_n) + F_I(y_n+1))`` at the menisci's pores, for the error estimate.
    """

    flux: np.ndarray
    next_pressure: np.ndarray
    meniscus_throat: np.ndarray
    meniscus_pore: np.ndarray
    meniscus_flux: np.ndarray
    threshold: np.ndarray
    next_candidate: np.ndarray
    near: np.ndarray
    head: np.ndarray
    candidate: np.ndarray
    implicit_flux: np.ndarray


class Injection(NamedTuple):
    """How the invader is injected (scaled).

    Attributes
    ----------
    control : int
        A :class:`Control`.
    rate : float
        ``Q`` (rate control).
    capacity, capacity_per_drained : float
        The reservoir's compliance is ``C = capacity + capacity_per_drained * V_drained``.
    ramp_rate : float
        ``dp_inv / dt`` of a ramp.
    """

    control: int
    rate: float
    capacity: float
    capacity_per_drained: float
    ramp_rate: float


class StepRules(NamedTuple):
    """How steps are taken.

    Attributes
    ----------
    dt_max : float
        The explicit step (stability limit times the safety factor).
    latching : bool
        Meniscus rule "latching" (True) or "threshold" (False).
    floor : float
        Pressure magnitude above which a pore activates its neighbours.
    pressure_step : float
        Accuracy limit of the explicit integrator: the largest change of the invading
        pressure or of a pressure difference across a candidate meniscus per step (inf: none).
    new_meniscus : float
        Length of a new meniscus (2: the distance between two pore centres).
    """

    dt_max: float
    latching: bool
    floor: float
    pressure_step: float
    new_meniscus: float


class Stops(NamedTuple):
    """When a call returns.

    Attributes
    ----------
    max_events : int
        Pores to drain in this call at most.
    t_end : float
        Model time to stop at.
    max_steps : int
        Time steps of the whole run at most (``fluid.max_steps``).
    at_breakthrough : bool
        Stop when an outlet pore drains.
    step_budget : int
        Steps of this call at most, so that the caller regains control (progress, observers)
        during long stretches without drainage.
    """

    max_events: int
    t_end: float
    max_steps: int
    at_breakthrough: bool
    step_budget: int


class Menisci(NamedTuple):
    """A step's candidate menisci (:mod:`porenet.kinds.viscous.kernels.menisci`) and what they read.

    Attributes
    ----------
    throat, pore : ndarray of int64
        Candidate ``s`` is the meniscus in throat ``throat[s]`` entering pore ``pore[s]``.
    threshold : ndarray of float64
        Its threshold: the entry pressure (rule "threshold") or 0 (a latched meniscus).
    head, next : ndarray of int64
        Per pore, its first candidate; then each candidate's next one in the same pore (-1).
    pressure, flux : ndarray of float64, shape (N,)
        The pores' pressures at the step's start and their explicit fluxes.
    volume : ndarray of float64, shape (N,)
    conductance : ndarray of float64, shape (M,)
        ``A k`` (:attr:`Conductances.meniscus`).
    length, area : ndarray of float64, shape (M,)
        Meniscus lengths and throat areas.
    """

    throat: np.ndarray
    pore: np.ndarray
    threshold: np.ndarray
    head: np.ndarray
    next: np.ndarray
    pressure: np.ndarray
    flux: np.ndarray
    volume: np.ndarray
    conductance: np.ndarray
    length: np.ndarray
    area: np.ndarray


class Pump(NamedTuple):
    """The injection over one step.

    Attributes
    ----------
    control : int
        A :class:`Control`.
    pressure : float
        The invading pressure at the step's start.
    rate : float
        ``Q``.
    capacity : float
        The reservoir's compliance now.
    ramp_rate : float
    """

    control: int
    pressure: float
    rate: float
    capacity: float
    ramp_rate: float


class Sweep(NamedTuple):
    """What a stencil sweep over the active pores reads (:func:`porenet.kinds.viscous.kernels.
    chebyshev.sweep`).

    Attributes
    ----------
    grid_n : int
        As :attr:`Network.grid_n`.
    box : ndarray of int64, shape (4,)
        The pores swept (grids): the active box, or a window of local time steps.
    n_active : int
        Lattices other than grids: the active pores are ``pores[:n_active]``.
    pores, pore_slot : ndarray of int64
        As :attr:`Front.pores` and :attr:`Front.pore_slot`.
    indptr, neighbour, throat : ndarray of int64
        As in :class:`Network`.
    between, outlet : ndarray of float64
        As :attr:`Conductances.between` and :attr:`Conductances.outlet`.
    inverse_volume : ndarray of float64, shape (N,)
        ``1 / V``.
    scratch : ndarray of float64, shape (N,)
        Work array of the list sweep.
    bounds : ndarray of int64, shape (4,)
        The box whose pores count as neighbours: ``box`` itself, or the active box around a
        window (whose ring is read, not written).
    """

    grid_n: int
    box: np.ndarray
    n_active: int
    pores: np.ndarray
    pore_slot: np.ndarray
    indptr: np.ndarray
    neighbour: np.ndarray
    throat: np.ndarray
    between: np.ndarray
    outlet: np.ndarray
    inverse_volume: np.ndarray
    scratch: np.ndarray
    bounds: np.ndarray


@njit(helper=True)
def book_step(
    flow: Flow,
    pump: Pump,
    dt: float,
    drained: float,
    stored: float,
    outflow: float,
    pressure_after: float,
) -> None:
    """Book one accepted step of length ``dt`` in ``flow``'s totals and counters, the same way
    for every integrator: the volume the menisci displaced (``drained``), the change of the
    defender's stored volume (``stored``), the volume out of the outlet (``outflow``), what the
    pump delivered and the reservoir stored (``pump`` holds the injection at the step's start,
    ``pressure_after`` the invading pressure at its end), the invading pressure and the time
    after the step, and one step more. These are the terms of the volume balances of
    :class:`Total` (docs/model.md section 4)."""
    totals = flow.totals
    reservoir = pump.capacity * (pressure_after - pump.pressure)
    totals[Total.DRAINED] += drained
    totals[Total.STORED_DEFENDER] += stored
    totals[Total.OUTFLOW] += outflow
    if pump.control == Control.RATE:
        totals[Total.INJECTED] += pump.rate * dt
    else:
        totals[Total.INJECTED] += drained + reservoir
    totals[Total.STORED_RESERVOIR] += reservoir
    totals[Total.INVADING_PRESSURE] = pressure_after
    totals[Total.TIME] += dt
    flow.counters[Count.STEPS] += 1


def new_flow(n_pores: int, n_throats: int, new_meniscus: float, invading_pressure: float) -> Flow:
    """A :class:`Flow` before the first event: pressures 0, nothing drained, new menisci,
    totals 0 but the predicted step and last rate (inf) and the invading pressure."""
    totals = np.zeros(len(Total))
    totals[Total.DT_NEXT] = totals[Total.LAST_RATE] = np.inf
    totals[Total.INVADING_PRESSURE] = invading_pressure
    return Flow(
        pressure=np.zeros(n_pores),
        drained=np.zeros(n_pores, dtype=bool),
        meniscus_length=np.full(n_throats, new_meniscus),
        latched=np.zeros(n_throats, dtype=bool),
        totals=totals,
        counters=np.zeros(len(Count), dtype=np.int64),
    )


def new_front(n_pores: int, n_throats: int, grid_n: int) -> Front:
    """An empty :class:`Front` (on grids an empty box that grows as pores drain)."""
    box = np.zeros(4, dtype=np.int64)
    box[[0, 2]] = grid_n
    return Front(
        throats=np.zeros(n_throats, dtype=np.int64),
        throat_slot=np.full(n_throats, -1, dtype=np.int64),
        pores=np.zeros(n_pores, dtype=np.int64),
        pore_slot=np.full(n_pores, -1, dtype=np.int64),
        box=box,
        settled=np.zeros(n_pores, dtype=bool),
    )


def new_records(n_pores: int) -> Records:
    """Empty :class:`Records` with room for every pore."""
    return Records(
        order=np.zeros(n_pores, dtype=np.int64),
        via=np.zeros(n_pores, dtype=np.int64),
        series=np.zeros((n_pores, len(Column))),
    )


def new_scratch(n_pores: int, n_throats: int) -> Scratch:
    """A clean :class:`Scratch`."""
    return Scratch(
        flux=np.zeros(n_pores),
        next_pressure=np.zeros(n_pores),
        meniscus_throat=np.zeros(n_throats, dtype=np.int64),
        meniscus_pore=np.zeros(n_throats, dtype=np.int64),
        meniscus_flux=np.zeros(n_throats),
        threshold=np.zeros(n_throats),
        next_candidate=np.zeros(n_throats, dtype=np.int64),
        near=np.zeros(n_throats, dtype=np.int64),
        head=np.full(n_pores, -1, dtype=np.int64),
        candidate=np.zeros(n_throats, dtype=bool),
        implicit_flux=np.zeros(n_pores),
    )
