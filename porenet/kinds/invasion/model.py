"""Quasi-static invasion percolation (docs/model.md section 3) as a FluidModel."""

from __future__ import annotations

from typing import Any

import numpy as np

from porenet.core.interfaces import FluidModel
from porenet.core.state import State
from porenet.kinds.invasion.config import InvasionPercolationConfig


class InvasionPercolation(FluidModel):
    """Classical invasion percolation with optional trapping.

    Apertures are quenched in a rigid medium, so the whole invasion is computed once at
    :meth:`setup` by the O(M log M) kernels of :mod:`porenet.kinds.invasion.kernels.ip`;
    :meth:`advance` then replays it in chunks so observers see the states they ask for. It reads
    ``state.apertures`` once and writes ``drained``, ``trapped``, ``invading_pressure``,
    ``n_drained``, ``breakthrough`` and ``record`` (pressures in units of gamma/a). It defines no
    pressure field: ``state.pressure`` stays None.
    """

    solves_pressure = False
    config: InvasionPercolationConfig

    def setup(self, state: State) -> None:
        from porenet.kinds.invasion.kernels import ip

        lat = self.lattice
        at = self.context.injection.at
        stop = self.context.stop
        self._indptr, self._neighbours, _ = lat.adjacency
        self._outlet = lat.outlet_mask(at)
        self._entry = np.asarray(lat.entry_pressures(state.apertures), dtype=np.float64)
        self._online: Any = None  # porenet.kinds.invasion.kernels.online.OnlineState
        if self.context.deformable:
            self._setup_online(state)
            return
        max_steps = lat.n_pores if stop.max_drained is None else int(stop.max_drained)
        order, via = ip.invasion_sequence(
            lat.adjacency,
            self._entry,
            lat.inlet_pores(at),
            self._outlet,
            trapping=self.config.trapping,
            stop_at_outlet=stop.at == "breakthrough",
            max_steps=max_steps,
        )
        self._order = order
        self._via = via
        self._pressure = ip.step_pressures(self._entry, via)
        self._cursor = 0

    def _setup_online(self, state: State) -> None:
        """Deformable media: the invasion is computed one pore at a time
        (:mod:`porenet.kinds.invasion.kernels.online`), re-reading the frontier's entry pressures
        after every mechanical update, with trapping detected as pores drain."""
        from porenet.kernels.graph import max_degree
        from porenet.kinds.invasion.kernels import online as ip_online

        lat = self.lattice
        indptr, neighbours, throats = (np.ascontiguousarray(a, np.int64) for a in lat.adjacency)
        self._graph = ip_online.Graph(indptr, neighbours, throats)
        self._outlet = np.ascontiguousarray(self._outlet, dtype=bool)
        self._online = ip_online.online_state(lat.n_pores, lat.n_throats, max_degree(indptr))
        inlets = np.ascontiguousarray(lat.inlet_pores(self.context.injection.at), np.int64)
        ip_online.online_start(self._graph, inlets, self._outlet, self.config.trapping,
                               self._online)  # fmt: skip
        drained = self._online.status == ip_online.DRAINED
        pores = np.flatnonzero(drained)
        state.drained[pores] = True
        k = len(pores)
        state.record.extend(pores, np.full(k, -1), np.zeros(k), np.zeros(k))
        state.n_drained = k
        state.breakthrough = bool(self._outlet[pores].any())
        self._exhausted = False

    def apertures_changed(self, state: State, throats: np.ndarray | None = None) -> None:
        """Re-read the entry pressures of the frontier throats (the only ones the next step
        compares) from the deformed apertures."""
        from porenet.kinds.invasion.kernels.online import online_frontier

        if self._online is None:  # pragma: no cover - the Simulation plans deformable runs
            raise NotImplementedError("invasion percolation was set up for a rigid medium")
        front = online_frontier(self._online)
        self._entry[front] = self.lattice.entry_pressures(state.apertures[front], front)

    def _advance_online(self, state: State, max_events: int) -> int:
        from porenet.kinds.invasion.kernels.online import online_step

        assert self._online is not None
        stop = self.context.stop
        done = 0
        while done < max_events and not self._exhausted:
            pore, throat, pressure = online_step(
                self._graph, self._entry, self._outlet, self.config.trapping, self._online
            )
            if pore < 0:
                self._exhausted = True
                break
            state.drained[pore] = True
            state.record.extend(
                np.array([pore]), np.array([throat]), np.array([pressure]), np.zeros(1)
            )
            state.n_drained += 1
            state.invading_pressure = float(pressure)
            done += 1
            if self._outlet[pore]:
                state.breakthrough = True
                if stop.at == "breakthrough":
                    self._exhausted = True
        state.step += 1
        return done

    def advance(self, state: State, max_events: int) -> int:
        if self._online is not None:
            return self._advance_online(state, max_events)
        start = self._cursor
        stop = min(len(self._order), start + max(int(max_events), 0))
        if stop <= start:
            return 0
        pores = self._order[start:stop]
        state.drained[pores] = True
        state.record.extend(
            pores, self._via[start:stop], self._pressure[start:stop], np.zeros(stop - start)
        )
        state.n_drained += stop - start
        state.invading_pressure = float(self._pressure[stop - 1])
        if not state.breakthrough and bool(self._outlet[pores].any()):
            state.breakthrough = True
        state.step += 1
        self._cursor = stop
        return stop - start

    @property
    def exhausted(self) -> bool:
        if self._online is not None:
            return self._exhausted
        return self._cursor >= len(self._order)

    def finalize(self, state: State) -> None:
        from porenet.kinds.invasion.kernels import trapping

        state.trapped[:] = trapping.enclosed_defender(
            self._indptr, self._neighbours, state.drained, self._outlet
        )

    def summary(self, state: State) -> dict[str, Any]:
        p = state.record.pressure[: state.record.size]
        steps = p[state.record.throat[: state.record.size] >= 0]
        p_max = float(steps.max()) if steps.size else 0.0
        quantile = np.count_nonzero(self._entry <= p_max) / self._entry.size if steps.size else 0.0
        scale = self.context.scales.pressure
        return {
            "max_entry_pressure": p_max * scale,
            "max_entry_pressure_quantile": quantile,
        }
