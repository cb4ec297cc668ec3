"""The paper's deformable medium: prestressed blocks and Hertzian springs (docs/model.md §5)."""

from __future__ import annotations

from typing import Any

import numpy as np

from porenet.analysis.numbers import fracturing_number, modulus_for
from porenet.core.errors import ConfigError, NumericalError
from porenet.core.interfaces import Lattice, RunContext, SolidModel
from porenet.core.state import State
from porenet.kinds.hertz.config import HertzConfig
from porenet.kinds.hertz.kernels.springs import Stat


def scaled_modulus(config: HertzConfig, lattice: Lattice, context: RunContext) -> float:
    """E* in units of gamma / a, from ``modulus`` or from ``fracturing_number`` (Eq. 2)."""
    if config.modulus is not None:
        return float(config.modulus) / context.scales.pressure
    disorder = getattr(lattice.config, "disorder", None)
    if disorder is None:
        raise ConfigError(
            "solid.fracturing_number needs the lattice's 'disorder' (lambda) to derive E*; "
            "this lattice has none (give solid.modulus instead)"
        )
    assert config.fracturing_number is not None
    return modulus_for(config.fracturing_number, 1.0, float(disorder), 1.0, config.prestrain)


class HertzSolid(SolidModel):
    """Prestressed block-and-spring network with Hertzian contacts and no tension.

    Writes ``state.spring_compression`` (h / a), ``state.spring_force`` (gamma a),
    ``state.displacement`` ((n_particles, 2), a) and, through :meth:`update`, returns the
    aperture changes (a) that the Coupler applies. The update is
    :mod:`porenet.kinds.hertz.kernels.springs`: force balance on every free particle, linearised
    about the current state, with contacts that open at ``h <= 0`` (and close again at ``h > 0``
    under ``recontact = 'restore'``) iterated within the update.
    """

    config: HertzConfig

    def __init__(self, config: HertzConfig, lattice: Lattice, context: RunContext) -> None:
        from porenet.kinds.hertz.kernels import springs as mk

        super().__init__(config, lattice, context)
        self.modulus = scaled_modulus(config, lattice, context)
        try:
            xy = np.ascontiguousarray(lattice.particle_coords, dtype=np.float64)
            springs = np.ascontiguousarray(lattice.spring_particles, dtype=np.int64)
            pair_pore, pair_particle = lattice.pore_particle_pairs
            fixed = np.ascontiguousarray(lattice.fixed_particles, dtype=bool)
        except NotImplementedError as exc:
            raise ConfigError(
                f"solid kind 'hertz' needs a lattice that describes its particles: {exc}"
            ) from None
        if springs.shape != (lattice.n_throats, 2):
            raise ConfigError(
                f"lattice {type(lattice).__name__}: spring_particles has shape {springs.shape}, "
                f"expected ({lattice.n_throats}, 2) (one spring per throat)"
            )
        self._xy, self._springs, self._fixed = xy, springs, fixed
        self._axis = mk.spring_axes(springs, xy)
        self._pair_pore = np.ascontiguousarray(pair_pore, dtype=np.int64)
        self._pair_particle = np.ascontiguousarray(pair_particle, dtype=np.int64)
        self._pair_dir = mk.pore_particle_directions(
            self._pair_pore, self._pair_particle, np.asarray(lattice.pore_coords), xy
        )
        self._chains = None
        if self._wants_chains():
            from porenet.kinds.hertz.kernels import chains as ck

            self._chains = ck.find_chains(springs, self._axis, fixed)
            if self._chains is None and config.solver == "chains":
                raise ConfigError(
                    "solid.solver = 'chains' needs every spring along x or y and every line of "
                    "springs to end at fixed particles; this lattice does not (use "
                    "'sparse-direct' or 'auto')"
                )
        if self._chains is not None:
            order = np.argsort(self._pair_pore, kind="stable")
            self._pair_pore = self._pair_pore[order]
            self._pair_particle = self._pair_particle[order]
            self._pair_dir = np.ascontiguousarray(self._pair_dir[order])
            self._pair_ptr = np.searchsorted(self._pair_pore, np.arange(lattice.n_pores + 1))
            self._particle_chain = ck.particle_chains(self._chains, len(xy))
            self._contacts = ck.PoreContacts(self._pair_ptr, self._pair_particle, self._pair_dir,
                                             float(config.pressure_area_factor))  # fmt: skip
        self.h0 = 2.0 * config.prestrain
        self.k0 = float(mk.hertz_stiffness(self.h0, self.modulus))
        self.disorder = getattr(lattice.config, "disorder", None)

    def _wants_chains(self) -> bool:
        """Whether to look for chains (the line-by-line solver) when the solid is built."""
        return self.config.solver in ("auto", "chains")

    @property
    def compliance(self) -> float:
        """``A_p / K_0`` (a per gamma/a): the change of one spring's compression under a
        pressure change of 1 gamma/a in one of its pores, at the prestress stiffness."""
        return self.config.pressure_area_factor / self.k0

    @property
    def solver(self) -> str:
        """The linear solver in use: 'chains' or 'sparse-direct'."""
        return "chains" if self._chains is not None else "sparse-direct"

    def setup(self, state: State) -> None:
        from porenet.kinds.hertz.kernels.springs import ApertureMap, ContactLaw, hertz_force

        m = self._springs.shape[0]
        state.spring_compression = np.full(m, self.h0)
        state.spring_force = hertz_force(state.spring_compression, self.modulus)
        state.displacement = np.zeros_like(self._xy)
        self._mode = np.zeros(m, dtype=np.int8)
        self._load = np.zeros_like(self._xy)  # fluid forces of the pressures `_seen`
        self._seen = np.zeros(state.n_pores)  # the prestress balances zero pore pressure
        self._changed = np.zeros(m, dtype=np.int64)
        if self._chains is not None:
            self._dirty = np.zeros(len(self._chains.chain_axis), dtype=bool)
        mean = float(self.lattice.mean_aperture)
        self._floor = self.config.aperture_floor * mean
        self._cap = self.config.aperture_cap * mean
        self._at_floor = np.zeros(m, dtype=bool)
        self._at_cap = np.zeros(m, dtype=bool)
        #: Apertures the particle positions give, before the floor and the cap (a).
        self.geometric_apertures = np.array(state.apertures, dtype=np.float64, copy=True)
        #: From the compressions to the apertures the fluid sees (floor, cap).
        self.aperture_map = ApertureMap(self.geometric_apertures, state.apertures, self._floor,
                                        self._cap, self._at_floor, self._at_cap)  # fmt: skip
        cfg = self.config
        self.law = ContactLaw(
            modulus=self.modulus,
            cohesion_stiffness=cfg.cohesion * self.k0,
            contact_stiffness=self.k0,
            foundation_stiffness=cfg.foundation * self.k0,
            recontact=cfg.recontact == "restore",
            max_iterations=cfg.max_contact_iterations,
        )
        self._stats = np.zeros(len(Stat))
        self.updates = 0
        self.chains_solved = 0
        self.n_removed = 0
        self.largest_residual = 0.0
        self.contact_iterations = 0
        self.unsettled = 0
        self._series: dict[str, list[float]] = {
            "time": [],
            "drained": [],
            "removed_springs": [],
            "max_aperture_change": [],
            "balance_residual": [],
        }

    def update(
        self, state: State, pore_pressure: np.ndarray, tolerance: float = 0.0
    ) -> np.ndarray | None:
        """Balance forces under ``pore_pressure`` (gamma/a) and write the new compressions,
        forces, displacements and apertures (each bounded by the aperture floor and cap).

        A pore's pressure reaches its particles only once it moved by more than
        ``tolerance K_0 / A_p`` since it last did (a change that would deform a spring by at
        most ``tolerance``, in units of a; 0 is exact), and only the lines of springs through
        those particles are solved (with chains; the sparse solver always solves all).

        Returns
        -------
        ndarray of int64 or None
            The throats whose aperture changed (None: possibly all).
        """
        if self._chains is not None:
            changed = self._update_chains(state, pore_pressure, tolerance)
            if changed is None:  # no pore's pressure moved beyond the tolerance
                return np.zeros(0, dtype=np.int64)
        else:
            changed = self._update_sparse(state, pore_pressure)
        self.updates += 1
        series = self._series
        series["time"].append(state.time)
        series["drained"].append(float(state.n_drained))
        series["removed_springs"].append(float(self.n_removed))
        stats = self._stats
        series["max_aperture_change"].append(float(stats[Stat.LARGEST_CHANGE]))
        series["balance_residual"].append(float(stats[Stat.RESIDUAL]))
        self.largest_residual = max(self.largest_residual, float(stats[Stat.RESIDUAL]))
        self.contact_iterations = max(self.contact_iterations, int(stats[Stat.ITERATIONS]))
        self.unsettled += int(stats[Stat.UNSETTLED])
        return changed

    def _numerical_error(self, state: State, what: str) -> NumericalError:
        return NumericalError(
            f"hertz solid: non-finite {what} in mechanical update {self.updates + 1} after "
            f"{state.n_drained} drained pores (t = {state.time:g} scaled)"
        )

    def _update_chains(
        self, state: State, pore_pressure: np.ndarray, tolerance: float
    ) -> np.ndarray | None:
        """Refresh the loads and solve the lines they changed; None if no pore was refreshed."""
        from porenet.kinds.hertz.kernels import chains as ck

        cfg = self.config
        assert self._chains is not None and state.displacement is not None
        threshold = tolerance * self.k0 / cfg.pressure_area_factor if tolerance > 0 else 0.0
        refreshed = ck.refresh_loads(pore_pressure, self._seen, threshold, self._contacts,
                                     self._load, self._particle_chain, self._dirty)  # fmt: skip
        if refreshed == 0:
            return None
        stats = self._stats
        ck.solve_chains(
            self._chains, self._xy, self._load, self._dirty, self._spring_state(state), self.law,
            state.displacement, self.aperture_map, self._changed, stats,
        )  # fmt: skip
        if stats[Stat.FINITE] == 0:
            raise self._numerical_error(state, "displacement")
        self.chains_solved += int(stats[Stat.SOLVED])
        self.n_removed += int(stats[Stat.OPENED])
        return self._changed[: int(stats[Stat.CHANGED])]

    def _spring_state(self, state: State) -> Any:
        """The springs' compressions and forces (in the State) and modes, as the kernels take
        them (:class:`porenet.kinds.hertz.kernels.springs.SpringState`)."""
        from porenet.kinds.hertz.kernels.springs import SpringState

        return SpringState(state.spring_compression, state.spring_force, self._mode)

    def _update_sparse(self, state: State, pore_pressure: np.ndarray) -> None:
        from porenet.kinds.hertz.kernels import springs as mk

        cfg = self.config
        h, force = state.spring_compression, state.spring_force
        assert h is not None and force is not None and state.displacement is not None
        mk.pressure_loads(
            pore_pressure, self._pair_pore, self._pair_particle, self._pair_dir,
            cfg.pressure_area_factor, self._load,
        )  # fmt: skip
        k_f = self.law.foundation_stiffness
        springs = self._spring_state(state)
        du, dh, force_new, iterations, unsettled = mk.solve_sparse(
            self._springs, self._axis, self._fixed, self._load, springs, self.law,
            state.displacement,
        )  # fmt: skip
        largest, finite = mk.apply_update(dh, force_new, du, springs, state.displacement,
                                          self.aperture_map)  # fmt: skip
        if not finite:
            raise self._numerical_error(state, "displacement or force")
        self.n_removed = int(np.count_nonzero(self._mode == mk.OPEN))
        residual = mk.balance_residual(
            self._load, force, self._springs, self._axis, self._fixed, state.displacement, k_f
        )
        stats = self._stats
        stats[:] = 0.0
        stats[Stat.ITERATIONS] = iterations
        stats[Stat.UNSETTLED] = unsettled
        stats[Stat.RESIDUAL] = residual
        stats[Stat.LARGEST_CHANGE] = largest
        stats[Stat.FINITE] = 1.0

    @property
    def removed(self) -> np.ndarray:
        """(M,) bool: springs currently open (removed: no contact)."""
        from porenet.kinds.hertz.kernels.springs import OPEN

        return self._mode == OPEN

    def summary(self, state: State) -> dict[str, Any]:
        """Scalars for ``/summary`` (SI)."""
        sc = self.context.scales
        out: dict[str, Any] = {
            "modulus": self.modulus * sc.pressure,
            "prestrain": self.config.prestrain,
            "foundation": self.config.foundation,
            "springs_removed": self.n_removed,
            "mechanical_updates": self.updates,
            "mechanics_solver": self.solver,
            "largest_balance_residual": self.largest_residual * sc.pressure * sc.area,
            "mechanics_lines_solved": self.chains_solved,
            "largest_contact_iterations": self.contact_iterations,
            "unsettled_updates": self.unsettled,
            "apertures_at_floor": int(self._at_floor.sum()),
            "apertures_at_cap": int(self._at_cap.sum()),
        }
        if self.disorder is not None:
            # Eq. 2 in scaled units (gamma = a = 1)
            out["fracturing_number"] = fracturing_number(
                1.0, float(self.disorder), 1.0, self.modulus, self.config.prestrain
            )
        return out

    def fields(self, state: State) -> dict[str, np.ndarray]:
        """Copies of the solid fields now (scaled)."""
        return {
            "spring_compression": np.asarray(state.spring_compression).copy(),
            "spring_force": np.asarray(state.spring_force).copy(),
            "removed_springs": self.removed.copy(),
            "displacement": np.asarray(state.displacement).copy(),
        }

    def snapshot(self, state: State) -> dict[str, np.ndarray]:
        return {"apertures": state.apertures.copy(), **self.fields(state)}

    def outputs(self, state: State) -> dict[str, Any]:
        """Final solid fields and the per-update series, scaled (the Simulation converts)."""
        return {
            "final": self.fields(state),
            "series": {k: np.asarray(v, dtype=np.float64) for k, v in self._series.items()},
        }
