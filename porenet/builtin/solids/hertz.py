"""The paper's deformable medium: prestressed blocks and Hertzian springs (MODEL.md section 5)."""

from __future__ import annotations

import math
from typing import Any, ClassVar, Literal

import numpy as np
from pydantic import Field, model_validator

from porenet.config.base import ModelConfig
from porenet.core.errors import ConfigError, NumericalError
from porenet.core.interfaces import Lattice, RunContext, SolidModel
from porenet.core.state import State


class HertzConfig(ModelConfig):
    """Block-and-spring network with Hertzian contacts, prestressed in compression, no tension.

    Give the stiffness either as ``modulus`` (E*, Pa) or as ``fracturing_number``
    (N_f = gamma / (lambda a E* eps_0^(1/2)), Eq. 2 of the paper), not both.
    """

    kind: Literal["hertz"] = "hertz"
    modulus: float | None = Field(
        None, gt=0, description="Constrained Young modulus E* of the particles (Pa)."
    )
    fracturing_number: float | None = Field(
        None,
        gt=0,
        description="Fracturing number N_f = gamma / (lambda a E* eps_0^(1/2)) (-), from which "
        "E* is derived (needs the lattice's disorder lambda). Fracturing dominates for "
        "N_f >~ 1.",
    )
    prestrain: float = Field(
        0.05,
        gt=0,
        lt=1,
        description="Initial strain eps_0 = h_0 / 2a of every spring (-). Paper: 0.05.",
    )
    pressure_area_factor: float = Field(
        1.0, gt=0, description="c_p in the pressure force f_p = p A_p, A_p = c_p a^2 (-)."
    )
    cohesion: float = Field(
        1e-6,
        gt=0,
        le=1e-2,
        description="Stiffness of an open (removed) spring relative to the prestress stiffness "
        "K_0 = 2 E* sqrt(R* h_0) (-): the small cohesive regularisation that keeps a particle "
        "that lost its contacts solvable. Results do not depend on it (docs/model.md).",
    )
    boundary: Literal["fixed-ring"] = Field(
        "fixed-ring",
        description="Mechanical boundary: 'fixed-ring', the outer ring of particles (the "
        "lattice's fixed_particles) never moves (confinement).",
    )
    recontact: Literal["restore", "never"] = Field(
        "restore",
        description="'restore': a removed spring whose particles touch again (h > 0) is a "
        "contact again; 'never': a removed spring stays removed (particles may then overlap, "
        "bounded only by the aperture floor).",
    )
    aperture_floor: float = Field(
        0.01,
        gt=0,
        lt=1,
        description="Smallest aperture, as a fraction of the mean aperture (-): compaction "
        "that would close a throat further stops there and is counted in the summary.",
    )
    aperture_cap: float = Field(
        2.0,
        gt=1,
        description="Largest aperture, as a multiple of the mean aperture (-): particles may "
        "separate further, but the throat the fluid sees stops widening there (its "
        "conductance grows like r^4 and would stall the flow solver); counted in the summary.",
    )
    solver: Literal["auto", "chains", "sparse-direct"] = Field(
        "auto",
        description="Linear solver of each update: 'chains' (x and y decouple when every spring "
        "lies along x or y; each line of springs between fixed particles is a tridiagonal "
        "system, O(N)), 'sparse-direct' (any lattice: scipy SuperLU of the 2-D stiffness "
        "matrix) or 'auto' (chains when the lattice allows them).",
    )
    max_contact_iterations: int = Field(
        50,
        ge=1,
        description="Most solves per update while contacts open and close (-); an update that "
        "still changes after them is counted in the summary as unsettled.",
    )
    coupler: Literal["pressure-aperture"] = Field(
        "pressure-aperture",
        description="Coupler kind that passes pore pressures to the solid and apertures back.",
    )
    coupling: Literal["every-step", "interval", "adaptive"] = Field(
        "adaptive",
        description="When the solid is updated: 'every-step' (after every fluid step; for "
        "invasion percolation every drained pore, the quasi-static rule), 'interval' (every "
        "coupling_interval fluid steps) or 'adaptive' (after a fluid step that changed some "
        "pore pressure by more than coupling_tolerance since the last update).",
    )
    coupling_interval: int = Field(
        1, ge=1, description="Fluid steps between updates for coupling = 'interval' (-)."
    )
    coupling_tolerance: float = Field(
        0.05,
        gt=0,
        description="Largest pore-pressure change since the last update that 'adaptive' "
        "coupling lets pass, in units of the capillary pressure gamma / a (-).",
    )

    builds_nothing: ClassVar[bool] = False

    @model_validator(mode="after")
    def _exactly_one_stiffness(self) -> HertzConfig:
        if (self.modulus is None) == (self.fracturing_number is None):
            raise ValueError(
                "give exactly one of 'modulus' (E*, Pa) and 'fracturing_number' (N_f)"
                + (" (both were given)" if self.modulus is not None else "")
            )
        return self

    def effects(self) -> dict[str, bool]:
        return {"deformation": True, "contact_loss": True}


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
    return 1.0 / (float(config.fracturing_number) * float(disorder) * math.sqrt(config.prestrain))


def fracturing_number(modulus_scaled: float, disorder: float, prestrain: float) -> float:
    """Eq. 2: ``N_f = gamma / (lambda a E* eps_0^(1/2))`` with E* in units of gamma / a."""
    return 1.0 / (disorder * modulus_scaled * math.sqrt(prestrain))


class HertzSolid(SolidModel):
    """Prestressed block-and-spring network with Hertzian contacts and no tension.

    Writes ``state.spring_compression`` (h / a), ``state.spring_force`` (gamma a),
    ``state.displacement`` ((n_particles, 2), a) and, through :meth:`update`, returns the
    aperture changes (a) that the Coupler applies. The update is
    :mod:`porenet.kernels.mechanics`: force balance on every free particle, linearised about
    the current state, with contacts that open at ``h <= 0`` (and close again at ``h > 0``
    under ``recontact = 'restore'``) iterated within the update.
    """

    config: HertzConfig

    def __init__(self, config: HertzConfig, lattice: Lattice, context: RunContext) -> None:
        from porenet.kernels import mechanics as mk

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
        if config.solver in ("auto", "chains"):
            self._chains = mk.find_chains(springs, self._axis, fixed)
            if self._chains is None and config.solver == "chains":
                raise ConfigError(
                    "solid.solver = 'chains' needs every spring along x or y and every line of "
                    "springs to end at fixed particles; this lattice does not (use "
                    "'sparse-direct' or 'auto')"
                )
        self.h0 = 2.0 * config.prestrain
        self.k0 = float(mk.hertz_stiffness(self.h0, self.modulus))
        self.disorder = getattr(lattice.config, "disorder", None)

    @property
    def solver(self) -> str:
        """The linear solver in use: 'chains' or 'sparse-direct'."""
        return "chains" if self._chains is not None else "sparse-direct"

    def setup(self, state: State) -> None:
        from porenet.kernels import mechanics as mk

        m = self._springs.shape[0]
        state.spring_compression = np.full(m, self.h0)
        state.spring_force = mk.hertz_force(state.spring_compression, self.modulus)
        state.displacement = np.zeros_like(self._xy)
        self._mode = np.zeros(m, dtype=np.int8)
        self._load = np.zeros_like(self._xy)
        self._du = np.zeros_like(self._xy)
        self._dh = np.zeros(m)
        self._force_new = np.zeros(m)
        mean = float(self.lattice.mean_aperture)
        self._floor = self.config.aperture_floor * mean
        self._cap = self.config.aperture_cap * mean
        self._at_floor = np.zeros(m, dtype=bool)
        self._at_cap = np.zeros(m, dtype=bool)
        #: Apertures the particle positions give, before the floor and the cap (a).
        self.geometric_apertures = np.array(state.apertures, dtype=np.float64, copy=True)
        self.updates = 0
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

    def update(self, state: State, pore_pressure: np.ndarray) -> np.ndarray:
        """Balance forces under ``pore_pressure`` (gamma/a); apply and return the aperture
        changes (a), each throat bounded below by the aperture floor."""
        from porenet.kernels import mechanics as mk

        cfg = self.config
        h, force = state.spring_compression, state.spring_force
        assert h is not None and force is not None and state.displacement is not None
        mk.pressure_loads(
            pore_pressure, self._pair_pore, self._pair_particle, self._pair_dir,
            cfg.pressure_area_factor, self._load,
        )  # fmt: skip
        k_c = cfg.cohesion * self.k0
        recontact = cfg.recontact == "restore"
        if self._chains is not None:
            self._du[:] = 0.0
            iterations, unsettled = mk.solve_chains(
                *self._chains, self._xy, self._load, h, force, self._mode, self.modulus, k_c,
                self.k0, recontact, cfg.max_contact_iterations, self._du, self._dh,
                self._force_new,
            )  # fmt: skip
            du, dh, force_new = self._du, self._dh, self._force_new
        else:
            du, dh, force_new, iterations, unsettled = mk.solve_sparse(
                self._springs, self._axis, self._fixed, self._load, h, force, self._mode,
                self.modulus, k_c, self.k0, recontact, cfg.max_contact_iterations,
            )  # fmt: skip
        if not (np.all(np.isfinite(du)) and np.all(np.isfinite(force_new))):
            bad = (
                int(np.flatnonzero(~np.isfinite(du).all(axis=1))[0])
                if not np.all(np.isfinite(du))
                else -1
            )
            raise NumericalError(
                f"hertz solid: non-finite displacement (particle {bad}) in mechanical update "
                f"{self.updates + 1} after {state.n_drained} drained pores (t = {state.time:g} "
                f"scaled)"
            )
        self.geometric_apertures += mk.aperture_change(dh, h)
        target = self.geometric_apertures
        low, high = target < self._floor, target > self._cap
        self._at_floor |= low
        self._at_cap |= high
        r = state.apertures
        dr = np.clip(target, self._floor, self._cap) - r
        r += dr
        h += dh
        force[:] = force_new
        state.displacement += du
        residual = mk.balance_residual(self._load, force, self._springs, self._axis, self._fixed)
        self.updates += 1
        self.largest_residual = max(self.largest_residual, residual)
        self.contact_iterations = max(self.contact_iterations, int(iterations))
        self.unsettled += int(unsettled)
        series = self._series
        series["time"].append(state.time)
        series["drained"].append(float(state.n_drained))
        series["removed_springs"].append(float(self.removed.sum()))
        series["max_aperture_change"].append(float(np.max(np.abs(dr))) if dr.size else 0.0)
        series["balance_residual"].append(residual)
        return dr

    @property
    def removed(self) -> np.ndarray:
        """(M,) bool: springs currently open (removed: no contact)."""
        from porenet.kernels.mechanics import OPEN

        return self._mode == OPEN

    def summary(self, state: State) -> dict[str, Any]:
        """Scalars for ``/summary`` (SI)."""
        sc = self.context.scales
        out: dict[str, Any] = {
            "modulus": self.modulus * sc.pressure,
            "prestrain": self.config.prestrain,
            "springs_removed": int(self.removed.sum()),
            "mechanical_updates": self.updates,
            "mechanics_solver": self.solver,
            "largest_balance_residual": self.largest_residual * sc.pressure * sc.area,
            "largest_contact_iterations": self.contact_iterations,
            "unsettled_updates": self.unsettled,
            "apertures_at_floor": int(self._at_floor.sum()),
            "apertures_at_cap": int(self._at_cap.sum()),
        }
        if self.disorder is not None:
            out["fracturing_number"] = fracturing_number(
                self.modulus, float(self.disorder), self.config.prestrain
            )
        return out

    def outputs(self, state: State) -> dict[str, Any]:
        """Final solid fields and the per-update series, scaled (the Simulation converts)."""
        return {
            "final": {
                "spring_compression": np.asarray(state.spring_compression).copy(),
                "spring_force": np.asarray(state.spring_force).copy(),
                "removed_springs": self.removed.copy(),
                "displacement": np.asarray(state.displacement).copy(),
            },
            "series": {k: np.asarray(v, dtype=np.float64) for k, v in self._series.items()},
        }
