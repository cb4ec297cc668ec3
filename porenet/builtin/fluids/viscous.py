"""The paper's dynamic drainage model (docs/model.md §4) as a FluidModel, kind ``viscous``."""

from __future__ import annotations

import math
import time
from typing import Any

import numpy as np

from porenet.builtin.fluids.config import ViscousConfig, auto_integrator
from porenet.core.errors import NumericalError
from porenet.core.interfaces import FluidModel
from porenet.core.state import State
from porenet.kernels._jit import PARALLEL_MIN, threads
from porenet.kernels.viscous.window import box_area, no_window
from porenet.threads import CallPace

#: Length of a new meniscus: the distance between two pore centres, 2a.
MENISCUS_LENGTH = 2.0

#: Drainage events between the points where a macro step of local time steps ends (counted
#: from the first event after the inlets, so the same in every run of a scene: where the
#: calls end does not matter). The other integrators give the same results for any value.
_CHUNK = 256
#: Most time steps per call into the kernel. Within it a call aims at the Simulation's
#: ``call_seconds`` (:class:`porenet.threads.CallPace`): the Simulation regains control
#: that often to run observers (progress, snapshots), check the stops and choose the
#: threads. Where a call ends changes no result (``tests/verification/test_chunking.py``).
_STEP_CHUNK = 20_000

#: The step-controlled integrators' counters in ``/summary``: attribute -> slot of the
#: kernel module of the same name's ``CTRL`` (:mod:`porenet.kernels.viscous.implicit`,
#: :mod:`porenet.kernels.viscous.rkc`).
_SUMMARY_COUNTERS = {
    "implicit": {
        "linear_solves": "solves",
        "factorizations": "factorizations",
        "rejected_steps": "rejected",
    },
    "rkc": {
        "stage_sweeps": "stages",
        "rkc_steps": "rkc_steps",
        "rejected_steps": "rejected",
        "rejected_for_events": "rejected_events",
        "rejected_stage_sweeps": "rejected_stages",
        "explicit_steps": "explicit_steps",
    },
}


class ViscousDrainage(FluidModel):
    """The dynamic model: pore pressures, Darcy fluxes, advancing menisci, injection reservoir.

    Reads ``state.apertures`` at :meth:`setup`. Writes ``drained``, ``trapped``, ``pressure``
    (defender pressure; invader pressure in drained pores), ``invading_pressure``, ``time``,
    ``step``, ``n_drained``, ``breakthrough``, ``meniscus_length`` and ``record`` (drainage
    times, and the invading pressure at each drainage). Scaled units throughout.
    """

    solves_pressure = True
    config: ViscousConfig

    # -- setup --------------------------------------------------------------------------
    def setup(self, state: State) -> None:
        from porenet.kernels.viscous import explicit as vk

        lat, cfg, sc = self.lattice, self.config, self.context.scales
        at = self.context.injection.at
        self._conductances(state)
        self._injection()
        self._integrator = self._choose_integrator()
        self._allocate(state)
        for inlet in lat.inlet_pores(at):
            vk.drain_pore(
                int(inlet), -1, *self._csr, self._vol, MENISCUS_LENGTH, self._g_eff,
                self._g_out, self._grid_n, self._box, self._p, state.drained,
                self._ell, self._latched, self._front, self._fpos, self._act, self._apos,
                self._acc, self._cnt, self._order, self._via,
                self._series,
            )  # fmt: skip
        if self._outlet[state.drained].any():  # an inlet on the outlet: breakthrough at once
            self._cnt[5] = 1
        self._events0 = int(self._cnt[0])
        self._pace = CallPace(most=_STEP_CHUNK)
        self._parallel_work = 0.0
        self._status = -1
        self._synced = 0
        self._pending_saturations = [
            math.ceil(s * lat.n_pores) for s in sorted(cfg.snapshot_saturations)
        ]
        self._pending_times = sorted(t / sc.time for t in cfg.snapshot_times)
        self._t_end = math.inf if cfg.max_time is None else cfg.max_time / sc.time
        self.snapshots: list[dict[str, Any]] = []
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
        if self.config.control != "rate" or self._q <= 0:
            return "explicit"
        explicit_steps = 2.8 * float(np.mean(self._vol)) / (self._q * self._dt)
        return auto_integrator(explicit_steps, self.lattice.n_pores)

    def _conductances(self, state: State) -> None:
        """Throat, pore and outlet properties from the apertures, the stable step and the
        accuracy limit (scaled units)."""
        lat, cfg = self.lattice, self.config
        at = self.context.injection.at
        indptr, nbr, thr = lat.adjacency
        self._csr = (
            np.asarray(indptr, np.int64),
            np.asarray(nbr, np.int64),
            np.asarray(thr, np.int64),
        )
        self._tp = np.ascontiguousarray(lat.throat_pores, dtype=np.int64)
        c_area, c_perm = lat.throat_factors
        r = np.asarray(state.apertures, dtype=np.float64)
        self._area = c_area * r**2
        self._g_num = self._area * c_perm * r**2  # A k: meniscus conductance times length
        self._g_eff = self._g_num / MENISCUS_LENGTH  # zeroed for throats touching drained pores
        self._pe = 2.0 / r
        self._vol = np.ascontiguousarray(lat.pore_volumes, dtype=np.float64)
        links = lat.outlet_links(at)
        self._g_out = links * c_area * c_perm * lat.mean_aperture**4  # half throats, length a
        self._outlet = np.ascontiguousarray(lat.outlet_mask(at), dtype=bool)
        #: Boundary cross-section A_b / a^2 (4 L a for centre injection).
        self.cross_section = float(links.sum())
        # Canonical square grids are swept as a stencil over a growing box of active pores.
        self._grid_n = int(lat.grid_shape[0]) if lat.canonical_grid else 0
        self._box = np.zeros(4, dtype=np.int64)
        self._box[[0, 2]] = self._grid_n  # empty: grows as pores drain
        degree_sum = np.zeros(lat.n_pores)
        np.add.at(degree_sum, self._tp[:, 0], self._g_eff)
        np.add.at(degree_sum, self._tp[:, 1], self._g_eff)
        self.dt_stable = float(np.min(self._vol / (degree_sum + self._g_out)))
        self._dt = cfg.safety_factor * self.dt_stable
        spread = float(np.max(self._pe) - np.min(self._pe))
        #: Unit of the accuracy limits, gamma/a: the entry-pressure spread (a floor of 1 % of
        #: the mean entry pressure keeps it finite for nearly uniform apertures).
        self._pressure_scale = max(spread, 0.01 * float(np.mean(self._pe)))
        self._pressure_step = (
            math.inf if cfg.pressure_step is None else cfg.pressure_step * self._pressure_scale
        )

    def _injection(self) -> None:
        """Control, rate (a^2 gamma / mu), reservoir compliance and ramp (scaled)."""
        from porenet.kernels.viscous import menisci as mk

        cfg, sc = self.config, self.context.scales
        if sc.time is None:  # pragma: no cover - the config always has a viscosity
            raise ValueError("the viscous model needs a viscosity")
        self._control = {"rate": mk.CONTROL_RATE, "pressure": mk.CONTROL_PRESSURE,
                         "ramp": mk.CONTROL_RAMP}[cfg.control]  # fmt: skip
        if cfg.capillary_number is not None:
            self._q = cfg.capillary_number * self.cross_section
        elif cfg.injection_rate is not None:
            self._q = cfg.injection_rate * cfg.viscosity / (sc.length**2 * cfg.interfacial_tension)
        else:
            self._q = 0.0
        self._capacity = float(np.mean(self._vol)) if cfg.reservoir == "pore" else 0.0
        self._capacity_per_drained = 1.0 if cfg.reservoir == "drained" else 0.0
        self._ramp = 0.0 if cfg.ramp_rate is None else cfg.ramp_rate * sc.time / sc.pressure

    def _allocate(self, state: State) -> None:
        """The model's state, scratch and record arrays; the State shares the first two."""
        from porenet.kernels.viscous import explicit as vk

        n, m = self.lattice.n_pores, self.lattice.n_throats
        self._p = np.zeros(n)
        state.pressure = self._p
        self._ell = np.full(m, MENISCUS_LENGTH)
        state.meniscus_length = self._ell
        self._latched = np.zeros(m, dtype=bool)
        self._front, self._fpos = np.zeros(m, dtype=np.int64), np.full(m, -1, dtype=np.int64)
        self._act, self._apos = np.zeros(n, dtype=np.int64), np.full(n, -1, dtype=np.int64)
        self._flux, self._p_next = np.zeros(n), np.zeros(n)
        self._on_t, self._on_p = np.zeros(m, dtype=np.int64), np.zeros(m, dtype=np.int64)
        self._landing = np.zeros(m)
        self._acc = np.zeros(vk.N_ACC)
        self._acc[[vk.ACC["dt_next"], vk.ACC["last_rate"]]] = np.inf
        self._acc[vk.ACC["invading_pressure"]] = (
            self.config.injection_pressure / self.context.scales.pressure
        )
        self._cnt = np.zeros(vk.N_CNT, dtype=np.int64)
        self._order, self._via = np.zeros(n, dtype=np.int64), np.zeros(n, dtype=np.int64)
        self._series = np.zeros((n, len(vk.SERIES)))
        self._no_window = no_window()
        #: Scratch the kernels keep clean between calls (see rkc_advance's ``work``).
        self._work = (np.full(n, -1, dtype=np.int64), np.zeros(m, dtype=bool), np.zeros(n))
        self._local: Any = None  # LocalSteps, built at the first RKC call where they apply
        if self.integrator == "rkc":
            from porenet.kernels.viscous import rkc
            from porenet.kernels.viscous.chebyshev import spectral_radius

            self._ybuf = np.zeros((3, n))
            self._f0, self._fnew, self._zero = np.zeros(n), np.zeros(n), np.zeros(n)
            self._ctrl = np.zeros(rkc.N_CTRL)
            #: Spectral radius of the pore-to-pore operator (scaled), which sets the stages.
            self.spectral_radius = spectral_radius(self._tp, self._g_eff, self._g_out, self._vol)
        if self.integrator == "implicit":
            from porenet.kernels.viscous import implicit as ik

            self._mstate = np.zeros(m, dtype=np.int8)
            self._mflux = np.zeros(m)
            self._ctrl = np.zeros(ik.N_CTRL)
            self._cache: dict[str, Any] = {}

    def _check_step_count(self, state: State) -> None:
        """Fail at once, saying why, when the run cannot reach breakthrough within max_steps.

        Under rate control breakthrough needs at least the volume of the shortest path of
        pores from the inlet to the outlet (each pore costs a meniscus sweep of at least
        ``2 A_min``), delivered at rate Q: a lower bound on the time, hence on the steps.
        """
        from scipy.sparse import csr_matrix
        from scipy.sparse.csgraph import shortest_path

        cfg, stop = self.config, self.context.stop
        if cfg.control != "rate" or stop.at != "breakthrough" or cfg.max_time is not None:
            return
        indptr, nbr, _ = self._csr
        n = len(indptr) - 1
        graph = csr_matrix((np.ones(len(nbr)), nbr, indptr), shape=(n, n))
        sources = np.flatnonzero(state.drained)
        dist = shortest_path(graph, unweighted=True, indices=sources, directed=False)
        hops = float(np.min(np.atleast_2d(dist)[:, self._outlet]))
        if not np.isfinite(hops):
            return
        volume = hops * MENISCUS_LENGTH * float(np.min(self._area))
        steps = volume / self._q / self._dt
        if steps > cfg.max_steps:
            sc = self.context.scales
            raise NumericalError(
                f"viscous model: Ca = {self._q / self.cross_section:.3g} needs at least "
                f"{steps:.3g} explicit time steps to reach breakthrough (time step "
                f"{self._dt * (sc.time or 0):.3g} s), more than fluid.max_steps = "
                f"{cfg.max_steps}; at such capillary numbers invasion percolation gives the "
                f"same pattern (see docs/accuracy.md), or raise max_steps"
            )

    # -- loop -----------------------------------------------------------------------------
    def advance(self, state: State, max_events: int) -> int:
        from porenet.kernels.viscous import explicit as vk

        cfg, stop = self.config, self.context.stop
        before = int(self._cnt[0])
        budget = max(int(max_events), 0)
        budget = min(budget, _CHUNK - (before - self._events0) % _CHUNK)
        if self._pending_saturations:
            budget = min(budget, max(self._pending_saturations[0] - before, 0))
        if stop.at == "complete":
            # "complete" is reached at the event that drains the last undrained outlet pore
            # (_all_trapped): a call may end there, never past it, so the run stops at that
            # event wherever its calls end (it was checked only where calls ended, which
            # depends on the machine's speed)
            budget = min(budget, max(self._undrained_outlets(state), 1))
        t_end = self._t_end
        if self._pending_times:
            t_end = min(t_end, self._pending_times[0])
        status = 0
        steps0, sweeps0, wall0 = int(self._cnt[1]), self._sweeps(), time.perf_counter()
        if budget > 0 and self.integrator == "implicit":
            status = self._implicit_advance(state, budget, t_end)
        elif budget > 0 and self.integrator == "rkc":
            status = self._rkc_advance(state, budget, t_end)
        elif budget > 0:
            status = vk.explicit_advance(
                *self._csr, self._tp, self._g_eff, self._g_num, self._area, self._pe, self._vol,
                self._g_out, self._outlet, self._grid_n, self._box, self._p, state.drained,
                self._ell, self._latched, self._front, self._fpos, self._act, self._apos,
                self._flux, self._p_next, self._on_t, self._on_p, self._landing,
                self._acc, self._cnt, self._order, self._via,
                self._series, self._dt, self._control, self._q, self._capacity,
                self._capacity_per_drained, self._ramp, cfg.meniscus == "latching",
                cfg.pressure_floor, self._pressure_step, MENISCUS_LENGTH, budget, t_end,
                cfg.max_steps, stop.at == "breakthrough", self._step_chunk(), self._box,
                self._no_window, self._work[0],
            )  # fmt: skip
        self._pace.record(int(self._cnt[1]) - steps0, time.perf_counter() - wall0, threads())
        if self._grid_n > 0 and box_area(self._box) >= PARALLEL_MIN:
            self._parallel_work += self._sweeps() - sweeps0
        self._sync(state)
        if status in (3, 4):
            raise NumericalError(
                f"viscous model: {vk.STATUS[status]} at t = {state.time:g} (scaled) after "
                f"{int(self._cnt[1])} steps and {state.n_drained} drained pores"
                + (f" (max_steps = {cfg.max_steps})" if status == 3 else "")
            )
        if status == 7:
            from porenet.kernels.viscous import implicit as ik

            raise NumericalError(
                f"viscous model (implicit integrator): {ik.STATUS[7]} at t = {state.time:g} "
                f"(scaled) after {int(self._cnt[1])} steps and {state.n_drained} drained pores "
                f"(meniscus in throat {int(self._cnt[vk.CNT['where']])}); try a smaller "
                f"'tolerance' or the explicit integrator"
            )
        n_now = int(self._cnt[0])
        if self._pending_saturations and n_now >= self._pending_saturations[0]:
            self._pending_saturations.pop(0)
            self._snapshot(state)
        if self._pending_times and state.time >= self._pending_times[0] * (1 - 1e-12):
            self._pending_times.pop(0)
            self._snapshot(state)
            if status == 2:
                status = 0  # a snapshot time, not the end
        if status in (2, 5, 6) or (
            status == 0 and stop.at == "complete" and self._all_trapped(state)
        ):
            self._status = status if status else 5
        return n_now - before

    def _implicit_advance(self, state: State, budget: int, t_end: float) -> int:
        from porenet.kernels.viscous import implicit as ik

        cfg, stop = self.config, self.context.stop
        return ik.implicit_advance(
            *self._csr, self._tp, self._g_eff, self._g_num, self._area, self._pe, self._vol,
            self._g_out, self._outlet, self._grid_n, self._box, self._p, state.drained,
            self._ell, self._latched, self._front, self._fpos, self._act, self._apos,
            self._mstate, self._mflux, self._ctrl, self._acc, self._cnt, self._order,
            self._via, self._series, self._cache, self._control, self._q, self._capacity,
            self._capacity_per_drained, self._ramp, cfg.meniscus == "latching",
            MENISCUS_LENGTH, self.dt_stable, self._pressure_scale, cfg.tolerance,
            cfg.event_tolerance, cfg.pressure_floor, budget, t_end, cfg.max_steps,
            stop.at == "breakthrough", self._step_chunk(),
        )  # fmt: skip

    def _rkc_advance(self, state: State, budget: int, t_end: float) -> int:
        if self._local is None and self._local_steps_apply():
            from porenet.builtin.fluids.local_steps import LocalSteps

            self._local = LocalSteps(
                self, self.config.window_tolerance, always=self.config.local_steps == "on"
            )
        if self._local is not None:
            return self._local.advance(state, budget, t_end, self._step_chunk())
        return self._rkc_single(state, budget, t_end)

    def _local_steps_apply(self) -> bool:
        """Whether this run may take local time steps (``local_steps`` not 'off'): the RKC
        integrator on a square grid under rate control, without a coupled solid."""
        return (
            self.config.local_steps != "off"
            and self._grid_n > 0
            and self._control == 0  # rate
            and self._q > 0
            and self.step_limit is None
        )

    def _rkc_single(
        self,
        state: State,
        budget: int,
        t_end: float,
        wbox: np.ndarray | None = None,
        win: tuple | None = None,
        front: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None,
        step_budget: int | None = None,
    ) -> int:
        """Single-rate RKC steps over the active box; or, given ``wbox``, ``win`` and
        ``front``, the fine integration of one macro step of local time steps: RKC over the
        window ``wbox`` with the window's own front ``(front, fpos, cnt)`` (a copy of the
        counters whose slot 2 counts it). At most ``step_budget`` steps (default
        :meth:`_step_chunk`)."""
        from porenet.kernels.viscous import rkc

        cfg, stop = self.config, self.context.stop
        box = self._box if wbox is None else wbox
        fr, fpos, cnt = (self._front, self._fpos, self._cnt) if front is None else front
        return rkc.rkc_advance(
            *self._csr, self._tp, self._g_eff, self._g_num, self._area, self._pe, self._vol,
            self._g_out, self._outlet, self._grid_n, box, self._p, state.drained,
            self._ell, self._latched, fr, fpos, self._act, self._apos,
            self._flux, self._p_next, self._on_t, self._on_p, self._landing,
            self._acc, cnt, self._order, self._via, self._series,
            self._ybuf, self._f0, self._fnew, self._zero, self._ctrl, self.spectral_radius,
            self.dt_stable, self._dt, self._control, self._q, self._capacity,
            self._capacity_per_drained, self._ramp, cfg.meniscus == "latching",
            cfg.pressure_floor, self._pressure_step, self._pressure_scale, cfg.tolerance,
            MENISCUS_LENGTH, budget, t_end, cfg.max_steps, stop.at == "breakthrough",
            self._step_chunk() if step_budget is None else step_budget, self._box,
            self._no_window if win is None else win, self._work,
        )  # fmt: skip

    def rates_changed(self) -> None:
        """The pressures, the active box or the conductances changed outside the RKC kernel
        (local time steps, a deformed solid): its next call recomputes ``F_E(p)``."""
        if self.integrator == "rkc":
            from porenet.kernels.viscous import rkc

            self._ctrl[rkc.CTRL["f0_valid"]] = 0.0

    def _no_menisci(self) -> tuple[tuple, tuple]:
        """The menisci and pump tuples of :func:`porenet.kernels.viscous.rkc_step.imex_stages` for a
        step with no meniscus listed (the far field of local time steps)."""
        m, n = len(self._pe), len(self._p)
        menisci = (self._on_t, self._on_p, np.empty(m), np.full(n, -1, dtype=np.int64),
                   np.empty(m, dtype=np.int64), self._p, self._f0, self._vol, self._g_num,
                   self._ell, self._area)  # fmt: skip
        capacity = self._capacity + self._capacity_per_drained * self._acc[7]
        pump = (self._control, float(self._acc[1]), self._q, capacity, self._ramp)
        return menisci, pump

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
        area = box_area(self._box)
        if self.integrator == "explicit":
            return float(self._cnt[1]) * area
        if self.integrator != "rkc":
            return 0.0
        if self._local is None:
            return float(self._ctrl[1] + self._ctrl[4]) * area
        st = self._local.stats
        return float(
            st["window_pore_stages"] + st["coarse_pore_stages"] + st["single_rate_sweeps"] * area
        )

    def parallel_work(self) -> float | None:
        """Pore sweeps (:meth:`_sweeps`) of boxes large enough for threads (``PARALLEL_MIN``
        pores), so far; None on lattices other than square grids, which run on one thread."""
        if self._grid_n == 0 or self.integrator == "implicit":
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
        from porenet.kernels.viscous.diffusion import refresh_throats

        if throats is None:
            throats = np.arange(len(self._area), dtype=np.int64)
        c_area, c_perm = self.lattice.throat_factors
        limit = refresh_throats(
            np.ascontiguousarray(throats, dtype=np.int64), state.apertures, c_area, c_perm,
            MENISCUS_LENGTH, self._tp, state.drained, self._area, self._g_num, self._g_eff,
            self._pe, self._csr[0], self._csr[2], self._vol, self._g_out,
        )  # fmt: skip
        self.rates_changed()
        if limit < self.dt_stable:
            self.dt_stable = limit
            self._dt = self.config.safety_factor * self.dt_stable
        if limit < math.inf and self.integrator == "rkc":
            # a throat conducts more: the Lanczos value may no longer bound the spectrum,
            # Gershgorin's (2 / dt_stable, dt_stable a lower bound of every pore's) does
            self.spectral_radius = max(self.spectral_radius, 2.0 / self.dt_stable)

    def _sync(self, state: State) -> None:
        """Copy the kernel's counters into the State and extend the record."""
        k = int(self._cnt[0])
        start = self._synced
        if k > start:
            rows = self._series[start:k]  # columns 0, 1: time and invading pressure
            state.record.extend(self._order[start:k], self._via[start:k], rows[:, 1], rows[:, 0])
            self._synced = k
        state.n_drained = k
        state.time = float(self._acc[0])
        state.invading_pressure = float(self._acc[1])
        state.breakthrough = bool(self._cnt[5])
        state.step = int(self._cnt[1])

    def _undrained_outlets(self, state: State) -> int:
        """Outlet pores the invader has not drained yet."""
        return int(np.count_nonzero(self._outlet & ~state.drained))

    def _all_trapped(self, state: State) -> bool:
        """Whether every undrained pore is trapped (its defending cluster holds no outlet
        pore): the same as every outlet pore being drained, since an undrained outlet pore is
        never trapped and a cluster without one always is."""
        return self._undrained_outlets(state) == 0

    def _snapshot(self, state: State) -> None:
        pressure = self._p.copy()
        pressure[state.drained] = state.invading_pressure
        self.snapshots.append(
            {
                "time": state.time,
                "saturation": state.n_drained / state.n_pores,
                "invading_pressure": state.invading_pressure,
                "pressure": pressure,
                "drained": state.drained.copy(),
            }
        )

    @property
    def exhausted(self) -> bool:
        return self._status >= 0

    @property
    def stop_reason(self) -> str | None:
        # _status is set only to 2 (end time), 5 (nothing left to invade) or 6 (stationary)
        return {-1: None, 2: "max_time", 5: "complete", 6: "stationary"}[self._status]

    def finalize(self, state: State) -> None:
        from porenet.kernels.invasion import ip

        self._p[state.drained] = state.invading_pressure
        state.trapped[:] = ip.enclosed_defender(
            self._csr[0], self._csr[1], state.drained, self._outlet
        )

    # -- outputs ----------------------------------------------------------------------------
    def volumes(self) -> dict[str, float]:
        """Running volume totals (units of a^3), see
        :data:`porenet.kernels.viscous.explicit.ACC`."""
        from porenet.kernels.viscous import explicit as vk

        return {name: float(self._acc[i]) for name, i in vk.ACC.items()}

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
        """Rows at each drainage event (inlets included), scaled units."""
        from porenet.kernels.viscous import explicit as vk

        rows = self._series[: int(self._cnt[0])]
        series = {name: rows[:, c].copy() for c, name in enumerate(vk.SERIES)}
        t = series["time"]
        with np.errstate(divide="ignore", invalid="ignore"):
            ca = np.where(t > 0, series["drained"] / (t * self.cross_section), 0.0)
        series["capillary_number"] = ca
        return series

    def outputs(self, state: State) -> dict[str, Any]:
        return {"timeseries": self.timeseries(), "snapshots": self.snapshots}

    def largest_balance_error(self) -> float:
        """Largest relative volume imbalance over the run: the two balances of
        :meth:`balance_errors` now, and their sum (injected = stored + outflow + released) at
        every drainage event."""
        from porenet.kernels.viscous import explicit as vk

        rows = self._series[: int(self._cnt[0])]
        col = {name: c for c, name in enumerate(vk.SERIES)}
        injected, drained = rows[:, col["injected"]], rows[:, col["drained"]]
        scale = np.maximum(np.maximum(np.abs(injected), np.abs(drained)), 1e-300)
        combined = injected - rows[:, col["stored"]] - rows[:, col["outflow"]]
        combined -= rows[:, col["released"]]
        worst = float(np.max(np.abs(combined) / scale)) if combined.size else 0.0
        return max(worst, *self.balance_errors())

    def summary(self, state: State) -> dict[str, Any]:
        cfg, sc = self.config, self.context.scales
        requested = cfg.capillary_number
        if requested is None and cfg.injection_rate is not None:
            requested = self._q / self.cross_section
        steps = int(self._cnt[1])
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
            import importlib

            # the kernel module of each step-controlled integrator has its name
            slots = importlib.import_module(f"porenet.kernels.viscous.{self.integrator}").CTRL
            out["time_step_s"] = state.time / max(steps, 1) * (sc.time or 0.0)
            for key, slot in _SUMMARY_COUNTERS[self.integrator].items():
                out[key] = int(self._ctrl[slots[slot]])
        if self.integrator == "rkc":
            out["local_steps"] = self._local is not None
            if self._local is not None:
                out.update(self._local.stats)
        return out
