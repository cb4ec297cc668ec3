"""Config of the rule-based pattern classifier, kind ``rules`` (docs/classification.md).

Pure Python (pydantic and porenet's light modules), so that the scene schema, ``porenet
validate`` and ``porenet plan`` import neither scipy nor the pattern analysis; the
classifier, :mod:`porenet.kinds.rules.model`, is imported only when a run classifies.
"""

from __future__ import annotations

from typing import Any, Literal

from pydantic import Field, model_validator

from porenet.config.base import ModelConfig


class RulesClassifierConfig(ModelConfig):
    """Rule-based regime from D_f, finger width and straight runs (docs/classification.md)."""

    kind: Literal["rules"] = "rules"
    fracture_fraction: float = Field(
        0.5,
        gt=0,
        le=1,
        description="Fraction of drained pores in thin straight runs, or entered through "
        "opened throats (deformable media), for FR.",
    )
    fracture_onset: float = Field(
        0.15, ge=0, le=1, description="Fraction from which FR/CF or FR/VF is reported."
    )
    width_split: float = Field(
        1.5, gt=1, description="Mean finger width (pores) between VF (below) and CF (above)."
    )
    width_scale: float = Field(
        0.3, gt=0, description="Width difference (pores) that makes the width vote certain."
    )
    dimension_split: float = Field(
        1.73, gt=1, lt=2, description="Bias-corrected D_f between VF (below) and CF (above)."
    )
    dimension_scale: float = Field(
        0.09, gt=0, description="D_f difference that makes the D_f vote certain."
    )
    intermediate_band: float = Field(
        0.25, ge=0, lt=1, description="Votes closer to 0 than this give CF/VF."
    )
    min_drained: int = Field(
        20, ge=2, description="Smaller patterns fall back on the theory predictor."
    )

    @model_validator(mode="after")
    def _ordered(self) -> RulesClassifierConfig:
        if self.fracture_onset > self.fracture_fraction:
            raise ValueError(
                f"fracture_onset ({self.fracture_onset}) must not exceed "
                f"fracture_fraction ({self.fracture_fraction})"
            )
        return self

    @classmethod
    def example_scene(cls) -> dict[str, Any]:
        """A small scene classified by this classifier (the contract suite runs it)."""
        from porenet.kinds.scenes import INVASION, tiny_scene

        return tiny_scene(INVASION, classifier={"kind": "rules"})
