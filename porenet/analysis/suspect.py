"""Results that look physically wrong, said plainly (docs/stability.md, "Suspect results").

:func:`suspect_physics` reads a finished run's summary and returns one sentence per problem;
the Simulation logs each as a warning (printed by ``porenet run``, also with ``-q``) and
stores them, joined by ``"; "``, as ``/summary`` attribute ``physics_warnings`` (empty when
none). :func:`regime_disagreement` adds one when the pattern's label and the theory's
prediction for the scene (what ``porenet plan`` prints) have no regime in common;
:func:`porenet.analysis.classify.classify_run` asks it, at the end of a run and in ``porenet
classify``. Pure arithmetic on the summary: nothing is recomputed.
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


def regime_parts(label: str) -> set[str]:
    """The pure regimes a label names: ``"FR/VF"`` -> ``{"FR", "VF"}``."""
    return set(label.split("/"))


def regime_disagreement(
    regime: str | None,
    predicted: str | None,
    classifier: str,
    basis: dict[str, float | None] | None = None,
) -> str | None:
    """A sentence when the pattern's label and the theory's prediction share no regime, else
    None.

    Labels agree when they name a regime in common: CF/VF agrees with CF and with VF, FR/VF
    with FR and with VF; CF against VF, CF against FR or FR/VF, VF against FR/CF disagree.

    Parameters
    ----------
    regime : str or None
        The classifier's label (None: not classified).
    predicted : str or None
        The regime the theory predicts for the scene (None: the scene determines none).
    classifier : str
        The kind that gave the label, named in the sentence.
    basis : dict, optional
        ``ca_star`` and ``fracturing_number`` of the prediction, quoted when known.
    """
    if regime is None or predicted is None or regime_parts(regime) & regime_parts(predicted):
        return None
    numbers = []
    for key, name in (("ca_star", "Ca*"), ("fracturing_number", "N_f")):
        value = (basis or {}).get(key)
        if _positive(value):
            numbers.append(f"{name} = {float(value):.3g}")  # type: ignore[arg-type]
    quoted = f" ({', '.join(numbers)})" if numbers else ""
    return (
        f"the pattern is labelled {regime} by {classifier}, but the theory predicts "
        f"{predicted} for this scene{quoted}, as porenet plan says: the run may not be at the "
        "conditions asked for (see any other warning) or the label may be wrong, so look at the "
        "pattern (porenet plot) before using either"
    )


def _positive(value: Any) -> bool:
    try:
        return math.isfinite(float(value)) and float(value) > 0
    except (TypeError, ValueError):
        return False
