"""The rule-based classifier: CF, VF, FR or an intermediate label from the pattern itself.

docs/model.md section 7: D_f alone cannot classify a finite sample, so the rules combine it with
geometric features (:func:`porenet.analysis.features.pattern_features`):

1. **Fracturing** is recognised by a fraction ``f``, the larger of two: drained pores in thin
   straight runs (channels one pore wide and at least
   :data:`~porenet.analysis.features.LONG_RUN` pores long) and, in deformable media, drained
   pores entered through throats the solid opened (their spring removed,
   :func:`~porenet.analysis.features.opened_fraction`; fractures need not be straight).
   ``f >= fracture_fraction`` gives FR; ``fracture_onset <= f < fracture_fraction`` an
   intermediate FR/CF or FR/VF.
2. **Capillary against viscous fingering** is a weighted vote of two indicators, each in
   [-1, 1] (positive: CF): the mean finger width against ``width_split`` (CF clusters are fat,
   VF fingers one pore wide) and the fractal dimension against ``dimension_split`` (after
   removing the estimator's known finite-size bias, docs/fractal.md). The D_f vote is
   weighted down when its uncertainty exceeds ``dimension_scale``. A vote within
   ``intermediate_band`` of 0 gives CF/VF.

On lattices without a grid layout (3-D, imported networks) the features are measured on the
pores and throats (:mod:`porenet.analysis.network_features`) and the verdict's details say
that the thresholds were calibrated on the square lattice.

Patterns too small to judge (fewer than ``min_drained`` pores) raise ``ValueError``; at the
end of a run :func:`porenet.analysis.classify.classify_run` then falls back on the theory
predictor, with its confidence halved. Thresholds and the accuracy
they give on labelled ensembles: docs/classification.md.
"""

from __future__ import annotations

import math
from typing import Any

from porenet.analysis.classify import measure_dimension
from porenet.analysis.features import pattern_features
from porenet.core.interfaces import Classification, Classifier
from porenet.kinds.rules.config import RulesClassifierConfig


def _clip(x: float) -> float:
    return max(-1.0, min(1.0, x))


class RulesClassifier(Classifier):
    """Labels a run from its pattern (see the module docstring)."""

    config: RulesClassifierConfig

    def __init__(self, config: RulesClassifierConfig | None = None) -> None:
        super().__init__(config or RulesClassifierConfig())

    def classify(self, run: Any) -> Classification:
        c = self.config
        data = getattr(run, "data", run)
        if int(data.drained.sum()) < c.min_drained:
            raise ValueError(f"rules: fewer than {c.min_drained} drained pores")
        features = pattern_features(data)
        fit = measure_dimension(data)
        details: dict[str, Any] = dict(features)
        if data.grid_shape is None:  # the thresholds were calibrated on the square lattice
            details["note"] = (
                "features measured on the network's pores and throats; the thresholds were "
                "calibrated on the square lattice (docs/classification.md)"
            )
        # CF (+) against VF (-): width always votes, D_f with a weight set by its uncertainty
        votes = [(1.0, _clip((features["finger_width_mean"] - c.width_split) / c.width_scale))]
        if fit is not None:
            corrected = fit.dimension - (0.0 if math.isnan(fit.bias) else fit.bias)
            weight = min(1.0, c.dimension_scale / fit.error) if fit.error > 0 else 1.0
            votes.append((weight, _clip((corrected - c.dimension_split) / c.dimension_scale)))
            details.update(
                fractal_dimension=fit.dimension,
                fractal_dimension_error=fit.error,
                fractal_dimension_corrected=corrected,
            )
        vote = sum(w * v for w, v in votes) / sum(w for w, _ in votes)
        details["fingering_vote"] = vote
        fingering = "CF" if vote > 0 else "VF"
        f = features["thin_run_fraction"]
        if not math.isnan(features["opened_fraction"]):
            f = max(f, features["opened_fraction"])
        hi, lo = c.fracture_fraction, c.fracture_onset
        if f >= hi:
            span = max(hi - lo, 1e-9)
            return Classification("FR", 0.5 + 0.5 * min(1.0, (f - hi) / span), details)
        if f >= lo:
            middle, half = 0.5 * (hi + lo), max(0.5 * (hi - lo), 1e-9)
            return Classification(f"FR/{fingering}", 1.0 - 0.5 * abs(f - middle) / half, details)
        band = c.intermediate_band
        if abs(vote) < band:
            return Classification("CF/VF", 1.0 - 0.5 * abs(vote) / band if band else 1.0, details)
        return Classification(fingering, 0.5 + 0.5 * min(1.0, abs(vote)), details)
