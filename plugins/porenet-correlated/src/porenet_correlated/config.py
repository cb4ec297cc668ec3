"""Config of the ``correlated.gaussian`` lattice (pydantic only; no numerics imported here)."""

from __future__ import annotations

from pathlib import Path
from typing import Any, Literal

from pydantic import Field, field_validator

from porenet.kinds.square.config import SquareLatticeConfig

KIND = "correlated.gaussian"

#: Largest accepted correlation length (pores). Longer lengths make the field a single smooth
#: ramp across any practical lattice and only cost memory.
MAX_CORRELATION_LENGTH = 1000.0


class CorrelatedLatticeConfig(SquareLatticeConfig):
    """The paper's ``n x n`` square lattice with spatially correlated uniform apertures.

    Same geometry and fields as ``square``; the apertures have the same uniform marginal on
    [(1-lambda) r_mean, (1+lambda) r_mean], arranged in space by a Gaussian random field whose
    kernel has standard deviation ``correlation_length`` pore spacings.
    """

    kind: Literal["correlated.gaussian"] = "correlated.gaussian"
    correlation_length: float = Field(
        ...,
        gt=0,
        le=MAX_CORRELATION_LENGTH,
        description="Correlation length l of the apertures, in pore spacings (2a, the distance "
        "between neighbouring pore centres; l pores = 2 a l m): standard deviation of the "
        "Gaussian smoothing kernel, so the field's covariance is exp(-d^2 / (4 l^2)) at a "
        "distance of d pores. 0 < l <= 1000.",
    )

    @field_validator("apertures_file")
    @classmethod
    def _no_apertures_file(cls, value: Path | None) -> Path | None:
        if value is not None:
            raise ValueError(
                f"not used by kind {KIND!r}, whose apertures are drawn from correlation_length "
                "and disorder; use kind 'square' to read apertures from a file"
            )
        return value

    @classmethod
    def example_scene(cls) -> dict[str, Any]:
        """A small scene on this lattice, for porenet's contract suite (docs/contract.md)."""
        lattice = {"kind": KIND, "n": 12, "disorder": 0.3, "correlation_length": 2.0}
        return {"seed": 1, "lattice": lattice, "fluid": {}}
