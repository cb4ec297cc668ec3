"""Config of the paper's square lattice, kind ``square``, and its aperture-file reader.

numpy, pydantic and porenet's light modules only, so that the scene schema, ``porenet
validate`` and ``porenet plan`` import no numerics beyond numpy; the lattice,
:mod:`porenet.kinds.square.model`, is imported only when a scene builds it.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any, Literal

import numpy as np
from pydantic import Field, ValidationInfo, field_validator, model_validator

from porenet.config.base import ModelConfig
from porenet.config.lattice_fields import (
    AperturesFile,
    AreaFactor,
    Disorder,
    MeanAperture,
    PermeabilityFactor,
    PoreSize,
    VolumeFactor,
    needs_disorder,
    read_apertures,
    resolve_input_file,
)
from porenet.core.extent import LatticeExtent

#: Most pores a side.
MAX_N = 10_000


def load_apertures_file(path: Path, n: int) -> np.ndarray:
    """Read and check the apertures (m) of an ``n x n`` lattice from a NumPy file.

    The file is an ``.npz`` archive with an array named ``apertures``
    (``numpy.savez(path, apertures=a)``) or an ``.npy`` file holding the array
    (``numpy.save(path, a)``): ``2 n (n-1)`` positive, finite floats in canonical throat order
    (horizontal then vertical, row-major). Nothing is unpickled.

    Raises
    ------
    ValueError
        Naming the file, what is wrong with it and what is expected.
    """
    order = "canonical order: horizontal then vertical, row-major"
    return read_apertures(path, 2 * n * (n - 1), "2 n (n-1)", f"n = {n}", order)


class SquareLatticeConfig(ModelConfig):
    """The paper's ``n x n`` square lattice with uncorrelated uniform apertures."""

    kind: Literal["square"] = "square"
    n: int = Field(..., ge=3, le=MAX_N, description="Pores per side; L = n a. Paper: 400.")
    pore_size: PoreSize = 1e-7
    disorder: Disorder = None
    mean_aperture: MeanAperture = None
    area_factor: AreaFactor = 1.0
    permeability_factor: PermeabilityFactor = 1.0
    volume_factor: VolumeFactor = 1.0
    apertures_file: AperturesFile = None

    @field_validator("apertures_file")
    @classmethod
    def _resolve(cls, value: Path | None, info: ValidationInfo) -> Path | None:
        path = resolve_input_file(value, info, ".npz or .npy file of apertures")
        n = (info.data or {}).get("n")
        if path is not None and n is not None:  # (an invalid n is reported on its own)
            load_apertures_file(path, n)
        return path

    @model_validator(mode="after")
    def _check(self) -> SquareLatticeConfig:
        return needs_disorder(self)

    def site_names(self) -> tuple[str, ...]:
        """The named injection sites of this lattice (docs/lattices.md)."""
        return ("centre", "x-", "x+", "y-", "y+", "left-edge")

    def extent(self) -> LatticeExtent:
        """The size the plan and the cost model read (:mod:`porenet.core.extent`)."""
        n = self.n
        return LatticeExtent(
            pores=n * n, throats=2 * n * (n - 1), dimension=2, side=n,
            outlet_links={"centre": 4 * n, "face": n}, canonical_grid=True,
            disorder=self.disorder, size_field=f"lattice.n = {n}",
        )  # fmt: skip

    @classmethod
    def example_scene(cls) -> dict[str, Any]:
        """A small scene on this lattice (the contract suite runs it)."""
        from porenet.kinds.scenes import INVASION, tiny_scene

        return tiny_scene(INVASION)
