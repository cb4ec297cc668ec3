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
    "regime",
    "regime_confidence",
    "classifier",
    "classifier_note",
)


def measure_dimension(data: RunData) -> FractalFit | None:
    """The pattern's D_f (:func:`porenet.analysis.fractal.pattern_dimension`), or ``None``
    when the pattern cannot be measured (too few drained pores, no grid)."""
    from porenet.analysis.fractal import pattern_dimension

    try:
        return pattern_dimension(data)
    except ValueError:
        return None


def _theory_instead(data: RunData, why: str) -> tuple[Classification | None, str]:
    """The theory prediction with half its confidence, or None if the scene has none."""
    from porenet.builtin.classifiers.theory import TheoryClassifier

    try:
        theory = TheoryClassifier().classify(data)
    except ValueError as exc:
        note = f"{why}; no theory prediction either ({exc}): not classified"
        log.warning("%s", note)
        return None, note
    note = f"{why}; theory prediction, confidence halved"
    log.warning("%s", note)
    return Classification(theory.regime, 0.5 * theory.confidence, theory.details), note


def classify_run(data: RunData, classifier: Classifier, kind: str) -> dict[str, Any]:
    """The summary attributes of :data:`SUMMARY_KEYS` for one run.

    ``fractal_dimension`` and its error are ``nan`` when the pattern cannot be measured. A
    classifier that cannot judge the pattern (it raises ``ValueError``) is replaced by the
    theory predictor with half its confidence, and ``classifier_note`` says so (it is empty
    otherwise); if the scene determines no theory prediction either, ``regime`` and
    ``regime_confidence`` are ``None`` (not written to the run file). The run file of a long
    run is never lost to its analysis.

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
    details = {} if verdict is None else verdict.details
    if "fractal_dimension" in details:
        dimension = float(details["fractal_dimension"])
        error = float(details.get("fractal_dimension_error", math.nan))
    else:
        fit = measure_dimension(data)
        dimension, error = (math.nan, math.nan) if fit is None else (fit.dimension, fit.error)
    return {
        "fractal_dimension": dimension,
        "fractal_dimension_error": error,
        "regime": None if verdict is None else verdict.regime,
        "regime_confidence": None if verdict is None else float(verdict.confidence),
        "classifier": kind,
        "classifier_note": note,
    }


def describe(summary: dict[str, Any]) -> str:
    """One line for people: the regime, its confidence and classifier, and D_f."""
    if summary.get("regime") is None:
        return f"not classified: {summary.get('classifier_note', '')}"
    return (
        f"{summary['regime']} (confidence {summary['regime_confidence']:.2f}, "
        f"{summary['classifier']}), D_f = {summary['fractal_dimension']:.3f} "
        f"± {summary['fractal_dimension_error']:.3f}"
    )
