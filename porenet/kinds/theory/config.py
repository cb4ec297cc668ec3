"""Config of the theory classifier, kind ``theory``: the regime the plan predicted from Ca*
and N_f (docs/model.md section 6), looking at no pattern."""

from __future__ import annotations

from typing import Literal

from porenet.config.base import ModelConfig


class TheoryClassifierConfig(ModelConfig):
    """Regime predicted from Ca* and N_f alone (docs/model.md section 6); looks at no pattern."""

    kind: Literal["theory"] = "theory"
