"""The regime the plan predicted for a run, as a classifier's verdict.

``porenet plan`` predicts a regime from the scene's dimensionless numbers (docs/model.md
section 6) and the run stores it in its ``/summary`` (``plan_regime``, ``plan_ca_star``, ...;
:func:`porenet.core.plan.plan_summary`): a function of the run file alone. The analysis falls
back on it when a classifier cannot judge a pattern, and the ``theory`` classifier returns it.
"""

from __future__ import annotations

from typing import Any

from porenet.core.interfaces import Classification


def planned_verdict(run: Any) -> Classification:
    """The plan's predicted regime of ``run`` (a RunResult or a run file's RunData) and its
    confidence, with Ca* and N_f as details. Run files written before porenet stored the
    prediction are planned again from their scene (which needs the scene's plugins).

    Raises
    ------
    ValueError
        When the scene determines no prediction (no disorder, or no requested rate).
    """
    data = getattr(run, "data", run)
    summary = getattr(data, "summary", None) or {}
    if "plan_regime" in summary:
        regime = summary["plan_regime"] or None  # "": the scene determines none
        confidence = summary.get("plan_regime_confidence")
        ca_star, nf = summary.get("plan_ca_star"), summary.get("plan_fracturing_number")
    else:
        regime, confidence, ca_star, nf = _planned_again(data.scene)
    if regime is None:
        raise ValueError("theory: the scene determines no Ca* (no disorder, or no requested rate)")
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
