"""Config of the viscous drainage model, kind ``viscous``, and the ``integrator = "auto"`` rule.

Pure Python (pydantic and porenet's light modules), so that the scene schema, ``porenet
validate`` and ``porenet plan`` import no numerics; the model, :mod:`porenet.kinds.viscous.model`,
is imported only when a scene builds it. :func:`auto_integrator` is here too: the cost
estimate (:mod:`porenet.kinds.viscous.cost`) applies the same rule as the model.
"""

from __future__ import annotations

from typing import Any, Literal

from pydantic import Field, model_validator

from porenet.config.base import ModelConfig

#: ``integrator = "auto"``: the stabilised (RKC) integrator once the explicit one would need
#: more than this many steps per drained pore, the implicit one once it would need more than
#: :data:`AUTO_IMPLICIT_PER_PORE` times the number of pores N (docs/performance.md).
AUTO_RKC_STEPS = 50.0
AUTO_IMPLICIT_PER_PORE = 50.0


def auto_integrator(explicit_steps_per_drained: float, n_pores: int) -> str:
    """What ``integrator = 'auto'`` picks under rate control, from the explicit integrator's
    steps per drained pore (see
    :meth:`porenet.kinds.viscous.model.ViscousDrainage._choose_integrator`; the cost model of
    :mod:`porenet.core.cost` applies the same rule)."""
    if explicit_steps_per_drained > AUTO_IMPLICIT_PER_PORE * n_pores:
        return "implicit"
    return "rkc" if explicit_steps_per_drained > AUTO_RKC_STEPS else "explicit"


class ViscousConfig(ModelConfig):
    """Inviscid invader at one pressure displacing a viscous defender (Holtzman & Juanes 2010).

    The defender's pore pressures evolve with the effective compressibility ``c_t = a/gamma``
    and Darcy fluxes; menisci advance from drained pores once the pressure difference exceeds
    the entry pressure ``2 gamma / r``; the outer edge drains to a reservoir at p = 0.
    """

    kind: Literal["viscous"] = "viscous"
    viscosity: float = Field(
        1e-3, gt=0, description="Viscosity mu of the defending fluid (Pa s). Paper: 1e-3."
    )
    interfacial_tension: float = Field(
        0.07, gt=0, description="Interfacial tension gamma (N/m). Paper: 0.07 N/m."
    )
    control: Literal["rate", "pressure", "ramp"] = Field(
        "rate",
        description="Injection control: 'rate' (a pump at rate Q into a reservoir of "
        "compliance C_inj, the paper's approximately constant rate), 'pressure' (fixed "
        "invading pressure) or 'ramp' (invading pressure rising linearly in time).",
    )
    capillary_number: float | None = Field(
        None,
        gt=0,
        description="Requested Ca = mu v / gamma (-), v = Q / A_b with A_b = 4 L a (centre "
        "injection). Give this or 'injection_rate' for rate control.",
    )
    injection_rate: float | None = Field(
        None, gt=0, description="Volumetric injection rate Q (m^3/s), instead of Ca."
    )
    reservoir: Literal["pore", "drained"] = Field(
        "pore",
        description="Compliance of the injection reservoir: 'pore' C_inj = c_t V (one pore, "
        "default) or 'drained' C_inj = c_t V_drained (stores far more fluid in the invader).",
    )
    injection_pressure: float = Field(
        0.0,
        ge=0,
        description="Invading pressure (Pa): the fixed value for 'pressure' control, the "
        "starting value for 'ramp' and for 'rate' control (default 0).",
    )
    ramp_rate: float | None = Field(None, gt=0, description="d p_inv / dt of a 'ramp' (Pa/s).")
    meniscus: Literal["threshold", "latching"] = Field(
        "threshold",
        description="'threshold': a meniscus advances only while p_inv - p_i exceeds its entry "
        "pressure; 'latching': once started it advances while p_inv > p_i.",
    )
    integrator: Literal["auto", "explicit", "rkc", "implicit"] = Field(
        "auto",
        description="Time integrator: 'explicit' (forward Euler between pores, point-implicit "
        "menisci and reservoir; its steps per drained pore grow like 1/Ca), 'rkc' (stabilised "
        "explicit IMEX Runge-Kutta-Chebyshev steps, the same point-implicit menisci in every "
        "stage; its sweeps grow like 1/sqrt(Ca)), 'implicit' (backward Euler over all pores "
        "with sliding menisci and located events; its cost does not grow with 1/Ca but each "
        "step factorises the pore matrix) or 'auto': explicit while it needs at most 50 steps "
        "per drained pore, rkc beyond, implicit beyond 50 N (N the number of pores: only on "
        "small lattices at very small Ca); docs/accuracy.md, docs/performance.md. All land "
        "menisci exactly on l = 0 and keep the injection reservoir stable.",
    )
    local_steps: Literal["auto", "on", "off"] = Field(
        "auto",
        description="RKC integrator, rate control, square grids without a coupled solid: "
        "fine steps only in a window of pores around the menisci that move, one long step "
        "elsewhere (local time stepping, docs/model.md). 'auto' takes them where they are "
        "predicted to pay (active box of at least 200 x 200 pores), 'on' wherever they "
        "apply, 'off' never (every step sweeps the whole box of active pores).",
    )
    window_tolerance: float = Field(
        1.0,
        gt=0,
        description="Local time steps: a pore whose error estimate in the long step over "
        "everything exceeds this fraction of 'tolerance' is integrated with the fine steps "
        "of the window (-). Smaller is more accurate and slower (docs/accuracy.md).",
    )
    safety_factor: float = Field(
        1.0,
        gt=0,
        le=1,
        description="Explicit step as a fraction of the limit min_i c_t V_i / sum_j g_ij (-), "
        "below which every explicit update is a convex combination of pressures (stable, "
        "and no pressure leaves the range of its neighbours'). Smaller is more accurate in "
        "the pressure field and slower (docs/accuracy.md). Explicit integrator only.",
    )
    tolerance: float = Field(
        1e-2,
        gt=0,
        lt=1,
        description="Implicit and rkc integrators: local error allowed per step, as a fraction "
        "of the spread of entry pressures 2 gamma (1/r_min - 1/r_max) (-), in the max norm "
        "over the pore pressures and p_inv (implicit: the backward Euler estimate 0.5 |p' - "
        "p - dt dp/dt|; rkc: the RKC estimate 0.8 (p - p') + 0.4 dt (dp/dt + dp'/dt)). "
        "Smaller is more accurate and slower.",
    )
    event_tolerance: float = Field(
        1e-10,
        gt=0,
        lt=1e-2,
        description="Implicit integrator only: relative precision in time of the located "
        "events (a meniscus landing on l = 0, a meniscus reaching its entry pressure), as a "
        "fraction of the step that contains them (-).",
    )
    pressure_floor: float = Field(
        1e-9,
        ge=0,
        description="Explicit integrator: pressures below this magnitude, in units of "
        "gamma/a, do not spread to inactive neighbours (-); 0 lets every pressure spread "
        "(exact, slowest). Both integrators: a pressure-controlled run is stationary once no "
        "meniscus advances and no pressure changes by more than this per stable step (the "
        "implicit one uses at least 1e-15).",
    )
    pressure_step: float | None = Field(
        0.1,
        gt=0,
        description="Explicit integrator only: accuracy limit of the time step, largest "
        "change per step of the invading pressure and of the pressure difference across "
        "each meniscus that may advance, as a fraction of the spread of entry pressures "
        "2 gamma (1/r_min - 1/r_max) (-). inf (None from Python): the stability limit alone "
        "(slightly faster and less accurate; docs/accuracy.md).",
    )
    max_time: float | None = Field(
        None, gt=0, description="End the run at this time (s) if it has not stopped before."
    )
    max_steps: int = Field(
        200_000_000, gt=0, description="Time steps after which the run fails as runaway (-)."
    )
    snapshot_saturations: list[float] = Field(
        default_factory=list,
        description="Drained fractions (0-1) at which to store the pressure field: a shorthand "
        "for an [[observers]] table of kind 'snapshots'.",
    )
    snapshot_times: list[float] = Field(
        default_factory=list,
        description="Times (s) at which to store the pressure field: a shorthand for an "
        "[[observers]] table of kind 'snapshots'.",
    )

    @model_validator(mode="after")
    def _check(self) -> ViscousConfig:
        given = [n for n in ("capillary_number", "injection_rate") if getattr(self, n) is not None]
        if self.control == "rate" and len(given) != 1:
            raise ValueError(
                "rate control needs exactly one of 'capillary_number' and 'injection_rate' "
                f"(got {' and '.join(given) if given else 'neither'})"
            )
        if self.control != "rate" and given:
            raise ValueError(f"'{given[0]}' applies only to control = 'rate'")
        if self.control == "ramp" and self.ramp_rate is None:
            raise ValueError("control = 'ramp' needs 'ramp_rate' (Pa/s)")
        if self.control != "ramp" and self.ramp_rate is not None:
            raise ValueError("'ramp_rate' applies only to control = 'ramp'")
        if self.control == "pressure" and self.injection_pressure <= 0:
            raise ValueError("control = 'pressure' needs a positive 'injection_pressure' (Pa)")
        if any(not 0 < s <= 1 for s in self.snapshot_saturations):
            raise ValueError("'snapshot_saturations' must lie in (0, 1]")
        if any(t <= 0 for t in self.snapshot_times):
            raise ValueError("'snapshot_times' must be positive (s)")
        return self

    def effects(self) -> dict[str, bool]:
        return {"capillarity": True, "viscous_dissipation": True, "trapping": True}

    @classmethod
    def example_scene(cls) -> dict[str, Any]:
        """A small scene of viscous drainage on the square lattice (the contract suite runs it)."""
        from porenet.kinds.scenes import VISCOUS, tiny_scene

        return tiny_scene(VISCOUS)

    def implied_observers(self) -> list[ModelConfig]:
        """``snapshot_saturations`` and ``snapshot_times`` are a shorthand for one
        ``snapshots`` observer (docs/run-file.md)."""
        if not self.snapshot_saturations and not self.snapshot_times:
            return []
        from porenet.kinds.snapshots.config import SnapshotsConfig

        return [
            SnapshotsConfig(
                saturations=list(self.snapshot_saturations or []),
                times=list(self.snapshot_times or []),
            )
        ]
