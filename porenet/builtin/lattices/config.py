"""Config of the built-in square lattice, kind ``square``, and the aperture-file reader its
validation uses.

numpy, pydantic and porenet's light modules only, so that the scene schema, ``porenet
validate`` and ``porenet plan`` import no numerics beyond numpy; the lattice,
:mod:`porenet.builtin.lattices.square`, is imported only when a scene builds it.
"""

from __future__ import annotations

from pathlib import Path
from typing import Literal

import numpy as np
from pydantic import Field, ValidationInfo, field_validator, model_validator

from porenet.config.base import ModelConfig

MAX_N = 10_000


def load_apertures_file(path: Path, n: int) -> np.ndarray:
    """Read and check an ``apertures`` array (m) from an .npz file for an n x n lattice."""
    expected = 2 * n * (n - 1)
    try:
        with np.load(path, allow_pickle=False) as data:
            if "apertures" not in data.files:
                raise ValueError(
                    f"{path}: no array named 'apertures' (found: {', '.join(data.files) or 'none'})"
                )
            apertures = np.asarray(data["apertures"], dtype=np.float64)
    except (OSError, ValueError, EOFError) as exc:
        if isinstance(exc, ValueError) and str(exc).startswith(str(path)):
            raise
        raise ValueError(f"{path}: cannot read as .npz: {exc}") from None
    if apertures.shape != (expected,):
        raise ValueError(
            f"{path}: 'apertures' has shape {apertures.shape}, expected ({expected},) = "
            f"2 n (n-1) throats for n = {n} (canonical order: horizontal then vertical, row-major)"
        )
    bad = ~(np.isfinite(apertures) & (apertures > 0))
    if bad.any():
        first = int(np.flatnonzero(bad)[0])
        raise ValueError(
            f"{path}: {int(bad.sum())} aperture(s) are not positive and finite "
            f"(first: throat {first} = {apertures[first]!r})"
        )
    return apertures


class SquareLatticeConfig(ModelConfig):
    """The paper's ``n x n`` square lattice with uncorrelated uniform apertures."""

    kind: Literal["square"] = "square"
    n: int = Field(..., ge=3, le=MAX_N, description="Pores per side; L = n a. Paper: 400.")
    pore_size: float = Field(
        1e-7, gt=0, description="Pore size a (m), half the node spacing. Paper: 1e-7 m."
    )
    disorder: float | None = Field(
        None,
        gt=0,
        lt=1,
        description="Disorder lambda: apertures uniform in [(1-lambda) r_mean, (1+lambda) r_mean]."
        " Required unless apertures_file is given.",
    )
    mean_aperture: float | None = Field(
        None, gt=0, description="Mean aperture r_mean (m). Default: the pore size a."
    )
    area_factor: float = Field(1.0, gt=0, description="c_A in throat area A = c_A r^2 (-).")
    permeability_factor: float = Field(
        1.0, gt=0, description="c_k in throat permeability k = c_k r^2 (-)."
    )
    volume_factor: float = Field(1.0, gt=0, description="c_V in pore volume V = c_V a^3 (-).")
    apertures_file: Path | None = Field(
        None,
        description=".npz file with an 'apertures' array (m) in canonical throat order; a "
        "relative path is read from the scene file's directory.",
    )

    @field_validator("apertures_file")
    @classmethod
    def _resolve(cls, value: Path | None, info: ValidationInfo) -> Path | None:
        if value is None:
            return None
        base = (info.context or {}).get("base_dir")
        path = Path(value).expanduser()
        if not path.is_absolute() and base is not None:
            path = Path(base) / path
        if not path.is_file():
            raise ValueError(f"file not found: {path}")
        return path.resolve()

    @model_validator(mode="after")
    def _check(self) -> SquareLatticeConfig:
        if self.apertures_file is None and self.disorder is None:
            raise ValueError("'disorder' is required (or give 'apertures_file')")
        if self.apertures_file is not None:
            load_apertures_file(self.apertures_file, self.n)
        return self
