"""The ``linear.springs`` solid: the block-and-spring network of docs/model.md section 5 with
linear (Hookean) contacts, the mechanics in :mod:`porenet_linear.springs`."""

from __future__ import annotations

from typing import Any

import numpy as np

from porenet.core.errors import ConfigError, NumericalError
from porenet.core.interfaces import Lattice, RunContext, SolidModel
from porenet.core.state import State
from porenet_linear import springs as sp
from porenet_linear.config import LinearSpringsConfig


def scaled_stiffness(config: LinearSpringsConfig, lattice: Lattice, context: RunContext) -> float:
    """The contact stiffness k in units of gamma (porenet's force gamma a per length a), from
    ``stiffness`` (N/m) or from ``fracturing_number`` and the lattice's disorder."""
    if config.stiffness is not None:
        gamma = context.scales.pressure * context.scales.length  # (gamma / a) a, N/m
        return float(config.stiffness) / gamma
    disorder = getattr(lattice.config, "disorder", None)
    if disorder is None:
        raise ConfigError(
            "solid.fracturing_number needs the lattice's 'disorder' (lambda) to derive k; "
            "this lattice has none (give solid.stiffness instead)"
        )
    assert config.fracturing_number is not None
    return sp.stiffness_for(config.fracturing_number, float(disorder))


class LinearSprings(SolidModel):
    """Prestressed block-and-spring network with linear contacts and no tension.

    Writes ``state.spring_compression`` (overlap h, a), ``state.spring_force`` (gamma a),
    ``state.displacement`` ((n_particles, 2), a, from the prestressed state) and, in place,
    ``state.apertures`` (a, bounded by the aperture floor and cap); :meth:`update` returns
    the throats whose aperture changed. Every update solves force balance from scratch
    (:func:`porenet_linear.springs.solve`): nothing accumulates between updates.
    """

    config: LinearSpringsConfig

    def __init__(self, config: LinearSpringsConfig, lattice: Lattice, context: RunContext) -> None:
        super().__init__(config, lattice, context)
        self.stiffness = scaled_stiffness(config, lattice, context)
        try:
            self.net = sp.network(lattice)
        except NotImplementedError as exc:
            raise ConfigError(
                f"solid kind 'linear.springs' needs a lattice that describes its particles: {exc}"
            ) from None
        if self.net.springs.shape != (lattice.n_throats, 2):
            raise ConfigError(
                f"lattice {type(lattice).__name__}: {len(self.net.springs)} springs for "
                f"{lattice.n_throats} throats (the solid needs one spring per throat)"
            )
        self.h0 = 2.0 * config.prestrain
        self.disorder = getattr(lattice.config, "disorder", None)

    @property
    def compliance(self) -> float:
        """``A_p / k`` (a per gamma/a): a contact's compression under a pressure change of
        1 gamma/a in one of its pores (the adaptive coupler's measure)."""
        return self.config.pressure_area_factor / self.stiffness

    def setup(self, state: State) -> None:
        """The prestressed state: every contact at ``h_0`` with force ``k h_0``, which
        balances zero pore pressure."""
        m, n_particles = len(self.net.springs), self.net.b.shape[1] // 2
        state.spring_compression = np.full(m, self.h0)
        state.spring_force = np.full(m, self.stiffness * self.h0)
        state.displacement = np.zeros((n_particles, 2))
        self.closed = np.ones(m, dtype=bool)
        self.initial_apertures = state.apertures.copy()
        mean = float(self.lattice.mean_aperture)
        self.bounds = (self.config.aperture_floor * mean, self.config.aperture_cap * mean)
        self.updates = 0
        self.unsettled = 0
        self.largest_iterations = 0
        self.largest_residual = 0.0
        self.series: dict[str, list[float]] = {
            "time": [], "drained": [], "removed_springs": [], "max_aperture_change": [],
            "balance_residual": [],
        }  # fmt: skip

    def update(
        self, state: State, pore_pressure: np.ndarray, tolerance: float = 0.0
    ) -> np.ndarray | None:
        """Balance forces under ``pore_pressure`` (gamma/a, every pore) and write the solid
        fields and the apertures. Always exact: ``tolerance`` is not used (the coupler's
        adaptive schedule still skips updates by :attr:`compliance`)."""
        cfg = self.config
        load = sp.pressure_loads(self.net, pore_pressure, cfg.pressure_area_factor)
        sol = sp.solve(self.net, load, self.h0, self.stiffness, cfg.cohesion, self.closed,
                       cfg.max_contact_iterations)  # fmt: skip
        if not (np.all(np.isfinite(sol.displacement)) and np.all(np.isfinite(sol.force))):
            raise NumericalError(
                f"linear.springs: non-finite displacement in mechanical update "
                f"{self.updates + 1} after {state.n_drained} drained pores"
            )
        residual = sp.net_forces(self.net, load, sol.force)[self.net.free]
        new = np.clip(sp.aperture(sol.compression, self.h0, self.initial_apertures), *self.bounds)
        changed = np.flatnonzero(new != state.apertures)
        largest = float(np.abs(new - state.apertures).max(initial=0.0))
        state.apertures[:] = new
        state.spring_compression[:] = sol.compression
        state.spring_force[:] = sol.force
        state.displacement[:] = sol.displacement.reshape(-1, 2)
        self.closed = sol.closed
        self.updates += 1
        self.unsettled += not sol.settled
        self.largest_iterations = max(self.largest_iterations, sol.iterations)
        self.largest_residual = max(self.largest_residual, float(np.abs(residual).max()))
        for name, value in (("time", state.time), ("drained", state.n_drained),
                            ("removed_springs", np.count_nonzero(~sol.closed)),
                            ("max_aperture_change", largest),
                            ("balance_residual", float(np.abs(residual).max()))):  # fmt: skip
            self.series[name].append(float(value))
        return changed

    def summary(self, state: State) -> dict[str, Any]:
        """Scalars for ``/summary`` (SI): ``stiffness`` (N/m), ``fracturing_number`` (when
        the lattice has a disorder), ``largest_balance_residual`` (N), counts."""
        sc = self.context.scales
        lo, hi = self.bounds
        out: dict[str, Any] = {
            "stiffness": self.stiffness * sc.pressure * sc.length,
            "prestrain": self.config.prestrain,
            "springs_removed": int(np.count_nonzero(~self.closed)),
            "mechanical_updates": self.updates,
            "mechanics_solver": "sparse-direct",
            "largest_balance_residual": self.largest_residual * sc.pressure * sc.area,
            "largest_contact_iterations": self.largest_iterations,
            "unsettled_updates": self.unsettled,
            "apertures_at_floor": int(np.count_nonzero(state.apertures <= lo)),
            "apertures_at_cap": int(np.count_nonzero(state.apertures >= hi)),
        }
        if self.disorder is not None:
            out["fracturing_number"] = sp.fracturing_number(self.stiffness, float(self.disorder))
        return out

    def fields(self, state: State) -> dict[str, np.ndarray]:
        """Copies of the solid fields now (scaled)."""
        return {
            "spring_compression": np.asarray(state.spring_compression).copy(),
            "spring_force": np.asarray(state.spring_force).copy(),
            "removed_springs": ~self.closed,
            "displacement": np.asarray(state.displacement).copy(),
        }

    def snapshot(self, state: State) -> dict[str, np.ndarray]:
        return {"apertures": state.apertures.copy(), **self.fields(state)}

    def outputs(self, state: State) -> dict[str, Any]:
        """Final solid fields and the per-update series, scaled (the Simulation converts)."""
        return {
            "final": self.fields(state),
            "series": {k: np.asarray(v, dtype=np.float64) for k, v in self.series.items()},
        }
