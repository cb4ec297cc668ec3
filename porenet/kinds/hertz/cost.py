"""The cost estimate of the Hertzian solid (docs/cost.md): arithmetic on the scene alone.

Mechanical updates: one per fluid step (``every-step``), one per ``coupling_interval`` steps,
or, adaptive, the fluid's share of its steps (:attr:`porenet.core.cost.FluidCost.adaptive_scale`:
~0.3 of the viscous model's steps, every drained pore of invasion percolation) for ``N_f >=
0.1``, falling to 0 at ``N_f = 0.01`` (a stiff solid is never updated). Wall time: ``steps (3e-5
+ 1.8e-9 N)`` (one step per call and the coupler's check) and ``updates (2.3e-9 + 7e-9 w)
N^1.15`` (``w`` = 1 when fracturing). Memory: +600 bytes per pore. Above ``N_f = 10`` with a
viscous fluid the estimate says it is outside its calibration.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

from porenet.core.cost import CostRequest, FluidCost, SolidCost

#: Adaptive coupling: the N_f from which the fluid's full share of steps is followed by an
#: update, and the N_f below which a solid is never updated, at the default tolerance 3e-3.
ADAPTIVE_FULL_NF = 0.1
ADAPTIVE_NONE_NF = 0.01
ADAPTIVE_TOLERANCE = 3e-3
#: Viscous fluid: above this N_f the estimate says it is outside its calibration (steps and
#: updates 14x and 30x the estimate at N_f = 1e6, n = 30).
SOFT_NF = 10.0
#: Extra per fluid step in a deformable medium (one step per call, the coupler's check).
COUPLED_STEP_SECONDS = (30e-6, 1.8e-9)
#: One mechanical update: ``(c + c_fracture w) N^p`` s, with ``w`` the fracture weight
#: (contacts opening make an update ~4x dearer).
UPDATE_SECONDS = (2.3e-9, 7e-9, 1.15)
#: Peak memory of the solid, bytes per pore.
MEMORY_HERTZ = 600.0


def adaptive_ramp(nf: float | None, tolerance: float = ADAPTIVE_TOLERANCE) -> float:
    """Share of the fluid's full adaptive update rate that a solid of ``N_f`` gets: 1 for
    ``N_f >= 0.1`` at the default tolerance, falling linearly in ``log N_f`` to 0 at ``N_f =
    0.01``; a larger tolerance acts like a stiffer solid (``N_f`` scaled by ``3e-3 /
    tolerance``)."""
    if nf is None:
        return 1.0
    x = nf * ADAPTIVE_TOLERANCE / tolerance if tolerance > 0 else math.inf
    if x >= ADAPTIVE_FULL_NF:
        return 1.0
    if x <= ADAPTIVE_NONE_NF:
        return 0.0
    return math.log(x / ADAPTIVE_NONE_NF) / math.log(ADAPTIVE_FULL_NF / ADAPTIVE_NONE_NF)


def update_count(config: Any, steps: float, nf: float | None, adaptive_scale: float) -> float:
    """Mechanical updates over ``steps`` fluid steps under the config's coupling schedule."""
    schedule = getattr(config, "coupling", "every-step")
    if schedule == "every-step":
        return steps
    if schedule == "interval":
        return steps / max(1, int(getattr(config, "coupling_interval", 1)))
    tolerance = float(getattr(config, "coupling_tolerance", ADAPTIVE_TOLERANCE))
    return steps * adaptive_scale * adaptive_ramp(nf, tolerance)


def hertz_update_seconds(pores: int, fracture_weight: float) -> float:
    """Wall time of one update of the Hertzian solid (:data:`UPDATE_SECONDS`)."""
    c, c_fracture, p = UPDATE_SECONDS
    return (c + c_fracture * fracture_weight) * pores**p


def estimate(
    config: Any,
    request: CostRequest,
    fluid: FluidCost,
    *,
    update_seconds: Callable[[int, float], float] = hertz_update_seconds,
    memory_per_pore: float = MEMORY_HERTZ,
    notes: tuple[str, ...] = (),
) -> SolidCost:
    """Updates, wall time and memory of a Hertzian solid coupled to the fluid whose estimate
    is ``fluid``; a solid of the same coupling with another update cost (the frictional one)
    passes its own ``update_seconds(pores, fracture_weight)`` and memory."""
    nf, pores = request.fracturing_number, request.extent.pores
    out = list(notes)
    viscous = bool(request.scene.fluid.effects().get("viscous_dissipation", False))
    if viscous and nf is not None and nf > SOFT_NF:
        out.append(
            f"N_f = {nf:.3g} is beyond the model's calibration (N_f <= {SOFT_NF:g}): a soft "
            "solid opens throats towards the aperture cap and shortens the stable step; "
            "measured 14x the steps and 30x the updates at N_f = 1e6 (docs/cost.md, "
            '"Hard cases")'
        )
    if fluid.steps is None:
        return SolidCost(updates=None, wall_seconds=0.0, memory_bytes=0.0, notes=tuple(out))
    updates = update_count(config, fluid.steps, nf, fluid.adaptive_scale)
    wall = fluid.steps * (COUPLED_STEP_SECONDS[0] + COUPLED_STEP_SECONDS[1] * pores)
    wall += updates * update_seconds(pores, fluid.fracture_weight)
    return SolidCost(
        updates=updates,
        wall_seconds=wall,
        memory_bytes=memory_per_pore * pores,
        notes=tuple(out),
    )
