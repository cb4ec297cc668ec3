"""The Plan: which effects a scene calls for and so which objects a run builds.

Only the effects a scene calls for are simulated (docs/architecture.md, rule 7).
The plan is computed from the validated scene and the registry alone (no model is imported or
built), is printable (``porenet plan SCENE``), and is the only thing
:class:`~porenet.simulation.Simulation` builds from.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from porenet.analysis.numbers import (
    disorder_factor,
    fracturing_number,
    modified_capillary_number,
)
from porenet.core.cost import CostEstimate, estimate_cost
from porenet.core.extent import lattice_extent
from porenet.core.kinds import builds_nothing, feeds_back
from porenet.core.kinds import effects as effects_of
from porenet.core.registry import Registry
from porenet.core.sites import site_geometry

#: Keys of :attr:`Plan.numbers` that other code reads.
CA_STAR = "Ca* = Ca (L/a) / [lambda/(1-lambda^2)]"
FRACTURING_NUMBER = "fracturing number N_f"


@dataclass(frozen=True)
class ModelPlan:
    """One model slot: whether it is built, by whom, and why."""

    family: str
    kind: str
    package: str
    built: bool
    reason: str


@dataclass(frozen=True)
class Plan:
    """The effects of a scene and the models that will be built for it.

    Attributes
    ----------
    scene : SceneConfig
        The validated scene.
    effects : dict of str to bool
        ``capillarity``, ``viscous_dissipation``, ``trapping``, ``deformation``,
        ``contact_loss``, ``aperture_feedback`` (the solid's deformation changes the
        apertures the fluid sees: a coupler that feeds back), and any a kind adds: which
        physics the run simulates.
    models : tuple of ModelPlan
        Lattice, fluid, solid, coupler and observers, built or skipped.
    output : Path or None
        Run file to write at the end.
    progress : bool
        Whether a progress display is attached.
    numbers : dict of str to float
        The dimensionless numbers the scene determines (:func:`dimensionless_numbers`).
    regime : tuple of (str, float) or None
        The regime the theory predicts (:func:`porenet.analysis.regimes.predict_regime`)
        and its confidence; None when the scene does not determine it.
    cost : CostEstimate or None
        Estimated drained pores, steps, updates, memory and wall time (docs/cost.md).
    """

    scene: Any
    effects: dict[str, bool]
    models: tuple[ModelPlan, ...]
    output: Path | None = None
    progress: bool = False
    numbers: dict[str, float] = field(default_factory=dict)
    regime: tuple[str, float] | None = None
    cost: CostEstimate | None = None

    def builds(self, family: str) -> bool:
        """True if at least one model of ``family`` will be built."""
        return any(m.built for m in self.models if m.family == family)

    def describe(self) -> str:
        """A human-readable account of the plan."""
        lines = ["effects:"]
        for name, on in self.effects.items():
            lines.append(f"  {name:<20} {'yes' if on else 'no'}")
        lines.append("models:")
        for m in self.models:
            status = "build" if m.built else "skip "
            lines.append(f"  {status} {m.family:<10} {m.kind:<24} [{m.package}]  {m.reason}")
        if self.numbers:
            lines.append("numbers:")
            width = max(20, *(len(key) for key in self.numbers))
            for key, value in self.numbers.items():
                lines.append(f"  {key:<{width}} {value:.6g}")
        if self.regime is not None:
            regime, confidence = self.regime
            ca_star = self.numbers.get(CA_STAR)
            nf = self.numbers.get(FRACTURING_NUMBER)
            basis = [
                "Ca* -> 0 (quasi-static)"
                if not self.effects.get("viscous_dissipation")
                else f"Ca* = {ca_star:.3g}",
                f"N_f = {nf:.3g}" if nf is not None else "N_f = 0 (rigid)",
            ]
            lines.append(
                f"predicted regime: {regime} (confidence {confidence:.2f}; "
                f"{', '.join(basis)}; docs/model.md section 6)"
            )
        if self.cost is not None:
            lines.append(
                "estimated cost (a model, not a measurement: expect a factor ~2-3; docs/cost.md):"
            )
            lines.extend(self.cost.lines())
        lines.append(f"output: {self.output if self.output else 'none (nothing written)'}")
        return "\n".join(lines)


def make_plan(
    scene: Any, registry: Registry, *, output: str | Path | None = None, progress: bool = False
) -> Plan:
    """Plan the run of a validated scene."""
    effects = {
        "capillarity": True,
        "viscous_dissipation": False,
        "trapping": False,
        "deformation": False,
        "contact_loss": False,
        "aperture_feedback": False,
    }
    models: list[ModelPlan] = []
    lattice = registry.get("lattice", scene.lattice.kind)
    models.append(ModelPlan("lattice", lattice.kind, lattice.package, True, "pore network"))
    fluid = registry.get("fluid", scene.fluid.kind)
    effects.update(effects_of(scene.fluid))
    reason = (
        "pressure solve in the defending fluid"
        if effects["viscous_dissipation"]
        else "quasi-static: no pressure solve"
    )
    models.append(ModelPlan("fluid", fluid.kind, fluid.package, True, reason))
    solid = registry.get("solid", scene.solid.kind)
    effects.update(effects_of(scene.solid))
    effects["aperture_feedback"] = not builds_nothing(solid.config)
    if builds_nothing(solid.config):
        models.append(
            ModelPlan("solid", solid.kind, solid.package, False, "rigid: apertures never change")
        )
        models.append(ModelPlan("coupler", "-", "-", False, "no solid to couple"))
    else:
        models.append(ModelPlan("solid", solid.kind, solid.package, True, "mechanics"))
        coupler_kind = getattr(scene.solid, "coupler", None) or "-"
        package = "-"
        if ("coupler", coupler_kind) in registry:
            coupler = registry.get("coupler", coupler_kind)
            package = coupler.package
            effects["aperture_feedback"] = feeds_back(coupler.config)
        schedule = getattr(scene.solid, "coupling", None)
        reason = "fluid-solid exchange" + (f" ({schedule})" if schedule else "")
        if not effects["aperture_feedback"]:
            reason += "; apertures never change: the fluid sees the rigid medium"
        models.append(ModelPlan("coupler", coupler_kind, package, True, reason))
    models.append(_classifier_plan(scene, registry))
    for obs in scene.observers:
        entry = registry.get("observer", obs.kind)
        models.append(ModelPlan("observer", entry.kind, entry.package, True, "configured"))
    if progress:
        models.append(ModelPlan("observer", "(display)", "porenet", True, "progress on stderr"))
    if output is not None:
        models.append(ModelPlan("observer", "(run file)", "porenet", True, f"writes {output}"))
    numbers = dimensionless_numbers(scene)
    return Plan(
        scene=scene,
        effects=effects,
        models=tuple(models),
        output=None if output is None else Path(output),
        progress=progress,
        numbers=numbers,
        regime=predicted_regime(scene, numbers),
        cost=estimated_cost(scene, registry),
    )


def _classifier_plan(scene: Any, registry: Registry) -> ModelPlan:
    """The classifier slot: built unless the scene has none or asks for none."""
    config = getattr(scene, "classifier", None)
    kind = str(getattr(config, "kind", "-"))
    package = "-"
    if ("classifier", kind) in registry:
        package = registry.get("classifier", kind).package
    if config is None or builds_nothing(config):
        return ModelPlan("classifier", kind, package, False, "not requested")
    return ModelPlan(
        "classifier", kind, package, True, "labels the pattern at the end: D_f, regime"
    )


def estimated_cost(scene: Any, registry: Registry | None = None) -> CostEstimate:
    """The cost estimate; a kind the model cannot read gives "unknown", never an error."""
    try:
        return estimate_cost(scene, registry)
    except (AttributeError, TypeError, ValueError, ZeroDivisionError) as exc:
        return CostEstimate(None, None, None, None, None, (f"no estimate: {exc}",))


def predicted_regime(scene: Any, numbers: dict[str, float]) -> tuple[str, float] | None:
    """The regime the scene's fluid predicts (its config's ``predict_regime(numbers)``,
    :mod:`porenet.core.kinds`), or by default the regime of docs/model.md section 6 for the
    scene's Ca* and N_f, with its confidence.

    Quasi-static invasion is the limit Ca -> 0 (Ca* None); a rigid solid is N_f = 0. None
    when a viscous scene's Ca* cannot be computed (no disorder, pressure control).
    """
    from porenet.analysis.regimes import predict_regime

    own = getattr(scene.fluid, "predict_regime", None)
    if callable(own):
        return own(numbers)  # type: ignore[no-any-return]
    ca_star = numbers.get(CA_STAR)
    quasi_static = not bool(effects_of(scene.fluid).get("viscous_dissipation", False))
    if ca_star is None and not quasi_static:
        return None
    nf = numbers.get(FRACTURING_NUMBER)
    try:
        return predict_regime(None if quasi_static else ca_star, nf)
    except ValueError:
        return None


def dimensionless_numbers(scene: Any) -> dict[str, float]:
    """Size and disorder numbers of docs/model.md section 6 that the scene determines."""
    lat = scene.lattice
    numbers: dict[str, float] = {}
    pore_size = getattr(lat, "pore_size", None)
    extent = lattice_extent(lat)
    n = None if extent is None else extent.side
    if n is not None:
        numbers["pores_per_side"] = float(n)
        if pore_size is not None:
            # two lengths, both printed with their convention (docs/model.md section 1)
            numbers["L = n a (m), the L of Ca* and N_f"] = float(n) * float(pore_size)
            numbers["lattice extent 2 n a (m)"] = 2.0 * float(n) * float(pore_size)
    lam = None if extent is None else extent.disorder
    if lam is not None:
        numbers["disorder"] = float(lam)
        numbers["lambda/(1-lambda^2)"] = disorder_factor(float(lam))
    gamma = getattr(scene.fluid, "interfacial_tension", None)
    if gamma is not None and pore_size is not None:
        numbers["capillary pressure gamma/a (Pa)"] = float(gamma) / float(pore_size)
    ca = getattr(scene.fluid, "capillary_number", None)
    rate = getattr(scene.fluid, "injection_rate", None)
    viscosity = getattr(scene.fluid, "viscosity", None)
    if ca is None and extent is not None and None not in (rate, viscosity, gamma, pore_size):
        # Ca = mu Q / (gamma A_b), A_b = 4 L a (centre) or L a (left edge) on the square lattice
        cross_section = extent.cross_section(site_geometry(getattr(scene.injection, "at", "")))
        ca = float(rate) * float(viscosity) / (float(gamma) * cross_section * pore_size**2)
    if ca is not None:
        numbers["Ca"] = float(ca)
        if lam is not None and n is not None and 0 < float(lam) < 1:
            # Ca* ~ 1 is the CF/VF crossover (Fig. 2); L_x is the crossover length in pores
            numbers[CA_STAR] = modified_capillary_number(float(ca), int(n), float(lam))
            numbers["crossover length L_x / a"] = disorder_factor(float(lam)) / float(ca)
    solid = scene.solid
    nf = getattr(solid, "fracturing_number", None)
    modulus = getattr(solid, "modulus", None)
    prestrain = getattr(solid, "prestrain", None)
    if nf is None and modulus is not None and None not in (gamma, pore_size, lam, prestrain):
        nf = fracturing_number(gamma, lam, pore_size, modulus, prestrain)
    if nf is not None:
        numbers[FRACTURING_NUMBER] = float(nf)
    return numbers


#: The keys of :func:`plan_summary` in a run's ``/summary``.
PLAN_KEYS = (
    "plan_ca_star",
    "plan_fracturing_number",
    "plan_regime",
    "plan_regime_confidence",
    "plan_deformable",
)


def plan_summary(plan: Plan) -> dict[str, Any]:
    """What the plan predicted, for the run's ``/summary`` (docs/run-file.md): Ca*, N_f, the
    regime and its confidence (the regime ``""`` and the others None, not written, where the
    scene determines none), and whether the apertures the fluid sees can change (a solid model
    coupled back, effect ``aperture_feedback``). Stored with the
    run, so that classifying its run file needs nothing but the file (the analysis reads them:
    :func:`porenet.analysis.prediction.planned_verdict`, :func:`scene_is_deformable`)."""
    regime = plan.regime
    return {
        "plan_ca_star": plan.numbers.get(CA_STAR),
        "plan_fracturing_number": plan.numbers.get(FRACTURING_NUMBER),
        "plan_regime": "" if regime is None else regime[0],
        "plan_regime_confidence": None if regime is None else float(regime[1]),
        "plan_deformable": bool(plan.effects.get("aperture_feedback", False)),
    }


def scene_is_deformable(scene: dict[str, Any], summary: dict[str, Any] | None = None) -> bool:
    """Whether the apertures a run's fluid saw could change (and so the pattern fracture), from
    its run file: the plan's record ``plan_deformable`` in ``/summary``, or, for a run file
    written before porenet stored it (or a scene without a summary), whether its solid kind
    builds a model (a kind that builds nothing, the rigid medium, cannot). A solid kind this
    process does not know (its plugin is not installed) counts as deformable."""
    if summary and "plan_deformable" in summary:
        return bool(summary["plan_deformable"])
    from porenet.hooks import get_registry

    registry = get_registry()
    kind = ((scene or {}).get("solid") or {}).get("kind", registry.default("solid"))
    if ("solid", kind) not in registry:
        return True
    return not builds_nothing(registry.get("solid", kind).config)
