"""The ``centroid.nearest`` classifier: the regime whose typical pattern is closest."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from porenet.analysis.classify import measure_dimension
from porenet.analysis.features import pattern_features
from porenet.core.interfaces import Classification, Classifier
from porenet_centroid.config import FEATURES, CentroidClassifierConfig

#: The intermediate label of two neighbouring regimes (porenet's names).
PAIRS = {
    frozenset({"CF", "VF"}): "CF/VF",
    frozenset({"FR", "VF"}): "FR/VF",
    frozenset({"FR", "CF"}): "FR/CF",
}


class CentroidClassifier(Classifier):
    """Scaled Euclidean distance to each centroid; near-ties give intermediate labels.

    Confidence: ``1 - d1 / (2 d2)`` for a clear nearest centroid (``d1``, ``d2`` the two
    smallest distances), i.e. 0.5 when they are equal and 1 on a centroid.
    """

    config: CentroidClassifierConfig

    def __init__(self, config: CentroidClassifierConfig | None = None) -> None:
        super().__init__(config or CentroidClassifierConfig())

    def classify(self, run: Any) -> Classification:
        data = getattr(run, "data", run)
        if data.grid_shape is None:
            raise ValueError("centroid.nearest needs a lattice with a grid layout")
        features = pattern_features(data)
        fit = measure_dimension(data)
        if fit is None:
            raise ValueError("centroid.nearest: the pattern is too small to measure D_f")
        # D_f without its known finite-size bias, in units of its uncertainty when larger
        bias = 0.0 if math.isnan(fit.bias) else fit.bias
        features["fractal_dimension"] = fit.dimension - bias
        scales = dict(FEATURES)
        scales["fractal_dimension"] = max(scales["fractal_dimension"], fit.error)
        x = np.array([features[k] / s for k, s in scales.items()])
        centroids = self.config.centroids
        points = np.array([[getattr(c, k) / s for k, s in scales.items()] for c in centroids])
        d = np.linalg.norm(points - x, axis=1)
        first, second = np.argsort(d)[:2]
        details = dict(features, distances=d.tolist())
        details.update(fractal_dimension=fit.dimension, fractal_dimension_error=fit.error)
        ratio = d[first] / d[second] if d[second] > 0 else 1.0
        pair = frozenset({centroids[first].regime, centroids[second].regime})
        if ratio > self.config.tie_ratio and pair in PAIRS:
            return Classification(PAIRS[pair], float(ratio), details)
        confidence = 1.0 - 0.5 * ratio if math.isfinite(ratio) else 0.5
        return Classification(centroids[first].regime, float(confidence), details)
