"""The theory predictor: the regime of docs/model.md section 6 from the scene's Ca* and N_f."""

from __future__ import annotations

from typing import Any

from porenet.core.interfaces import Classification, Classifier
from porenet.kinds.theory.config import TheoryClassifierConfig as TheoryClassifierConfig


class TheoryClassifier(Classifier):
    """Places the run on the paper's phase diagram (Figs. 2-3) by its dimensionless numbers:
    the prediction ``porenet plan`` prints (:func:`porenet.core.plan.predicted_regime`)."""

    def classify(self, run: Any) -> Classification:
        """From the plan's prediction stored with the run (``plan_regime`` and its numbers in
        ``/summary``): a function of the run file alone. Run files written before porenet
        stored it are planned again from their scene (which needs the scene's plugins)."""
        data = getattr(run, "data", run)
        summary = getattr(data, "summary", None) or {}
        if "plan_regime" in summary:
            regime = summary["plan_regime"] or None  # "": the scene determines none
            confidence = summary.get("plan_regime_confidence")
            ca_star, nf = summary.get("plan_ca_star"), summary.get("plan_fracturing_number")
        else:
            regime, confidence, ca_star, nf = _planned_again(data.scene)
        if regime is None:
            raise ValueError(
                "theory: the scene determines no Ca* (no disorder, or no requested rate)"
            )
        details = {"ca_star": ca_star, "fracturing_number": nf}
        return Classification(str(regime), float(confidence), details)


def _planned_again(scene: dict[str, Any]) -> tuple[str | None, float | None, Any, Any]:
    """The prediction of an old run file's scene, planned again."""
    from porenet.config.loading import load_scene
    from porenet.core.plan import make_plan, plan_summary
    from porenet.hooks import get_registry

    registry = get_registry()
    numbers = plan_summary(make_plan(load_scene(scene, registry=registry), registry))
    return (numbers["plan_regime"] or None, numbers["plan_regime_confidence"],
            numbers["plan_ca_star"], numbers["plan_fracturing_number"])  # fmt: skip
