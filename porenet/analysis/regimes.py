"""The regimes of the paper's phase diagrams (Figs. 2-3) and their theoretical boundaries.

docs/model.md section 6: capillary fingering (CF) turns into viscous fingering (VF) at
``Ca* = Ca (L/a) / [λ/(1-λ²)] ≈ 1``, and fracturing (FR) dominates for ``N_f ≳ 1``. The paper
draws intermediate regimes (CF/VF, FR/VF, FR/CF) along those lines. :func:`predict_regime`
places a scene on the diagram.

Decision: the intermediate band is ``INTERMEDIATE_HALF_WIDTH`` = 0.5 decades either side of
each line (a factor ~3), the width of the intermediate points in the paper's Figs. 2-3.
"""

from __future__ import annotations

import math

#: The labels, pure regimes first.
REGIMES: tuple[str, ...] = ("CF", "VF", "FR", "CF/VF", "FR/VF", "FR/CF")

#: Half-width (decades of Ca* or N_f) of the intermediate band around each theoretical line.
INTERMEDIATE_HALF_WIDTH = 0.5


def _log10(value: float | None) -> float:
    if value is None or value <= 0:
        return -math.inf  # quasi-static (Ca = 0) or rigid (N_f = 0)
    if math.isinf(value):
        return math.inf
    return math.log10(value)


def _confidence(margin: float, intermediate: bool) -> float:
    """1 deep inside a pure regime or on a line; 0.5 at the edge of an intermediate band."""
    w = INTERMEDIATE_HALF_WIDTH
    if intermediate:
        return 1.0 - 0.5 * min(margin, w) / w
    return 0.5 + 0.5 * math.tanh((margin - w) / w)


def predict_regime(ca_star: float | None, fracturing_number: float | None) -> tuple[str, float]:
    """The regime the theory of docs/model.md section 6 predicts, with a confidence in [0.5, 1].

    Parameters
    ----------
    ca_star : float or None
        Modified capillary number ``Ca (L/a) / [λ/(1-λ²)]``; ``None`` or 0 for quasi-static
        invasion (Ca -> 0).
    fracturing_number : float or None
        ``N_f`` (Eq. 2); ``None`` or 0 for a rigid medium.

    Returns
    -------
    regime : str
        One of :data:`REGIMES`.
    confidence : float
        0.5 at the edge of an intermediate band, rising to 1 far from the lines (pure labels)
        or on a line (intermediate labels).
    """
    for name, value in (("ca_star", ca_star), ("fracturing_number", fracturing_number)):
        if value is not None and (math.isnan(value) or value < 0):
            raise ValueError(f"{name} must be a non-negative number, got {value}")
    x, y = _log10(ca_star), _log10(fracturing_number)
    w = INTERMEDIATE_HALF_WIDTH
    fingering = "VF" if x > 0 else "CF"
    if y > w:
        return "FR", _confidence(y, False)
    if y >= -w:
        return f"FR/{fingering}", _confidence(abs(y), True)
    if abs(x) <= w:
        return "CF/VF", _confidence(abs(x), True)
    margin = min(abs(x), abs(y))
    return fingering, _confidence(margin, False)
