"""Classify a finished run and produce the ``/summary`` attributes of issue 5.

:func:`classify_run` is what ``porenet run`` (at the end of a run) and ``porenet classify``
call: it asks a :class:`~porenet.core.interfaces.Classifier` for a verdict and adds the
pattern's fractal dimension (mass against distance from the inlet, docs/fractal.md).
"""

from __future__ import annotations

import logging
import math
from typing import TYPE_CHECKING, Any

from porenet.analysis.regimes import REGIMES
from porenet.core.errors import PluginError
from porenet.core.interfaces import Classification

log = logging.getLogger(__name__)

if TYPE_CHECKING:  # pragma: no cover
    from porenet.analysis.fractal import FractalFit
    from porenet.core.interfaces import Classifier
    from porenet.result import RunData

#: Attributes :func:`classify_run` returns (and the run file's ``/summary`` gains).
SUMMARY_KEYS = (
    "fractal_dimension",
    "fractal_dimension_error",
    "fractal_dimension_note",
    "regime",
    "regime_confidence",
    "classifier",
    "classifier_note",
)


def measure_dimension(data: RunData) -> FractalFit | None:
    """The pattern's D_f (:func:`porenet.analysis.fractal.pattern_dimension`), or ``None``
    when the pattern cannot be measured (too few drained pores, no grid)."""
    return dimension_or_reason(data)[0]


def dimension_or_reason(data: RunData) -> tuple[FractalFit | None, str]:
    """The pattern's D_f, or ``None`` and the reason it cannot be measured."""
    from porenet.analysis.fractal import pattern_dimension

    try:
        fit = pattern_dimension(data)
    except ValueError as exc:
        return None, f"D_f not measured: {exc}"
    if not math.isfinite(fit.dimension):
        return None, "D_f not measured: the fit gave no finite slope"
    return fit, ""


#: Labels with a fracturing part, and what remains of each in a medium that cannot fracture.
FRACTURING = {"FR": None, "FR/VF": "VF", "FR/CF": "CF"}


def _rigid(data: RunData) -> bool:
    """The run's medium could not deform (:func:`porenet.core.plan.scene_is_deformable`)."""
    from porenet.core.plan import scene_is_deformable

    return not scene_is_deformable(getattr(data, "scene", None) or {}, data.summary)


def _without_fracturing(
    data: RunData, verdict: Classification, kind: str
) -> tuple[Classification, str]:
    """A rigid medium cannot fracture: a fracturing label (straight runs of weak disorder look
    like fractures) becomes its fingering part, or, for plain FR, the rules' fingering vote or
    the theory prediction, at half the confidence; the note says so."""
    regime = FRACTURING[verdict.regime]
    if regime is None:
        vote = verdict.details.get("fingering_vote")
        if vote is not None and math.isfinite(float(vote)):
            regime = "CF" if float(vote) > 0 else "VF"
        else:
            theory, _ = _theory(data)
            regime = "VF" if theory is None or theory.regime.startswith("FR") else theory.regime
    note = (
        f"{kind} said {verdict.regime} in a rigid medium, which cannot fracture (straight runs "
        f"of weak disorder); labelled {regime}, confidence halved"
    )
    log.warning("%s", note)
    return Classification(regime, 0.5 * float(verdict.confidence), verdict.details), note


def _theory(data: RunData) -> tuple[Classification | None, str]:
    """The plan's prediction stored with the run as a verdict
    (:func:`porenet.analysis.prediction.planned_verdict`), or None and why the scene
    determines none."""
    from porenet.analysis.prediction import planned_verdict

    try:
        return planned_verdict(data), ""
    except ValueError as exc:
        return None, str(exc)


def _theory_instead(data: RunData, why: str) -> tuple[Classification | None, str]:
    """The theory prediction with half its confidence, or None if the scene has none."""
    theory, reason = _theory(data)
    if theory is None:
        note = f"{why}; no theory prediction either ({reason}): not classified"
        log.warning("%s", note)
        return None, note
    note = f"{why}; theory prediction, confidence halved"
    log.warning("%s", note)
    return Classification(theory.regime, 0.5 * theory.confidence, theory.details), note


def classify_run(data: RunData, classifier: Classifier, kind: str) -> dict[str, Any]:
    """The summary attributes of :data:`SUMMARY_KEYS` for one run, and ``physics_warnings``.

    ``fractal_dimension`` and its error are ``nan`` when the pattern cannot be measured, and
    ``fractal_dimension_note`` then says why (empty otherwise). A fracturing label (FR, FR/VF,
    FR/CF) in a rigid medium is replaced by its fingering part at half the confidence, with a
    note (docs/classification.md). A
    classifier that cannot judge the pattern (it raises ``ValueError``) is replaced by the
    theory predictor with half its confidence, and ``classifier_note`` says so (it is empty
    otherwise); if the scene determines no theory prediction either, ``regime`` and
    ``regime_confidence`` are ``None`` (not written to the run file). The run file of a long
    run is never lost to its analysis. ``physics_warnings`` is the run's suspect-result
    sentences (:func:`porenet.analysis.suspect.suspect_physics`), plus one when the label and
    the theory's prediction share no regime (:func:`~porenet.analysis.suspect.regime_disagreement`).

    Raises
    ------
    PluginError
        If the classifier returns a label outside :data:`~porenet.analysis.regimes.REGIMES`
        or a confidence outside [0, 1].
    """
    note = ""
    try:
        verdict: Classification | None = classifier.classify(data)
    except (ValueError, ArithmeticError) as exc:  # an unmeasurable pattern must not lose a run
        verdict, note = _theory_instead(data, f"{kind} failed ({exc})")
    if verdict is not None:
        if verdict.regime not in REGIMES:
            raise PluginError(
                f"classifier {kind!r} returned regime {verdict.regime!r}; "
                f"expected one of {', '.join(REGIMES)}"
            )
        if not 0.0 <= float(verdict.confidence) <= 1.0:
            raise PluginError(
                f"classifier {kind!r} returned confidence {verdict.confidence}, not in [0, 1]"
            )
        if verdict.regime in FRACTURING and _rigid(data):
            verdict, rigid_note = _without_fracturing(data, verdict, kind)
            note = f"{note}; {rigid_note}" if note else rigid_note
    details = {} if verdict is None else verdict.details
    warnings = _physics_warnings(data, None if verdict is None else verdict.regime, kind)
    if "fractal_dimension" in details and math.isfinite(float(details["fractal_dimension"])):
        dimension = float(details["fractal_dimension"])
        error = float(details.get("fractal_dimension_error", math.nan))
        why = ""
    else:
        fit, why = dimension_or_reason(data)
        dimension, error = (math.nan, math.nan) if fit is None else (fit.dimension, fit.error)
    return {
        "fractal_dimension": dimension,
        "fractal_dimension_error": error,
        "fractal_dimension_note": why,
        "regime": None if verdict is None else verdict.regime,
        "regime_confidence": None if verdict is None else float(verdict.confidence),
        "classifier": kind,
        "classifier_note": note,
        "physics_warnings": warnings,
    }


def _physics_warnings(data: RunData, regime: str | None, kind: str) -> str:
    """The run's suspect-result sentences (recomputed from its summary), with the
    disagreement of ``regime`` and the theory's prediction added when they share no regime
    (docs/stability.md, "Suspect results"); that sentence is logged."""
    from porenet.analysis.suspect import regime_disagreement, suspect_physics

    found = suspect_physics(dict(data.summary), len(data.throat_pores))
    if regime is not None:
        theory, _ = _theory(data)
        if theory is not None:
            sentence = regime_disagreement(regime, theory.regime, kind, theory.details)
            if sentence is not None:
                log.warning("suspect result: %s", sentence)
                found.append(sentence)
    return "; ".join(found)


def describe(summary: dict[str, Any]) -> str:
    """One line for people: the regime, its confidence and classifier, and D_f."""
    if summary.get("regime") is None:
        return f"not classified: {summary.get('classifier_note', '')}"
    dimension = float(summary.get("fractal_dimension", math.nan))
    if math.isfinite(dimension):
        measured = f"D_f = {dimension:.3f} ± {summary['fractal_dimension_error']:.3f}"
    else:  # a stated reason, never "nan ± nan"
        measured = summary.get("fractal_dimension_note") or "D_f not measured"
    return (
        f"{summary['regime']} (confidence {summary['regime_confidence']:.2f}, "
        f"{summary['classifier']}), {measured}"
    )
