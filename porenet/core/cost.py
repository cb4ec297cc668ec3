"""The estimated cost of a run, from its validated scene alone (docs/cost.md).

Nothing is built and no model is imported: each kind estimates its own part with the cost
estimate it registered (``register(..., cost="module:function")``, :mod:`porenet.core.kinds`),
as arithmetic on the lattice's size (its config's ``extent()``,
:class:`~porenet.core.extent.LatticeExtent`), the stop condition and the models' settings,
with per-unit costs measured on the project's 2-core machine (``python
tests/benchmarks/bench_cost.py`` prints predicted against measured):

1. the fluid's, ``estimate(config, request)`` with a :class:`CostRequest`: drained pores,
   fluid steps, wall time and memory (:class:`FluidCost`), knowing whether and how much the
   solid fractures;
2. a deformable solid's, ``estimate(config, request, fluid_cost)``: mechanical updates over
   the fluid's steps, their wall time and the solid's memory (:class:`SolidCost`);
3. this module adds the lattice's, the state's, the records' and the run data's memory
   (:data:`MEMORY_BASE` per pore) and the parts up (:func:`estimate_cost`).

A kind that provides no estimate gives ``None`` ("unknown") for what depends on it, with a
note that says so, never an error. The built-in kinds aim at a factor ~2-3 on steps and wall
time. Python start-up, imports and the first-run numba compilation (once per machine:
docs/performance.md, "First run") are not included.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from porenet.analysis.numbers import fracturing_number
from porenet.core.extent import LatticeExtent, lattice_extent
from porenet.core.kinds import builds_nothing, effects
from porenet.core.registry import Registry

#: Peak memory of the lattice, the state, the records and the run data, bytes per pore.
MEMORY_BASE = 240.0


@dataclass(frozen=True)
class CostRequest:
    """What a kind's cost estimate may read.

    Attributes
    ----------
    scene : SceneConfig
        The validated scene (the kind reads its own section and the stop condition).
    extent : LatticeExtent
        The lattice's size.
    fracturing_number : float or None
        ``N_f`` of a deformable solid (given, or from its modulus by Eq. 2 of the paper);
        None in a rigid medium or where the scene determines none.
    deformable : bool
        A solid model will change the apertures during the run.
    fractures : bool
        The solid's contacts open under tension (its effect ``contact_loss``): the medium
        can fracture, which changes what the fluid drains.
    """

    scene: Any
    extent: LatticeExtent
    fracturing_number: float | None
    deformable: bool
    fractures: bool


@dataclass(frozen=True)
class FluidCost:
    """A fluid kind's estimate (:class:`CostRequest` in, this out); ``None`` where unknown.

    Attributes
    ----------
    drained : float or None
        Pores drained by the stop condition (inlets included).
    steps : float or None
        Fluid steps: time steps, or drained pores of a model that drains one a step.
    wall_seconds : float or None
        Wall time of the fluid's part, build and run, on the calibration machine.
    memory_bytes : float
        Peak memory of the model's own arrays, beyond :data:`MEMORY_BASE` per pore.
    notes : tuple of str
        Assumptions and the parts the estimate does not cover.
    fracture_weight : float
        0 (the medium does not fracture) to 1 (it does), which a solid's update cost reads.
    adaptive_scale : float
        Share of the fluid's steps after which an adaptive coupler updates a solid soft
        enough to move by its tolerance at every chance (0.3 for the viscous model, 1 for
        invasion percolation, whose every step drains a pore).
    """

    drained: float | None
    steps: float | None
    wall_seconds: float | None
    memory_bytes: float = 0.0
    notes: tuple[str, ...] = ()
    fracture_weight: float = 0.0
    adaptive_scale: float = 1.0


@dataclass(frozen=True)
class SolidCost:
    """A deformable solid kind's estimate; ``None`` where unknown.

    Attributes
    ----------
    updates : float or None
        Mechanical updates over the run.
    wall_seconds : float or None
        Wall time the solid adds (its updates and the coupling's work per fluid step).
    memory_bytes : float
        Peak memory of the solid's arrays.
    notes : tuple of str
        Assumptions and the parts the estimate does not cover.
    """

    updates: float | None
    wall_seconds: float | None
    memory_bytes: float = 0.0
    notes: tuple[str, ...] = ()


@dataclass(frozen=True)
class CostEstimate:
    """Estimated size of a run (docs/cost.md); ``None`` where the model has no estimate.

    Attributes
    ----------
    drained : int or None
        Pores drained by the stop condition (inlets included).
    steps : int or None
        Fluid steps: time steps of the viscous model, drained pores of invasion percolation.
    mechanical_updates : int or None
        Solid updates (0 in a rigid medium).
    memory_bytes : int or None
        Peak memory of the run's arrays.
    wall_seconds : float or None
        Wall time of build and run on the calibration machine (no imports, no compilation).
    notes : tuple of str
        Assumptions and the parts the model does not cover.
    """

    drained: int | None
    steps: int | None
    mechanical_updates: int | None
    memory_bytes: int | None
    wall_seconds: float | None
    notes: tuple[str, ...] = ()

    def summary(self) -> str:
        """The estimate on one line."""
        return (
            f"{_count(self.drained)} drained pores, {_count(self.steps)} steps, "
            f"{_count(self.mechanical_updates)} mechanical updates, "
            f"{format_bytes(self.memory_bytes)}, {format_seconds(self.wall_seconds)}"
        )

    def lines(self) -> list[str]:
        """The estimate as text, one quantity a line, with units."""
        return [
            f"  {'drained pores':<20} {_count(self.drained)}",
            f"  {'fluid steps':<20} {_count(self.steps)}",
            f"  {'mechanical updates':<20} {_count(self.mechanical_updates)}",
            f"  {'memory':<20} {format_bytes(self.memory_bytes)}",
            f"  {'wall time':<20} {format_seconds(self.wall_seconds)}"
            + (
                " (build and run; not imports or numba's first compile)"
                if self.wall_seconds
                else ""
            ),
            *(f"  note: {note}" for note in self.notes),
        ]


def _count(value: int | None) -> str:
    if value is None:
        return "unknown"
    if value == 0:
        return "0"
    return f"~{_round2(value):,}"


def _round2(value: float) -> int:
    """``value`` to two significant figures."""
    if value < 100:
        return round(value)
    digits = math.floor(math.log10(value)) - 1
    return int(round(value / 10**digits) * 10**digits)


def format_bytes(value: float | None) -> str:
    """``~12 MB`` style, or ``unknown``."""
    if value is None:
        return "unknown"
    for unit, size in (("GB", 1e9), ("MB", 1e6), ("kB", 1e3)):
        if value >= size:
            scaled = value / size
            return f"~{scaled:.2g} {unit}" if scaled < 10 else f"~{_round2(scaled)} {unit}"
    return f"~{value:.0f} B"


def format_seconds(value: float | None) -> str:
    """``~40 s``, ``~3.5 min``, ``~2.1 h``, or ``unknown``."""
    if value is None:
        return "unknown"
    if value < 0.1:
        return "< 0.1 s"
    for unit, size, limit in (("s", 1, 90), ("min", 60, 5400), ("h", 3600, 48 * 3600)):
        if value < limit:
            scaled = value / size
            return f"~{scaled:.2g} {unit}" if scaled < 10 else f"~{_round2(scaled)} {unit}"
    return f"~{_round2(value / 86400)} days"


def solid_fracturing_number(scene: Any) -> float | None:
    """``N_f`` of the scene's solid (given, or from its modulus by Eq. 2), None if the scene
    determines none."""
    solid, lat = scene.solid, scene.lattice
    nf = getattr(solid, "fracturing_number", None)
    if nf is not None:
        return float(nf)
    modulus = getattr(solid, "modulus", None)
    gamma = getattr(scene.fluid, "interfacial_tension", None)
    lam = getattr(lat, "disorder", None)
    pore = getattr(lat, "pore_size", None)
    eps = getattr(solid, "prestrain", None)
    if None in (modulus, gamma, lam, pore, eps):
        return None
    return fracturing_number(float(gamma), float(lam), float(pore), float(modulus), float(eps))


def cost_request(scene: Any) -> CostRequest | None:
    """The request the kinds' estimates read, or None when the lattice describes no size."""
    extent = lattice_extent(scene.lattice)
    if extent is None:
        return None
    deformable = not builds_nothing(scene.solid)
    return CostRequest(
        scene=scene,
        extent=extent,
        fracturing_number=solid_fracturing_number(scene) if deformable else None,
        deformable=deformable,
        fractures=deformable and bool(effects(scene.solid).get("contact_loss", False)),
    )


def _no_estimate(role: str, config: Any) -> str:
    return (
        f"{role} {config.kind!r} provides no cost estimate (its plugin registers none; "
        'docs/cost.md, "Kinds without an estimate")'
    )


def _cost_function(registry: Registry, family: str, config: Any) -> Callable[..., Any] | None:
    if (family, config.kind) not in registry:
        return None
    return registry.get(family, config.kind).load_cost()


def estimate_cost(scene: Any, registry: Registry | None = None) -> CostEstimate:
    """Estimate drained pores, steps, mechanical updates, memory and wall time of ``scene``.

    ``scene`` is a validated scene; nothing is built. Each kind's estimate comes from
    ``registry`` (default: the process's). A kind that provides no estimate gives ``None``
    for what depends on it, with a note.
    """
    if registry is None:
        from porenet.hooks import get_registry

        registry = get_registry()
    lat, fluid, solid, stop = scene.lattice, scene.fluid, scene.solid, scene.stop
    request = cost_request(scene)
    if request is None:
        return CostEstimate(None, None, None, None, None, (f"lattice {lat.kind!r}: no size",))
    pores = request.extent.pores
    estimate_fluid = _cost_function(registry, "fluid", fluid)
    fluid_cost = None if estimate_fluid is None else estimate_fluid(fluid, request)
    if fluid_cost is None:
        drained = None if stop.max_drained is None else int(stop.max_drained)
        return CostEstimate(drained, None, None, None, None, (_no_estimate("fluid", fluid),))
    notes = list(fluid_cost.notes)
    memory = MEMORY_BASE * pores + fluid_cost.memory_bytes
    wall = fluid_cost.wall_seconds
    updates: float | None = 0.0
    if request.deformable:
        estimate_solid = _cost_function(registry, "solid", solid)
        solid_cost = None if estimate_solid is None else estimate_solid(solid, request, fluid_cost)
        if solid_cost is None:
            notes.append(_no_estimate("solid", solid))
            updates = wall = None
        else:
            notes.extend(solid_cost.notes)
            updates = solid_cost.updates
            memory += solid_cost.memory_bytes
            if wall is not None and solid_cost.wall_seconds is not None:
                wall += solid_cost.wall_seconds
            elif solid_cost.wall_seconds is None:
                wall = None

    def _int(value: float | None) -> int | None:
        return None if value is None else round(value)

    return CostEstimate(
        drained=_int(fluid_cost.drained),
        steps=_int(fluid_cost.steps),
        mechanical_updates=_int(updates),
        memory_bytes=_int(memory),
        wall_seconds=wall,
        notes=tuple(notes),
    )
