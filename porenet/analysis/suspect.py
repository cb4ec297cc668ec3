"""Results that look physically wrong, said plainly (docs/stability.md, "Suspect results").

:func:`suspect_physics` reads a finished run's summary and returns one sentence per problem;
the Simulation logs each as a warning (printed by ``porenet run`` unless ``-q``) and stores
them, joined by ``"; "``, as ``/summary`` attribute ``physics_warnings`` (empty when none).
Pure arithmetic on the summary: nothing is recomputed.
"""

from __future__ import annotations

import math
from typing import Any

#: A run whose throats sit at the aperture cap (or floor) for more than this fraction of all
#: throats is flagged: its pattern mostly reflects the limit, not the solid's response.
LIMIT_FRACTION = 0.5
#: A rate-controlled run whose measured Ca differs from the requested one by more than this
#: factor is flagged (the pump could not deliver it: fast injection, a compressible invader).
CA_FACTOR = 2.0


def suspect_physics(summary: dict[str, Any], n_throats: int) -> list[str]:
    """Sentences naming what looks wrong in a run's ``summary`` (empty list: nothing).

    Parameters
    ----------
    summary : dict
        The run's ``/summary`` (SI values), as built by the Simulation.
    n_throats : int
        Throats of the lattice.
    """
    found: list[str] = []
    for key, what in (("apertures_at_cap", "cap"), ("apertures_at_floor", "floor")):
        count = summary.get(key)
        if count is not None and n_throats > 0 and count > LIMIT_FRACTION * n_throats:
            found.append(
                f"{count} of {n_throats} throats reached the aperture {what} "
                f"(more than {LIMIT_FRACTION:.0%}): the pattern mostly reflects that limit, "
                "not the solid's response (a solid this soft is outside the model's range)"
            )
    requested = summary.get("capillary_number")
    measured = summary.get("capillary_number_measured")
    if _positive(requested) and _positive(measured):
        ratio = float(measured) / float(requested)
        if not 1.0 / CA_FACTOR <= ratio <= CA_FACTOR:
            found.append(
                f"measured Ca = {float(measured):.3g} is {ratio:.3g}x the requested "
                f"{float(requested):.3g} (more than a factor {CA_FACTOR:g} off): the run is not "
                "at the capillary number asked for, and its regime should be read at the "
                "measured one"
            )
    return found


def _positive(value: Any) -> bool:
    try:
        return math.isfinite(float(value)) and float(value) > 0
    except (TypeError, ValueError):
        return False
