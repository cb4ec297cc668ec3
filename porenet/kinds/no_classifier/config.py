"""Built-in pattern classifiers (kinds ``rules``, ``theory`` and ``none``).

A classifier labels a finished run with a regime (docs/model.md section 7); the scene's
``[classifier]`` section picks one (default ``rules``), ``kind = "none"`` skips the analysis.
"""

from __future__ import annotations

from typing import Any, ClassVar, Literal

from porenet.config.base import ModelConfig


class NoClassifierConfig(ModelConfig):
    """No pattern analysis at the end of the run (nothing is built or computed)."""

    kind: Literal["none"] = "none"
    builds_nothing: ClassVar[bool] = True

    @classmethod
    def example_scene(cls) -> dict[str, Any]:
        """A small scene that skips the classification (the contract suite runs it)."""
        from porenet.kinds.scenes import INVASION, tiny_scene

        return tiny_scene(INVASION, classifier={"kind": "none"})
