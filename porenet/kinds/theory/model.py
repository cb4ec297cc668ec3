"""The theory predictor: the regime of docs/model.md section 6 from the scene's Ca* and N_f."""

from __future__ import annotations

from typing import Any

from porenet.analysis.prediction import planned_verdict
from porenet.core.interfaces import Classification, Classifier
from porenet.kinds.theory.config import TheoryClassifierConfig as TheoryClassifierConfig


class TheoryClassifier(Classifier):
    """Places the run on the paper's phase diagram (Figs. 2-3) by its dimensionless numbers:
    the prediction ``porenet plan`` prints (:func:`porenet.core.plan.predicted_regime`)."""

    def classify(self, run: Any) -> Classification:
        """From the plan's prediction stored with the run
        (:func:`porenet.analysis.prediction.planned_verdict`): a function of the run file
        alone."""
        return planned_verdict(run)
