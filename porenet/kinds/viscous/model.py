"""The paper's dynamic drainage model (docs/model.md section 4) as a FluidModel, kind
``viscous``.

Length (over the ~500 lines of docs/architecture.md's rule): one class, the viscous model's side
of the FluidModel contract (setup, advance, apertures_changed, finalize, outputs). Its methods
share one object's state (the network, the flow, the conductances, the integrator in use);
splitting them across modules would have them read each other's attributes again, which the
named interfaces with LocalSteps removed. The numerics are in porenet/kinds/viscous/kernels/, the
implicit stepper in implicit_steps.py and the local steps in local_steps.py.
"""

from __future__ import annotations

import math
import time
from typing import Any

import numpy as np

from porenet.core.errors import ConfigError, NumericalError
from porenet.core.interfaces import FluidModel, Lattice
from porenet.core.state import State
from porenet.jit.jit import PARALLEL_MIN, threads, variant
from porenet.jit.threads import CallPace
from porenet.kinds.viscous.config import ViscousConfig, auto_integrator
from porenet.kinds.viscous.kernels.state import (
    Conductances,
    Control,
    Count,
    Injection,
    Menisci,
    Network,
    Pump,
    Status,
    StepRules,
    Stops,
    Total,
    new_flow,
    new_front,
    new_records,
    new_scratch,
)
from porenet.kinds.viscous.kernels.window import Window, box_area, no_window

#: Length of a new meniscus: the distance between two pore centres, 2a.
MENISCUS_LENGTH = 2.0


def throat_stretch(lattice: Lattice) -> np.ndarray | None:
    """``l / MENISCUS_LENGTH`` per throat, or None when every throat has the square lattice's
    length ``2a``.

    The kernels move every meniscus over the same reference length ``MENISCUS_LENGTH`` (2a).
    A throat of length ``l`` is mapped onto it exactly: its area is multiplied by
    ``l / 2a`` (so that it holds its volume ``A l``) and its conductance times length by
    ``2a / l`` (so that it conducts ``A k / l``); the meniscus position the kernels report is
    then ``2a`` times the fraction of the throat still ahead (docs/lattices.md, "Throat
    lengths"). A lattice of ``2a`` throats skips the scaling (which would change no bit)."""
    lengths = np.asarray(lattice.throat_lengths, dtype=np.float64)
    if np.all(lengths == MENISCUS_LENGTH):
        return None
    return lengths / MENISCUS_LENGTH


#: Drainage events between the points where a macro step of local time steps ends (counted
#: from the first event after the inlets, so the same in every run of a scene: where the
#: calls end does not matter). The other integrators give the same results for any value.
_CHUNK = 256
#: Most time steps per call into the kernel. Within it a call aims at the Simulation's
#: ``call_seconds`` (:class:`porenet.jit.threads.CallPace`): the Simulation regains control
#: that often to run observers (progress, snapshots), check the stops and choose the
#: threads. Where a call ends changes no result (``tests/verification/test_chunking.py``).
_STEP_CHUNK = 20_000

#: The step-controlled integrators' counters in ``/summary``: attribute -> slot of the
#: integrator's memory (:class:`porenet.kinds.viscous.kernels.rkc.Slot`,
#: :class:`porenet.kinds.viscous.implicit_steps.Slot`).
_SUMMARY_COUNTERS = {
    "implicit": {
        "linear_solves": "SOLVES",
        "factorizations": "FACTORIZATIONS",
        "rejected_steps": "REJECTED",
    },
    "rkc": {
        "stage_sweeps": "STAGES",
        "rkc_steps": "RKC_STEPS",
        "rejected_steps": "REJECTED",
        "rejected_for_events": "REJECTED_EVENTS",
        "rejected_stage_sweeps": "REJECTED_STAGES",
        "explicit_steps": "EXPLICIT_STEPS",
    },
}


class ViscousDrainage(FluidModel):
    """The dynamic model: pore pressures, Darcy fluxes, advancing menisci, injection reservoir.

    Reads ``state.apertures`` at :meth:`setup`. Writes ``drained``, ``trapped``, ``pressure``
    (defender pressure; invader pressure in drained pores), ``invading_pressure``, ``time``,
    ``step``, ``n_drained``, ``breakthrough``, ``meniscus_length`` and ``record`` (drainage
    times, and the invading pressure at each drainage). Scaled units throughout.

    The kernels' state is held in the named structures of
    :mod:`porenet.kinds.viscous.kernels.state`, public attributes from :meth:`setup` on:
    :attr:`network`, :attr:`conductances`, :attr:`flow`, :attr:`front`, :attr:`records`,
    :attr:`scratch`, :attr:`injection` and :attr:`rules` (and :attr:`rkc` for the RKC
    integrator). Local time steps (:class:`porenet.kinds.viscous.local_steps.LocalSteps`)
    use only these and the methods under "for local time steps" below.
    """

    solves_pressure = True
    config: ViscousConfig

    # -- setup --------------------------------------------------------------------------
    def setup(self, state: State) -> None:
        from porenet.kinds.viscous.kernels.explicit import drain_inlets

        lat, cfg, sc = self.lattice, self.config, self.context.scales
        at = self.context.injection.at
        self._conductances(state)
        self._injection()
        self._integrator = self._choose_integrator()
        self._allocate(state)
        inlets = np.asarray(lat.inlet_pores(at), dtype=np.int64)
        drain_inlets(inlets, self.network, self.conductances, self.flow, self.front,
                     self.records, MENISCUS_LENGTH)  # fmt: skip
        counters = self.flow.counters
        if self.network.outlet[state.drained].any():  # an inlet on the outlet: breakthrough
            counters[Count.BREAKTHROUGH] = 1
        self._events0 = int(counters[Count.EVENTS])
        self._pace = CallPace(most=_STEP_CHUNK)
        self._parallel_work = 0.0
        self._status = -1
        self._synced = 0
        self._t_end = math.inf if cfg.max_time is None else cfg.max_time / sc.time
        self._sync(state)
        if self.integrator == "explicit":
            self._check_step_count(state)

    @property
    def integrator(self) -> str:
        """The time integrator of this run: the config's choice, with 'auto' resolved at
        setup by :meth:`_choose_integrator` (still 'auto' before setup)."""
        return getattr(self, "_integrator", self.config.integrator)

    def _choose_integrator(self) -> str:
        """Resolve ``integrator = 'auto'`` (the one place that decides).

        From the explicit integrator's steps per drained pore, estimated as ``E = 2.8 V /
        (Q dt)`` (a drained pore takes ~2.8 mean pore volumes of injected fluid, counting what
        the defender stores): explicit while ``E <= 50``, RKC beyond, implicit beyond ``50 N``
        (N pores); explicit always under pressure or ramp control. An RKC step of length h
        costs ~sqrt(1.54 h rho) sweeps, so RKC pays once E is a few tens (measured crossover
        near E = 40 at n = 100); the implicit integrator's cost per drained pore does not
        depend on Ca but each of its ~20 factorisations per pore costs ~N^1.5 on a grid,
        against RKC's ~N sqrt(E) sweeps, so it wins only where E exceeds a multiple of N
        (measured: at n = 50 and Ca = 1e-6, E ~ 7e4 = 29 N, RKC is still 1.5x faster).
        ``python tests/benchmarks/bench_implicit.py`` measures all three (docs/performance.md)."""
        choice = self.config.integrator
        if choice != "auto":
            return choice
        if self.config.control != "rate" or self.injection_rate <= 0:
            return "explicit"
        explicit_steps = (
            2.8 * float(np.mean(self.network.volume)) / (self.injection_rate * self._dt)
        )
        return auto_integrator(explicit_steps, self.lattice.n_pores)

    def _conductances(self, state: State) -> None:
        """The network and the throats' conductances from the apertures, the stable step and
        the accuracy limit (scaled units)."""
        lat, cfg = self.lattice, self.config
        at = self.context.injection.at
        indptr, nbr, thr = lat.adjacency
        vol = np.ascontiguousarray(lat.pore_volumes, dtype=np.float64)
        tp = np.ascontiguousarray(lat.throat_pores, dtype=np.int64)
        #: Canonical square grids are swept as a stencil over a growing box of active pores.
        grid_n = int(lat.grid_shape[0]) if lat.canonical_grid else 0
        self.network = Network(
            indptr=np.asarray(indptr, np.int64),
            neighbour=np.asarray(nbr, np.int64),
            throat=np.asarray(thr, np.int64),
            throat_pores=tp,
            volume=vol,
            inverse_volume=1.0 / vol,
            outlet=np.ascontiguousarray(lat.outlet_mask(at), dtype=bool),
            grid_n=grid_n,
        )
        c_area, c_perm = lat.throat_factors
        stretch = throat_stretch(lat)
        if self.context.deformable and (np.ndim(c_area) or np.ndim(c_perm) or stretch is not None):
            raise ConfigError(
                f"the {type(lat).__name__} lattice's throats differ in shape or length: a "
                "deformable solid needs the square lattice's uniform throats (docs/lattices.md)"
            )
        r = np.asarray(state.apertures, dtype=np.float64)
        area = c_area * r**2
        g_num = area * c_perm * r**2  # A k: meniscus conductance times length
        if stretch is not None:  # throats of length l != 2a, on the kernels' reference length
            area = area * stretch
            g_num = g_num / stretch
        links = lat.outlet_links(at)
        outlet_factor = float(np.mean(c_area)) * float(np.mean(c_perm))
        self.conductances = Conductances(
            between=g_num / MENISCUS_LENGTH,  # zeroed for throats touching drained pores
            meniscus=g_num,
            area=area,
            entry_pressure=np.asarray(lat.entry_pressures(r), dtype=np.float64),
            outlet=links * outlet_factor * lat.mean_aperture**4,  # half throats, length a
        )
        cond = self.conductances
        #: Boundary cross-section A_b / a^2 (4 L a for centre injection).
        self.cross_section = float(links.sum())
        degree_sum = np.zeros(lat.n_pores)
        np.add.at(degree_sum, tp[:, 0], cond.between)
        np.add.at(degree_sum, tp[:, 1], cond.between)
        self.dt_stable = float(np.min(vol / (degree_sum + cond.outlet)))
        self._dt = cfg.safety_factor * self.dt_stable
        entry = cond.entry_pressure
        spread = float(np.max(entry) - np.min(entry))
        #: Unit of the accuracy limits, gamma/a: the entry-pressure spread (a floor of 1 % of
        #: the mean entry pressure keeps it finite for nearly uniform apertures).
        self.pressure_scale = max(spread, 0.01 * float(np.mean(entry)))
        self._pressure_step = (
            math.inf if cfg.pressure_step is None else cfg.pressure_step * self.pressure_scale
        )

    def _injection(self) -> None:
        """Control, rate (a^2 gamma / mu), reservoir compliance and ramp (scaled)."""
        cfg, sc = self.config, self.context.scales
        if sc.time is None:  # pragma: no cover - the config always has a viscosity
            raise ValueError("the viscous model needs a viscosity")
        control = {"rate": Control.RATE, "pressure": Control.PRESSURE,
                   "ramp": Control.RAMP}[cfg.control]  # fmt: skip
        if cfg.capillary_number is not None:
            rate = cfg.capillary_number * self.cross_section
        elif cfg.injection_rate is not None:
            rate = cfg.injection_rate * cfg.viscosity / (sc.length**2 * cfg.interfacial_tension)
        else:
            rate = 0.0
        self.injection = Injection(
            control=int(control),
            rate=rate,
            capacity=float(np.mean(self.network.volume)) if cfg.reservoir == "pore" else 0.0,
            capacity_per_drained=1.0 if cfg.reservoir == "drained" else 0.0,
            ramp_rate=0.0 if cfg.ramp_rate is None else cfg.ramp_rate * sc.time / sc.pressure,
        )

    @property
    def injection_rate(self) -> float:
        """The injection rate ``Q`` (scaled; 0 unless rate-controlled)."""
        return self.injection.rate

    def _step_rules(self) -> StepRules:
        """The rules of the explicit steps (the step changes when a deformed solid narrows
        the stable step: :meth:`apertures_changed`)."""
        cfg = self.config
        return StepRules(self._dt, cfg.meniscus == "latching", cfg.pressure_floor,
                         self._pressure_step, MENISCUS_LENGTH)  # fmt: skip

    def _allocate(self, state: State) -> None:
        """The model's state, scratch and record arrays; the State shares the pressures, the
        drained mask and the meniscus lengths."""
        n, m = self.lattice.n_pores, self.lattice.n_throats
        invading = self.config.injection_pressure / self.context.scales.pressure
        # the kernels drain the State's own mask
        self.flow = new_flow(n, m, MENISCUS_LENGTH, invading)._replace(drained=state.drained)
        state.pressure = self.flow.pressure
        state.meniscus_length = self.flow.meniscus_length
        self.front = new_front(n, m, self.network.grid_n)
        self.records = new_records(n)
        self.scratch = new_scratch(n, m)
        self.rules = self._step_rules()
        self.window_off: Window = no_window()
        self._local: Any = None  # LocalSteps, built at the first RKC call where they apply
        self.rkc: Any = None
        if self.integrator == "rkc":
            from porenet.kinds.viscous.kernels.chebyshev import spectral_radius
            from porenet.kinds.viscous.kernels.rkc import Rkc, Slot

            cond = self.conductances
            self.rkc = Rkc(
                stages=np.zeros((3, n)),
                f0=np.zeros(n),
                fnew=np.zeros(n),
                zero=np.zeros(n),
                memory=np.zeros(len(Slot)),
                # of the pore-to-pore operator (scaled), which sets the stages
                spectral_radius=spectral_radius(
                    self.network.throat_pores, cond.between, cond.outlet, self.network.volume
                ),
                dt_stable=self.dt_stable,
                pressure_scale=self.pressure_scale,
                tolerance=self.config.tolerance,
            )
        self.implicit: Any = None
        if self.integrator == "implicit":
            from porenet.kinds.viscous.implicit_steps import ImplicitSolver, Slot

            cfg = self.config
            self.implicit = ImplicitSolver(
                states=np.zeros(m, dtype=np.int8),
                fluxes=np.zeros(m),
                memory=np.zeros(len(Slot)),
                cache={},
                latching=cfg.meniscus == "latching",
                new_meniscus=MENISCUS_LENGTH,
                dt_min=self.dt_stable,
                pressure_scale=self.pressure_scale,
                tolerance=cfg.tolerance,
                event_tolerance=cfg.event_tolerance,
                floor=cfg.pressure_floor,
            )

    @property
    def spectral_radius(self) -> float:
        """The spectral radius of the pore-to-pore operator (RKC integrator; scaled)."""
        return float(self.rkc.spectral_radius)

    def _check_step_count(self, state: State) -> None:
        """Fail at once, saying why, when the run cannot reach breakthrough within max_steps.

        Under rate control breakthrough needs at least the volume of the shortest path of
        pores from the inlet to the outlet (each pore costs a meniscus sweep of at least
        ``2 A_min``), delivered at rate Q: a lower bound on the time, hence on the steps.
        """
        from scipy.sparse import csr_matrix
        from scipy.sparse.csgraph import shortest_path

        cfg, stop, net = self.config, self.context.stop, self.network
        if cfg.control != "rate" or stop.at != "breakthrough" or cfg.max_time is not None:
            return
        n = len(net.indptr) - 1
        graph = csr_matrix((np.ones(len(net.neighbour)), net.neighbour, net.indptr), shape=(n, n))
        sources = np.flatnonzero(state.drained)
        dist = shortest_path(graph, unweighted=True, indices=sources, directed=False)
        hops = float(np.min(np.atleast_2d(dist)[:, net.outlet]))
        if not np.isfinite(hops):
            return
        volume = hops * MENISCUS_LENGTH * float(np.min(self.conductances.area))
        steps = volume / self.injection_rate / self._dt
        if steps > cfg.max_steps:
            sc = self.context.scales
            raise NumericalError(
                f"viscous model: Ca = {self.injection_rate / self.cross_section:.3g} needs at "
                f"least {steps:.3g} explicit time steps to reach breakthrough (time step "
                f"{self._dt * (sc.time or 0):.3g} s), more than fluid.max_steps = "
                f"{cfg.max_steps}; at such capillary numbers invasion percolation gives the "
                f"same pattern (see docs/accuracy.md), or raise max_steps"
            )

    # -- loop -----------------------------------------------------------------------------
    def _stops(self, budget: int, t_end: float, step_budget: int | None = None) -> Stops:
        """The stops of one kernel call."""
        return Stops(
            max_events=budget,
            t_end=t_end,
            max_steps=self.config.max_steps,
            at_breakthrough=self.context.stop.at == "breakthrough",
            step_budget=self._step_chunk() if step_budget is None else step_budget,
        )

    def advance(self, state: State, max_events: int) -> int:
        from porenet.kinds.viscous.kernels.explicit import explicit_advance

        cfg, stop, counters = self.config, self.context.stop, self.flow.counters
        before = int(counters[Count.EVENTS])
        budget = max(int(max_events), 0)
        budget = min(budget, _CHUNK - (before - self._events0) % _CHUNK)
        if stop.at == "complete":
            # "complete" is reached at the event that drains the last undrained outlet pore
            # (_all_trapped): a call may end there, never past it, so the run stops at that
            # event wherever its calls end (it was checked only where calls ended, which
            # depends on the machine's speed)
            budget = min(budget, max(self._undrained_outlets(state), 1))
        t_end = self._t_end  # fluid.max_time, or an observer's time (stop_time) before it
        if self.stop_time is not None:
            t_end = min(t_end, self.stop_time)
        status = Status.BUDGET
        steps0, sweeps0 = int(counters[Count.STEPS]), self._sweeps()
        wall0 = time.perf_counter()
        if budget > 0 and self.integrator == "implicit":
            status = self._implicit_advance(state, budget, t_end)
        elif budget > 0 and self.integrator == "rkc":
            status = self._rkc_advance(state, budget, t_end)
        elif budget > 0:
            status = self.sized(explicit_advance)(
                self.network, self.conductances, self.flow, self.front, self.records,
                self.scratch, self.injection, self.rules, self._stops(budget, t_end),
                self.window_off,
            )  # fmt: skip
        self._pace.record(int(counters[Count.STEPS]) - steps0, time.perf_counter() - wall0,
                          threads())  # fmt: skip
        if self.network.grid_n > 0 and box_area(self.front.box) >= PARALLEL_MIN:
            self._parallel_work += self._sweeps() - sweeps0
        self._sync(state)
        if status in (Status.STEP_LIMIT, Status.NON_FINITE):
            raise NumericalError(
                f"viscous model: {Status(status).describe()} at t = {state.time:g} (scaled) "
                f"after {int(counters[Count.STEPS])} steps and {state.n_drained} drained pores"
                + (f" (max_steps = {cfg.max_steps})" if status == Status.STEP_LIMIT else "")
            )
        if status == Status.NOT_SETTLED:
            raise NumericalError(
                f"viscous model (implicit integrator): {Status.NOT_SETTLED.describe()} at "
                f"t = {state.time:g} (scaled) after {int(counters[Count.STEPS])} steps and "
                f"{state.n_drained} drained pores (meniscus in throat "
                f"{int(counters[Count.WHERE])}); try a smaller 'tolerance' or the explicit "
                "integrator"
            )
        n_now = int(counters[Count.EVENTS])
        if status == Status.END_TIME and t_end < self._t_end:
            status = Status.BUDGET  # an observer's time, not the end
        ended = (Status.END_TIME, Status.NO_MENISCUS, Status.STATIONARY)
        if status in ended or (
            status == Status.BUDGET and stop.at == "complete" and self._all_trapped(state)
        ):
            self._status = status if status else Status.NO_MENISCUS
        return n_now - before

    def _implicit_advance(self, state: State, budget: int, t_end: float) -> int:
        from porenet.kinds.viscous.implicit_steps import implicit_advance

        return implicit_advance(
            self.network, self.conductances, self.flow, self.front, self.records,
            self.injection, self._stops(budget, t_end), self.implicit,
        )  # fmt: skip

    def _rkc_advance(self, state: State, budget: int, t_end: float) -> int:
        if self._local is None and self._local_steps_apply():
            from porenet.kinds.viscous.local_steps import LocalSteps

            self._local = LocalSteps(
                self, self.config.window_tolerance, always=self.config.local_steps == "on"
            )
        if self._local is not None:
            return self._local.advance(state, budget, t_end, self._step_chunk())
        return self.rkc_steps(budget, t_end)

    def _local_steps_apply(self) -> bool:
        """Whether this run may take local time steps (``local_steps`` not 'off'): the RKC
        integrator on a square grid under rate control, without a coupled solid."""
        return (
            self.config.local_steps != "off"
            and self.network.grid_n > 0
            and self.injection.control == Control.RATE
            and self.injection_rate > 0
            and self.step_limit is None
        )

    #: The capability switches :meth:`sized` uses whatever the lattice and the scene (None:
    #: from them; ``{}``: the full kernels): ``porenet compile`` sets them to compile, on its
    #: tiny scenes, the variants that runs of every size call.
    switches: dict[str, bool] | None = None

    def sized(self, kernel: Any) -> Any:
        """``kernel`` as this run can use it (:func:`porenet.jit.jit.variant`): without
        the code for threads on a lattice where no box can reach
        :data:`~porenet.jit.jit.PARALLEL_MIN` pores (fewer pores, or not a square grid),
        without the code for lists of active pores on the square grid, and without the code
        for local time steps' windows where this run cannot take them. The same loops run, so
        the results are the same; a first run compiles only what it can call."""
        if self.switches is not None:
            return variant(kernel, **self.switches)
        from porenet.kinds.viscous.local_steps import LocalSteps

        grid = self.network.grid_n > 0
        windows = self._local_steps_apply() and (
            self.config.local_steps == "on" or self.lattice.n_pores >= LocalSteps.min_box
        )
        return variant(
            kernel,
            THREADS=grid and self.lattice.n_pores >= PARALLEL_MIN,
            LISTS=not grid,
            WINDOWS=windows,
        )

    # -- for local time steps (porenet.kinds.viscous.local_steps) --------------------------
    def rkc_steps(
        self,
        budget: int,
        t_end: float,
        step_budget: int | None = None,
        window: Window | None = None,
        window_front: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None,
    ) -> int:
        """Single-rate RKC steps over the active box until ``budget`` pores drain, model time
        ``t_end``, or ``step_budget`` steps (default: as many as fill the call's wall time);
        returns a :class:`~porenet.kinds.viscous.kernels.state.Status`. Given a ``window`` (mode
        FINE) and ``window_front = (throats, slots, counters)`` (the window's own frontier and
        a copy of :attr:`flow`'s counters whose ``N_FRONT`` counts it): the fine integration
        of one macro step of local time steps, over the window's box."""
        from porenet.kinds.viscous.kernels.rkc import rkc_advance

        flow, front = self.flow, self.front
        if window_front is not None:
            throats, slots, counters = window_front
            flow = flow._replace(counters=counters)
            front = front._replace(throats=throats, throat_slot=slots)
        return self.sized(rkc_advance)(
            self.network, self.conductances, flow, front, self.records, self.scratch,
            self.injection, self.rules, self._stops(budget, t_end, step_budget),
            self.window_off if window is None else window, self.rkc,
        )  # fmt: skip

    def rates_changed(self) -> None:
        """The pressures, the active box or the conductances changed outside the RKC kernel
        (local time steps, a deformed solid): its next call recomputes ``F_E(p)``."""
        if self.integrator == "rkc":
            from porenet.kinds.viscous.kernels.rkc import Slot

            self.rkc.memory[Slot.F0_VALID] = 0.0

    def no_menisci(self) -> tuple[Menisci, Pump]:
        """The menisci and pump of :func:`porenet.kinds.viscous.kernels.rkc_step.imex_stages` for a
        step with no meniscus listed (the far field of local time steps)."""
        m, n = len(self.conductances.area), len(self.flow.pressure)
        scratch, flow, cond = self.scratch, self.flow, self.conductances
        menisci = Menisci(
            throat=scratch.meniscus_throat,
            pore=scratch.meniscus_pore,
            threshold=np.empty(m),
            head=np.full(n, -1, dtype=np.int64),
            next=np.empty(m, dtype=np.int64),
            pressure=flow.pressure,
            flux=self.rkc.f0,
            volume=self.network.volume,
            conductance=cond.meniscus,
            length=flow.meniscus_length,
            area=cond.area,
        )
        inj, totals = self.injection, flow.totals
        capacity = inj.capacity + inj.capacity_per_drained * totals[Total.DRAINED_PORE_VOLUME]
        pump = Pump(inj.control, float(totals[Total.INVADING_PRESSURE]), inj.rate, capacity,
                    inj.ramp_rate)  # fmt: skip
        return menisci, pump

    def rkc_sweeps(self) -> float:
        """Stage sweeps and explicit steps the RKC integrator has taken so far."""
        from porenet.kinds.viscous.kernels.rkc import Slot

        memory = self.rkc.memory
        return float(memory[Slot.STAGES] + memory[Slot.EXPLICIT_STEPS])

    # -- calls ------------------------------------------------------------------------------
    def _step_chunk(self) -> int:
        """Most time steps of this kernel call: the coupler's limit (:attr:`step_limit`) if
        any, else as many as fill :attr:`call_seconds` (at most ``_STEP_CHUNK``)."""
        if self.step_limit is not None:
            return min(_STEP_CHUNK, self.step_limit)
        if self.call_seconds is None:
            return _STEP_CHUNK
        return self._pace.steps(self.call_seconds, threads())

    def _sweeps(self) -> float:
        """Pore sweeps done so far (the work of the kernels that run on threads): time steps
        times the active box for the explicit integrator, stage sweeps and explicit steps
        times it for RKC, the windows' and coarse steps' pore stages with local time steps;
        0 for the implicit integrator (its solves run on one thread)."""
        area = box_area(self.front.box)
        if self.integrator == "explicit":
            return float(self.flow.counters[Count.STEPS]) * area
        if self.integrator != "rkc":
            return 0.0
        if self._local is None:
            return self.rkc_sweeps() * area
        st = self._local.stats
        return float(
            st["window_pore_stages"] + st["coarse_pore_stages"] + st["single_rate_sweeps"] * area
        )

    def parallel_work(self) -> float | None:
        """Pore sweeps (:meth:`_sweeps`) of boxes large enough for threads (``PARALLEL_MIN``
        pores), so far; None on lattices other than square grids, which run on one thread."""
        if self.network.grid_n == 0 or self.integrator == "implicit":
            return None
        return self._parallel_work

    def apertures_changed(self, state: State, throats: np.ndarray | None = None) -> None:
        """Recompute the areas, conductances and entry pressures of the deformed throats (in
        place: the kernels keep reading the same arrays) and shrink the stable time step if
        they made it smaller (``g ~ r**4``). Only throats between undrained pores limit the
        explicit step (the menisci are implicit), so throats that opened inside the invaded
        region cost nothing. The step never grows back, and never exceeds the one taken at
        setup, so an undeformed medium keeps its time step. The safety factor and the
        accuracy limits keep their values; pore volumes do not change."""
        from porenet.kinds.viscous.kernels.diffusion import refresh_throats

        cond, net = self.conductances, self.network
        if throats is None:
            throats = np.arange(len(cond.area), dtype=np.int64)
        c_area, c_perm = self.lattice.throat_factors
        limit = refresh_throats(
            np.ascontiguousarray(throats, dtype=np.int64), state.apertures,
            (float(c_area), float(c_perm), MENISCUS_LENGTH), net, cond, state.drained,
        )  # fmt: skip
        self.rates_changed()
        if limit < self.dt_stable:
            self.dt_stable = limit
            self._dt = self.config.safety_factor * self.dt_stable
            self.rules = self._step_rules()
        if limit < math.inf and self.integrator == "rkc":
            # a throat conducts more: the Lanczos value may no longer bound the spectrum,
            # Gershgorin's (2 / dt_stable, dt_stable a lower bound of every pore's) does
            self.rkc = self.rkc._replace(
                spectral_radius=max(self.rkc.spectral_radius, 2.0 / self.dt_stable),
                dt_stable=self.dt_stable,
            )

    def _sync(self, state: State) -> None:
        """Copy the kernel's counters into the State and extend the record."""
        from porenet.kinds.viscous.kernels.state import Column

        counters, totals, records = self.flow.counters, self.flow.totals, self.records
        k = int(counters[Count.EVENTS])
        start = self._synced
        if k > start:
            rows = records.series[start:k]
            pressure, times = rows[:, Column.INVADING_PRESSURE], rows[:, Column.TIME]
            state.record.extend(records.order[start:k], records.via[start:k], pressure, times)
            self._synced = k
        state.n_drained = k
        state.time = float(totals[Total.TIME])
        state.invading_pressure = float(totals[Total.INVADING_PRESSURE])
        state.breakthrough = bool(counters[Count.BREAKTHROUGH])
        state.step = int(counters[Count.STEPS])

    def _undrained_outlets(self, state: State) -> int:
        """Outlet pores the invader has not drained yet."""
        return int(np.count_nonzero(self.network.outlet & ~state.drained))

    def _all_trapped(self, state: State) -> bool:
        """Whether every undrained pore is trapped (its defending cluster holds no outlet
        pore): the same as every outlet pore being drained, since an undrained outlet pore is
        never trapped and a cluster without one always is."""
        return self._undrained_outlets(state) == 0

    @property
    def exhausted(self) -> bool:
        return self._status >= 0

    @property
    def stop_reason(self) -> str | None:
        # _status is set only to END_TIME, NO_MENISCUS (nothing left to invade) or STATIONARY
        reasons = {-1: None, Status.END_TIME: "max_time", Status.NO_MENISCUS: "complete",
                   Status.STATIONARY: "stationary"}  # fmt: skip
        return reasons[self._status]

    def finalize(self, state: State) -> None:
        from porenet.kinds.invasion.kernels import trapping

        net = self.network
        self.flow.pressure[state.drained] = state.invading_pressure
        state.trapped[:] = trapping.enclosed_defender(
            net.indptr, net.neighbour, state.drained, net.outlet
        )

    # -- outputs ----------------------------------------------------------------------------
    def volumes(self) -> dict[str, float]:
        """Running volume totals (units of a^3), by the lower-case names of
        :class:`porenet.kinds.viscous.kernels.state.Total`."""
        totals = self.flow.totals
        return {slot.name.lower(): float(totals[slot]) for slot in Total}

    def balance_errors(self) -> tuple[float, float]:
        """Relative residuals of the invader balance (injected = drained + stored in the
        reservoir) and the defender balance (drained = stored in the defender + outflow +
        released), for the totals so far."""
        v = self.volumes()
        scale = max(abs(v["injected"]), abs(v["drained"]), 1e-300)
        invader = v["injected"] - v["drained"] - v["stored_reservoir"]
        defender = v["drained"] - v["stored_defender"] - v["outflow"] - v["released"]
        return abs(invader) / scale, abs(defender) / scale

    def measured_capillary_number(self) -> float:
        """Ca = mu v / gamma with v = V_drained / (t A_b): drained volume over time and the
        boundary cross-section (0 before any time has passed)."""
        v = self.volumes()
        t = v["time"]
        return v["drained"] / (t * self.cross_section) if t > 0 else 0.0

    def timeseries(self) -> dict[str, np.ndarray]:
        """Rows at each drainage event (inlets included), scaled units, by the lower-case
        names of :class:`porenet.kinds.viscous.kernels.state.Column`."""
        from porenet.kinds.viscous.kernels.state import Column

        rows = self.records.series[: int(self.flow.counters[Count.EVENTS])]
        series = {column.name.lower(): rows[:, column].copy() for column in Column}
        t = series["time"]
        with np.errstate(divide="ignore", invalid="ignore"):
            ca = np.where(t > 0, series["drained"] / (t * self.cross_section), 0.0)
        series["capillary_number"] = ca
        return series

    def outputs(self, state: State) -> dict[str, Any]:
        return {"timeseries": self.timeseries()}

    def largest_balance_error(self) -> float:
        """Largest relative volume imbalance over the run: the two balances of
        :meth:`balance_errors` now, and their sum (injected = stored + outflow + released) at
        every drainage event."""
        from porenet.kinds.viscous.kernels.state import Column

        rows = self.records.series[: int(self.flow.counters[Count.EVENTS])]
        injected, drained = rows[:, Column.INJECTED], rows[:, Column.DRAINED]
        scale = np.maximum(np.maximum(np.abs(injected), np.abs(drained)), 1e-300)
        combined = injected - rows[:, Column.STORED] - rows[:, Column.OUTFLOW]
        combined -= rows[:, Column.RELEASED]
        worst = float(np.max(np.abs(combined) / scale)) if combined.size else 0.0
        return max(worst, *self.balance_errors())

    def summary(self, state: State) -> dict[str, Any]:
        cfg, sc = self.config, self.context.scales
        requested = cfg.capillary_number
        if requested is None and cfg.injection_rate is not None:
            requested = self.injection_rate / self.cross_section
        steps = int(self.flow.counters[Count.STEPS])
        out = {
            "capillary_number": requested,
            "capillary_number_measured": self.measured_capillary_number(),
            "volume_balance_error": self.largest_balance_error(),
            "time_steps": steps,
            "stable_time_step_s": self.dt_stable * (sc.time or 0.0),
            # explicit: the fixed step; implicit: the mean accepted step
            "time_step_s": self._dt * (sc.time or 0.0),
            "final_invading_pressure": state.invading_pressure * sc.pressure,
            "integrator": self.integrator,
        }
        if self.integrator in _SUMMARY_COUNTERS:
            out["time_step_s"] = state.time / max(steps, 1) * (sc.time or 0.0)
            out.update(self._integrator_counters())
        if self.integrator == "rkc":
            out["local_steps"] = self._local is not None
            if self._local is not None:
                out.update(self._local.stats)
        return out

    def _integrator_counters(self) -> dict[str, int]:
        """The step-controlled integrator's counters for ``/summary``."""
        names = _SUMMARY_COUNTERS[self.integrator]
        if self.integrator == "rkc":
            from porenet.kinds.viscous.kernels.rkc import Slot

            return {key: int(self.rkc.memory[Slot[slot]]) for key, slot in names.items()}
        from porenet.kinds.viscous.implicit_steps import Slot as ImplicitSlot

        memory = self.implicit.memory
        return {key: int(memory[ImplicitSlot[slot]]) for key, slot in names.items()}
