"""The frictional solid: Hertz normal contacts with a tangential (Mindlin) stiffness and
optional Coulomb sliding (docs/model.md, "Frictional solid (kind hertz-mindlin)")."""

from __future__ import annotations

import time
from typing import Any

import numpy as np

from porenet.core.errors import ConfigError, NumericalError
from porenet.core.interfaces import Lattice, RunContext
from porenet.core.state import State
from porenet.kinds.hertz.kernels.springs import Stat
from porenet.kinds.hertz.model import HertzSolid
from porenet.kinds.mindlin.config import HertzMindlinConfig

#: The apertures the fluid sees follow the geometric ones once they lag by this fraction of
#: the solver's tolerance (a global solve moves every contact a little; docs/model.md,
#: "Frictional solid (kind hertz-mindlin)").
APERTURE_LAG = 0.01


#: A displacement this many lattice widths is a runaway (:meth:`HertzMindlinSolid.
#: _check_bounded`).
RUNAWAY = 1e6


class HertzMindlinSolid(HertzSolid):
    """The :class:`~porenet.kinds.hertz.model.HertzSolid` with frictional contacts.

    Each contact also carries a tangential force ``S`` with stiffness ``K_t = r_t K`` (``K``
    the Hertz tangent), capped by Coulomb's ``mu_f F`` where ``friction`` is given; a contact
    that opens loses both. Particle rotations are held (default) or solved. The update
    balances forces (and torques) on every free particle, with the contact iteration of
    :mod:`porenet.kinds.mindlin.kernels.frictional`, solved by multigrid
    (:mod:`porenet.kinds.mindlin.kernels.multigrid`; square lattice, rotations held) or by a
    sparse direct solver (:mod:`porenet.kinds.mindlin.kernels.frictional_sparse`).

    With ``r_t = 0`` it is the ``hertz`` solid, to the bit: every call goes to it.

    Writes, besides the Hertzian solid's fields, ``shear_force`` (gamma a), ``slip`` (a),
    ``sliding`` (bool) per spring and ``rotation`` (rad) per particle in its outputs.
    """

    config: HertzMindlinConfig

    @property
    def unresolved_deformation(self) -> float:
        """The multigrid's stopping tolerance plus the slip tolerance (units of ``a``): what
        the frictional solid leaves unresolved by design (docs/model.md, "Frictional solid
        (kind hertz-mindlin)", "Solver")."""
        return float(self.config.solver_tolerance) + float(self.config.slip_tolerance)

    def __init__(self, config: HertzMindlinConfig, lattice: Lattice, context: RunContext) -> None:
        self.stiffness_ratio = config.stiffness_ratio
        #: True when the contacts carry no tangential stiffness: the ``hertz`` solid exactly.
        self.frictionless = self.stiffness_ratio == 0.0
        super().__init__(config, lattice, context)
        if self.frictionless:
            return
        from porenet.kinds.hertz.kernels.chains import PoreContacts
        from porenet.kinds.mindlin.kernels.grid import find_grid

        self._grid = None
        if config.rotation == "held" and config.solver in ("auto", "multigrid"):
            self._grid = find_grid(self._xy, self._springs, self._fixed)
            if self._grid is None and config.solver == "multigrid":
                raise ConfigError(
                    "solid.solver = 'multigrid' needs the square lattice's layout (a full grid "
                    "of particles inside a fixed ring, springs between grid neighbours); this "
                    "lattice has none (use 'sparse-direct' or 'auto')"
                )
        order = np.argsort(self._pair_pore, kind="stable")
        pair_ptr = np.searchsorted(self._pair_pore[order], np.arange(lattice.n_pores + 1))
        self._contacts = PoreContacts(pair_ptr, np.ascontiguousarray(self._pair_particle[order]),
                                      np.ascontiguousarray(self._pair_dir[order]),
                                      float(config.pressure_area_factor))  # fmt: skip

    def _wants_chains(self) -> bool:
        return self.frictionless and self.config.solver != "sparse-direct"

    @property
    def solver(self) -> str:
        """The linear solver in use: 'chains', 'multigrid' or 'sparse-direct'."""
        if self.frictionless:
            return super().solver
        return "multigrid" if self._grid is not None else "sparse-direct"

    def setup(self, state: State) -> None:
        super().setup(state)
        if self.frictionless:
            return
        from porenet.kinds.mindlin.kernels import frictional as fr

        cfg = self.config
        m, n_particles = self._springs.shape[0], len(self._xy)
        self.shear = fr.ShearState(np.zeros(m), np.zeros(m), np.zeros(m, dtype=np.int8),
                                   np.ones(m))  # fmt: skip
        self.rotation = np.zeros(n_particles)
        self.friction_law = fr.FrictionLaw(
            modulus=self.modulus,
            cohesion_stiffness=cfg.cohesion * self.k0,
            contact_stiffness=self.k0,
            foundation_stiffness=cfg.foundation * self.k0,
            recontact=cfg.recontact == "restore",
            stiffness_ratio=self.stiffness_ratio,
            friction=np.inf if cfg.friction is None else float(cfg.friction),
            rotation=cfg.rotation == "free",
            max_iterations=cfg.max_contact_iterations,
            slip_tolerance=cfg.slip_tolerance,
        )
        self._work = fr.increments(m)
        self._force = np.zeros((n_particles, 2))
        self._torque = np.zeros(n_particles)
        self._du = np.zeros((n_particles, 2))
        self._dtheta = np.zeros(n_particles)
        self._no_chain = np.full((n_particles, 2), -1, dtype=np.int64)
        self._no_dirty = np.zeros(0, dtype=bool)
        #: The contacts' largest prestress force F_0 (gamma a), to judge loads by.
        self.prestress_force = float(np.max(state.spring_force))
        #: Round-off in the force balance: relative to the prestress force F_0.
        self.force_tolerance = 1e-12 * max(self.prestress_force, 1.0)
        #: The lattice's width (a), which :meth:`_check_bounded` judges displacements by.
        self._extent = float(max(np.ptp(self._xy[:, 0]), np.ptp(self._xy[:, 1])))
        self.solver_iterations = 0
        self.unconverged_solves = 0
        self.hierarchy_builds = 0
        self.largest_sliding = 0
        #: Contacts frozen for the rest of an update after cycling between modes, and
        #: contacts that started an update re-forming (left in contact at h <= 0), summed
        #: over the updates (docs/model.md, "Frictional solid": "Solver").
        self.frozen_contacts = 0
        self.reformed_at_start = 0
        #: Wall time spent in updates that solved something (s).
        self.seconds = 0.0
        #: How far (a) the apertures the fluid sees may lag the geometric ones: a hundredth of
        #: the solver's tolerance (0, exact, when it solves to round-off).
        self.aperture_lag = APERTURE_LAG * cfg.solver_tolerance
        self._series["sliding_contacts"] = []
        self._series["solver_iterations"] = []
        if self._grid is not None:
            from porenet.kinds.mindlin.grid_solver import GridSolver

            self._grid_solver = GridSolver(
                self._grid, cfg.solver_tolerance, self.force_tolerance, cfg.max_solver_iterations
            )
        else:
            from porenet.kinds.mindlin.kernels import frictional_sparse

            self._pattern = frictional_sparse.pattern(self._springs, self._axis, self._fixed,
                                                      cfg.rotation == "free")  # fmt: skip

    # -- an update ---------------------------------------------------------------------------

    def update(
        self, state: State, pore_pressure: np.ndarray, tolerance: float = 0.0
    ) -> np.ndarray | None:
        """Balance forces (and torques) under ``pore_pressure`` (gamma/a): see
        :meth:`HertzSolid.update`; a pore's pressure reaches its particles once it moved by
        more than ``tolerance K_0 / A_p`` since it last did."""
        if self.frictionless:
            return super().update(state, pore_pressure, tolerance)
        from porenet.kinds.hertz.kernels.chains import refresh_loads

        area = self.config.pressure_area_factor
        threshold = tolerance * self.k0 / area if tolerance > 0 else 0.0
        refreshed = refresh_loads(pore_pressure, self._seen, threshold, self._contacts,
                                  self._load, self._no_chain, self._no_dirty)  # fmt: skip
        if refreshed == 0 and self.updates > 0:
            return np.zeros(0, dtype=np.int64)
        start = time.perf_counter()
        changed = self._solve_and_apply(state)
        self.seconds += time.perf_counter() - start
        self.updates += 1
        stats, series = self._stats, self._series
        series["time"].append(state.time)
        series["drained"].append(float(state.n_drained))
        series["removed_springs"].append(float(self.n_removed))
        series["max_aperture_change"].append(float(stats[Stat.LARGEST_CHANGE]))
        series["balance_residual"].append(float(stats[Stat.RESIDUAL]))
        series["sliding_contacts"].append(float(self._sliding))
        series["solver_iterations"].append(float(self._iterations))
        self.largest_residual = max(self.largest_residual, float(stats[Stat.RESIDUAL]))
        self.contact_iterations = max(self.contact_iterations, int(stats[Stat.ITERATIONS]))
        self.unsettled += int(stats[Stat.UNSETTLED])
        return changed

    def _solve_and_apply(self, state: State) -> np.ndarray:
        """The contact iteration of one update (module docstring of
        :mod:`porenet.kinds.mindlin.kernels.frictional`), then its result applied."""
        from porenet.kinds.mindlin.kernels import frictional as fr

        law, work = self.friction_law, self._work
        springs = self._spring_state(state)
        assert state.displacement is not None
        self.reformed_at_start += fr.start_update(springs, self.shear, law, work)
        iterations, unsettled, solves = 0, 0, 0
        self._du[:] = 0.0
        self._dtheta[:] = 0.0
        while True:
            iterations += 1
            fr.trial_laws(springs, self.shear, law, work)
            fr.out_of_balance(self._load, state.displacement, self._springs, self._axis,
                              work.normal_base, work.shear_base, law.foundation_stiffness,
                              self._force, self._torque)  # fmt: skip
            solves += self._solve_increments(work)
            fr.solved_increments(self._springs, self._axis, self._du, self._dtheta, work)
            last = iterations >= law.max_iterations
            if fr.next_modes(springs, self.shear, law, work, not last) == 0:
                break
            if last:  # applied with the modes of this last solve; its imbalance is carried
                unsettled = 1
                break
        self.frozen_contacts += int(np.count_nonzero(work.flips >= fr.MAX_FLIPS))
        n_changed, largest, opened, sliding, finite = fr.apply_increments(
            springs, self.shear, law, work, self._du, self._dtheta, state.displacement,
            self.rotation, self.aperture_map, self._changed, self.aperture_lag,
        )  # fmt: skip
        if not finite:
            raise self._numerical_error(state, "displacement, rotation or force")
        fr.out_of_balance(self._load, state.displacement, self._springs, self._axis,
                          state.spring_force, self.shear.force, law.foundation_stiffness,
                          self._force, self._torque)  # fmt: skip
        residual = fr.largest_imbalance(self._force, self._torque, self._fixed, law.rotation)
        self._check_bounded(state, sliding)
        self.n_removed += opened
        self._sliding = sliding
        self.largest_sliding = max(self.largest_sliding, sliding)
        self._iterations = solves
        self.solver_iterations += solves
        stats = self._stats
        stats[:] = 0.0
        stats[Stat.ITERATIONS] = iterations
        stats[Stat.UNSETTLED] = unsettled
        stats[Stat.RESIDUAL] = residual
        stats[Stat.CHANGED] = n_changed
        stats[Stat.LARGEST_CHANGE] = largest
        stats[Stat.FINITE] = 1.0
        return self._changed[:n_changed].copy()

    def _check_bounded(self, state: State, sliding: int) -> None:
        """A particle that moved :data:`RUNAWAY` times further than the lattice is wide is a
        runaway, not a result (a crushed solid, N_f = 1e3, moves ~1e2 lattice widths and is
        flagged as suspect instead): raise, naming the update (docs/stability.md, "Frictional
        contacts")."""
        assert state.displacement is not None
        extent = self._extent
        u = state.displacement
        largest = max(float(u.max()), -float(u.min()))  # no temporary: every update
        if not largest <= RUNAWAY * extent:
            load = float(np.max(np.hypot(self._load[:, 0], self._load[:, 1])))
            raise NumericalError(
                f"hertz-mindlin solid: runaway displacement ({largest:.3g} a, over {RUNAWAY:g} "
                f"times the lattice's {extent:.3g} a) in mechanical update {self.updates + 1} "
                f"after {state.n_drained} drained pores (t = {state.time:g} scaled), {sliding} "
                f"contacts sliding; the largest pressure load on a particle is "
                f"{load / self.prestress_force:.3g} times the contacts' prestress force: the "
                "contact iteration found no bounded equilibrium (docs/stability.md, "
                '"Frictional contacts", on loads far beyond the prestress)'
            )

    def _solve_increments(self, work: Any) -> int:
        """Solve the linear system of the current trial laws for the increments (from the
        previous contact iteration's, if any); returns the solver's iterations (1 for a direct
        solve)."""
        law = self.friction_law
        if self._grid is None:
            from porenet.kinds.mindlin.kernels import frictional_sparse

            frictional_sparse.solve(self._pattern, work.normal_stiffness, work.shear_stiffness,
                                    law.foundation_stiffness, self._force, self._torque,
                                    self._du, self._dtheta)  # fmt: skip
            return 1
        solver = self._grid_solver
        try:
            iterations, converged, rebuilt = solver.solve(
                work.normal_stiffness, work.shear_stiffness, law.foundation_stiffness,
                self._force, self._du,
            )  # fmt: skip
        except (ZeroDivisionError, np.linalg.LinAlgError) as exc:
            stiff = work.normal_stiffness / self.k0
            raise NumericalError(
                f"hertz-mindlin solid: the multigrid found the stiffness matrix singular ({exc}) "
                f"in mechanical update {self.updates + 1}; normal contact stiffnesses from "
                f"{stiff.min():.3g} to {stiff.max():.3g} K_0 "
                '(docs/stability.md, "Frictional contacts")'
            ) from None
        self.hierarchy_builds += rebuilt
        if not converged:
            self.unconverged_solves += 1
        return iterations

    # -- records -----------------------------------------------------------------------------

    def summary(self, state: State) -> dict[str, Any]:
        out = super().summary(state)
        out["shear_stiffness_ratio"] = self.stiffness_ratio
        if self.frictionless:
            return out
        cfg, sc = self.config, self.context.scales
        out.update(
            friction=-1.0 if cfg.friction is None else float(cfg.friction),
            rotation=cfg.rotation,
            mechanics_solver=self.solver,
            solver_tolerance=cfg.solver_tolerance,
            slip_tolerance=cfg.slip_tolerance,
            solver_iterations=self.solver_iterations,
            unconverged_solves=self.unconverged_solves,
            multigrid_builds=self.hierarchy_builds,
            mechanics_time_s=self.seconds,
            sliding_contacts=int(np.count_nonzero(self.shear.mode)),
            largest_sliding_contacts=self.largest_sliding,
            frozen_contacts=self.frozen_contacts,
            contacts_reformed_at_start=self.reformed_at_start,
            prestress_force=self.prestress_force * sc.pressure * sc.area,
        )
        return out

    def fields(self, state: State) -> dict[str, np.ndarray]:
        out = super().fields(state)
        if self.frictionless:
            return out
        out.update(
            shear_force=self.shear.force.copy(),
            slip=self.shear.slip.copy(),
            sliding=self.shear.mode.astype(bool),
            rotation=self.rotation.copy(),
        )
        return out
