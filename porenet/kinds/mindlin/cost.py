"""The cost estimate of the frictional solid (docs/cost.md): the Hertzian solid's coupling
(:mod:`porenet.kinds.hertz.cost`) with an update of its own cost.

One update with rotations held and no sliding: ``1.9e-7 N`` s (the multigrid solve is linear in
N); with sliding (``friction``) times ``1 + 1.7 sqrt(r_t) w`` (``r_t = K_t / K_n``, ``w`` the
fracture weight). Memory: +1200 bytes per pore (two multigrid hierarchies).
"""

from __future__ import annotations

import math
from typing import Any

from porenet.core.cost import CostRequest, FluidCost, SolidCost
from porenet.kinds.hertz import cost as hertz_cost

#: One mechanical update (rotations held, no sliding), per pore: the multigrid solve is linear
#: in N (n = 400 Fig. 5 at N_f = 10: 29.7 ms an update, ``tests/benchmarks/bench_frictional.py
#: run``, docs/cost.md).
MINDLIN_UPDATE_SECONDS = 1.9e-7
#: With sliding (``solid.friction``) an update costs ``1 + c sqrt(r_t) w`` times one without
#: (``r_t = K_t / K_n``, ``w`` the fracture weight): contacts at Coulomb's cap change mode as
#: the load moves, each change a new solve, and the more so the stiffer the contacts and the
#: more the medium fractures. Fitted to the n = 400 study's runs with and without sliding
#: made with one code on one machine: the constant that keeps the worst point's median over
#: its seeds closest (``examples/scripts/fracture_shear.py --sliding-cost``: 12 points, 30
#: pairs, c = 1.74, every median within 1.21x, every pair within 1.61x; seeds of one point
#: differ by up to 1.4x); the form ``1 + c r_t w`` came within 1.32x at best on the medians
#: (docs/cost.md, "The model", paragraph "Sliding").
MINDLIN_SLIDING = 1.7
#: Extra peak memory per pore (two multigrid hierarchies), beyond the Hertzian solid's.
MEMORY_MINDLIN = 600.0


def sliding_factor(stiffness_ratio: float, weight: float) -> float:
    """What Coulomb sliding multiplies a frictional update's cost by: ``1 + c sqrt(r_t) w``
    (:data:`MINDLIN_SLIDING`; ``r_t = K_t / K_n``, ``w`` the fracture weight)."""
    return 1.0 + MINDLIN_SLIDING * math.sqrt(stiffness_ratio) * weight


def estimate(config: Any, request: CostRequest, fluid: FluidCost) -> SolidCost:
    """Updates, wall time and memory of the frictional solid."""
    sliding = getattr(config, "friction", None) is not None
    slide = sliding_factor(config.stiffness_ratio, fluid.fracture_weight) if sliding else 1.0
    notes: tuple[str, ...] = ()
    if sliding:
        notes = (
            f"solid.friction: sliding costed at {slide:.2g}x the mechanics of the same run "
            "without it (fitted to n = 400 runs with K_t/K_n 0.1-0.8 at N_f 1-30: each "
            "point's median over its seeds within 1.23x, single runs within 1.6x; "
            "docs/cost.md)",
        )
    return hertz_cost.estimate(
        config,
        request,
        fluid,
        update_seconds=lambda pores, weight: MINDLIN_UPDATE_SECONDS * pores * slide,
        memory_per_pore=hertz_cost.MEMORY_HERTZ + MEMORY_MINDLIN,
        notes=notes,
    )
