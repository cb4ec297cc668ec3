"""Config of the theory classifier, kind ``theory``: the regime the plan predicted from Ca*
and N_f (docs/model.md section 6), looking at no pattern."""

from __future__ import annotations

from typing import Any, Literal

from porenet.config.base import ModelConfig


class TheoryClassifierConfig(ModelConfig):
    """Regime predicted from Ca* and N_f alone (docs/model.md section 6); looks at no pattern."""

    kind: Literal["theory"] = "theory"

    @classmethod
    def example_scene(cls) -> dict[str, Any]:
        """A small scene classified by this classifier (the contract suite runs it)."""
        from porenet.kinds.scenes import INVASION, tiny_scene

        return tiny_scene(INVASION, classifier={"kind": "theory"})
