"""Config of the 3-D cubic lattice, kind ``cubic`` (docs/lattices.md, "The cubic lattice").

numpy, pydantic and porenet's light modules only; the lattice, :mod:`porenet.kinds.cubic.model`,
is imported only when a scene builds it.
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

#: Most pores of a cubic lattice (8 M pores, 200^3, need ~2 GB for invasion percolation).
MAX_CUBIC_PORES = 64_000_000


def cubic_throat_count(shape: tuple[int, int, int]) -> int:
    """Throats of an ``nx x ny x nz`` cubic lattice: ``(nx-1) ny nz + nx (ny-1) nz + nx ny
    (nz-1)``."""
    nx, ny, nz = shape
    return (nx - 1) * ny * nz + nx * (ny - 1) * nz + nx * ny * (nz - 1)


class CubicLatticeConfig(ModelConfig):
    """A simple cubic lattice of ``nx x ny x nz`` pores with uncorrelated uniform apertures
    (docs/lattices.md, "The cubic lattice"); ``nz = 1`` is a 2-D lattice, and with ``nx = ny``
    it is the square lattice, to the bit."""

    kind: Literal["cubic"] = "cubic"
    shape: tuple[int, int, int] = Field(
        ...,
        description="Pores along x, y and z, [nx, ny, nz] (each >= 1, nx and ny >= 3); "
        "nz = 1 is a 2-D lattice. L = max(shape) a.",
    )
    pore_size: PoreSize = 1e-7
    disorder: Disorder = None
    mean_aperture: MeanAperture = None
    area_factor: AreaFactor = 1.0
    permeability_factor: PermeabilityFactor = 1.0
    volume_factor: VolumeFactor = 1.0
    apertures_file: AperturesFile = None

    @field_validator("shape")
    @classmethod
    def _shape(cls, value: tuple[int, int, int]) -> tuple[int, int, int]:
        nx, ny, nz = value
        if nx < 3 or ny < 3 or nz < 1:
            raise ValueError(f"needs nx >= 3, ny >= 3 and nz >= 1, got {list(value)}")
        if nx * ny * nz > MAX_CUBIC_PORES:
            raise ValueError(
                f"{nx * ny * nz:,} pores is more than the {MAX_CUBIC_PORES:,} this lattice allows"
            )
        return value

    @field_validator("apertures_file")
    @classmethod
    def _resolve(cls, value: Path | None, info: ValidationInfo) -> Path | None:
        path = resolve_input_file(value, info, ".npz or .npy file of apertures")
        shape = (info.data or {}).get("shape")
        if path is not None and shape is not None:
            load_cubic_apertures_file(path, shape)
        return path

    @model_validator(mode="after")
    def _check(self) -> CubicLatticeConfig:
        return needs_disorder(self)

    def site_names(self) -> tuple[str, ...]:
        """The named injection sites of this lattice (docs/lattices.md): z faces in 3-D."""
        faces = ("x-", "x+", "y-", "y+") + (("z-", "z+") if self.shape[2] > 1 else ())
        return ("centre", *faces, "left-edge")

    def extent(self) -> LatticeExtent:
        """The size the plan and the cost model read (:mod:`porenet.core.extent`); the face
        cross-section is the x face's (``left-edge``)."""
        nx, ny, nz = self.shape
        boundary = 2 * (nx + ny) if nz == 1 else 2 * (nx * ny + ny * nz + nz * nx)
        return LatticeExtent(
            pores=nx * ny * nz, throats=cubic_throat_count(self.shape),
            dimension=2 if nz == 1 else 3, side=max(self.shape),
            outlet_links={"centre": boundary, "face": ny * nz},
            canonical_grid=nz == 1 and nx == ny, disorder=self.disorder,
            size_field=f"lattice.shape = {list(self.shape)}",
        )  # fmt: skip

    @classmethod
    def example_scene(cls) -> dict[str, Any]:
        """A small scene on a 6 x 6 x 6 cubic lattice (the contract suite runs it)."""
        from porenet.kinds.scenes import INVASION, tiny_scene

        return tiny_scene(INVASION) | {
            "lattice": {"kind": "cubic", "shape": [6, 6, 6], "disorder": 0.3}
        }


def load_cubic_apertures_file(path: Path, shape: tuple[int, int, int]) -> np.ndarray:
    """The apertures (m) of an ``nx x ny x nz`` cubic lattice from a NumPy file, as
    :func:`load_apertures_file` (canonical order: x throats, then y, then z, each in pore
    order)."""
    nx, ny, nz = shape
    formula = "(nx-1) ny nz + nx (ny-1) nz + nx ny (nz-1)"
    order = "canonical order: x throats, then y, then z, each in pore order"
    size = f"shape = [{nx}, {ny}, {nz}]"
    return read_apertures(path, cubic_throat_count(shape), formula, size, order)
