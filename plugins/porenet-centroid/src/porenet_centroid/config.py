"""Config of the ``centroid.nearest`` classifier (imported when the plugin registers)."""

from __future__ import annotations

from typing import Any, Literal

from pydantic import BaseModel, ConfigDict, Field, field_validator

from porenet.config.base import ModelConfig

#: The features a centroid is placed in, with the scale each is divided by (a difference of
#: one scale counts as much in every direction).
FEATURES: dict[str, float] = {
    "fractal_dimension": 0.1,
    "finger_width_mean": 0.3,
    "thin_run_fraction": 0.2,
}


class Centroid(BaseModel):
    """One regime's typical pattern, in the units of :data:`FEATURES`."""

    model_config = ConfigDict(extra="forbid", frozen=True)
    regime: Literal["CF", "VF", "FR"]
    fractal_dimension: float = Field(gt=0, le=2, description="D_f (-).")
    finger_width_mean: float = Field(ge=1, description="Mean finger width (pores).")
    thin_run_fraction: float = Field(ge=0, le=1, description="Drained fraction in thin runs.")


#: Defaults: the paper's D_f per regime (docs/model.md section 7) with the widths and thin-run
#: fractions porenet's calibration ensembles give (docs/classification.md).
DEFAULT_CENTROIDS = (
    Centroid(regime="CF", fractal_dimension=1.82, finger_width_mean=1.85, thin_run_fraction=0.0),
    Centroid(regime="VF", fractal_dimension=1.64, finger_width_mean=1.2, thin_run_fraction=0.01),
    Centroid(regime="FR", fractal_dimension=1.43, finger_width_mean=1.0, thin_run_fraction=0.9),
)


class CentroidClassifierConfig(ModelConfig):
    """Nearest regime centroid in (D_f, finger width, thin-run fraction); porenet-centroid."""

    kind: Literal["centroid.nearest"] = "centroid.nearest"
    centroids: tuple[Centroid, ...] = Field(
        DEFAULT_CENTROIDS, description="One centroid per regime (CF, VF, FR), each once."
    )
    tie_ratio: float = Field(
        0.8,
        gt=0,
        lt=1,
        description="Nearest over second-nearest distance above which the intermediate "
        "label of the two regimes is given.",
    )

    @field_validator("centroids")
    @classmethod
    def _one_per_regime(cls, value: tuple[Centroid, ...]) -> tuple[Centroid, ...]:
        regimes = [c.regime for c in value]
        if len(value) < 2 or len(set(regimes)) != len(regimes):
            raise ValueError(f"need at least two centroids, one per regime; got {regimes}")
        return value

    @classmethod
    def example_scene(cls) -> dict[str, Any]:
        """A small scene classified by this classifier, for porenet's contract suite
        (docs/contract.md): the smallest lattice whose pattern it can measure."""
        lattice = {"n": 20, "disorder": 0.3}
        return {"lattice": lattice, "fluid": {}, "classifier": {"kind": "centroid.nearest"}}
