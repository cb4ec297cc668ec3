"""The theory predictor: the regime of docs/model.md section 6 from the scene's Ca* and N_f."""

from __future__ import annotations

from typing import Any

from porenet.builtin.classifiers.config import TheoryClassifierConfig as TheoryClassifierConfig
from porenet.core.interfaces import Classification, Classifier


class TheoryClassifier(Classifier):
    """Places the run on the paper's phase diagram (Figs. 2-3) by its dimensionless numbers:
    the prediction ``porenet plan`` prints (:func:`porenet.core.plan.predicted_regime`)."""

    def classify(self, run: Any) -> Classification:
        from porenet.config.loading import load_scene
        from porenet.core.plan import CA_STAR, FRACTURING_NUMBER, make_plan
        from porenet.hooks import get_registry

        data = getattr(run, "data", run)
        registry = get_registry()
        plan = make_plan(load_scene(data.scene, registry=registry), registry)
        if plan.regime is None:
            raise ValueError(
                "theory: the scene determines no Ca* (no disorder, or no requested rate)"
            )
        details = {
            "ca_star": plan.numbers.get(CA_STAR),
            "fracturing_number": plan.numbers.get(FRACTURING_NUMBER),
        }
        return Classification(plan.regime[0], plan.regime[1], details)
