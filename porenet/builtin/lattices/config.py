"""Configs of the built-in lattices, kinds ``square`` and ``cubic``, and the aperture-file
reader their validation uses.

numpy, pydantic and porenet's light modules only, so that the scene schema, ``porenet
validate`` and ``porenet plan`` import no numerics beyond numpy; the lattice,
:mod:`porenet.builtin.lattices.square`, is imported only when a scene builds it.
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Any, Literal

import numpy as np
from pydantic import Field, ValidationInfo, field_validator, model_validator

from porenet.config.base import ModelConfig
from porenet.core.extent import LatticeExtent

MAX_N = 10_000


#: The first bytes of a NumPy .npy file and of an .npz (zip) archive.
NPY_MAGIC = b"\x93NUMPY"
NPZ_MAGICS = (b"PK\x03\x04", b"PK\x05\x06")


def _expected(count: int, formula: str, size: str) -> str:
    return (
        f"expected an .npz file with an array named 'apertures' (numpy.savez(path, "
        f"apertures=a)) or an .npy file (numpy.save(path, a)) of {formula} = {count} "
        f"positive, finite floats, the apertures in metres for {size}"
    )


def _read_array(path: Path, expected: str) -> np.ndarray:
    """The raw array of an .npy or .npz file, never unpickling anything (``expected`` says
    what the file should hold, for the messages)."""
    try:
        with path.open("rb") as fh:
            magic = fh.read(6)
    except OSError as exc:
        raise ValueError(f"cannot read {path}: {exc.strerror or exc}") from None
    npz = magic.startswith(NPZ_MAGICS)
    if not npz and magic != NPY_MAGIC:
        raise ValueError(f"{path} is not a NumPy file ({_what_it_is(magic)}); {expected}")
    try:
        if not npz:
            return np.load(path, allow_pickle=False)
        with np.load(path, allow_pickle=False) as data:
            if "apertures" not in data.files:
                found = ", ".join(data.files) or "none"
                raise ValueError(
                    f"{path} has no array named 'apertures' (found: {found}); {expected}"
                )
            return data["apertures"]
    except ValueError as exc:
        if str(exc).startswith(str(path)):
            raise
        if "pickle" in str(exc).lower() or "object arrays" in str(exc).lower():
            raise ValueError(f"{path} holds Python objects, not numbers; {expected}") from None
        raise ValueError(f"{path} is damaged ({exc}); {expected}") from None
    except Exception as exc:  # a damaged zip or header: zipfile, EOF, OSError
        raise ValueError(f"{path} is damaged ({exc}); {expected}") from None


def _what_it_is(magic: bytes) -> str:
    if not magic:
        return "it is empty"
    if magic[:1] == b"\x80":
        return "it looks like a Python pickle"
    if all(32 <= c < 127 or c in (9, 10, 13) for c in magic):
        return "it looks like a text file"
    return "unknown content"


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


def read_apertures(path: Path, count: int, formula: str, size: str, order: str) -> np.ndarray:
    """Read and check ``count`` apertures (m) from a NumPy file (as
    :func:`load_apertures_file`); ``formula`` and ``size`` say how the count follows from the
    lattice's size (``"2 n (n-1)"``, ``"n = 10"``) and ``order`` the canonical throat order,
    for the messages."""
    expected = _expected(count, formula, size)
    raw = _read_array(path, expected)
    if raw.dtype.kind != "f":
        raise ValueError(f"{path} holds {raw.dtype} values, not floats; {expected}")
    if raw.shape != (count,):
        raise ValueError(
            f"{path}: 'apertures' has shape {raw.shape}, expected ({count},) = {formula} "
            f"throats for {size} ({order})"
        )
    apertures = np.asarray(raw, dtype=np.float64)
    bad = ~(np.isfinite(apertures) & (apertures > 0))
    if bad.any():
        first = int(np.flatnonzero(bad)[0])
        raise ValueError(
            f"{path}: {int(bad.sum())} aperture(s) are not positive and finite "
            f"(first: throat {first} = {float(apertures[first])!r})"
        )
    return apertures


#: Fields every built-in lattice of drawn apertures shares (their descriptions are the
#: schema's and docs/configuration.md's).
PoreSize = Annotated[
    float, Field(gt=0, description="Pore size a (m), half the node spacing. Paper: 1e-7 m.")
]
Disorder = Annotated[
    float | None,
    Field(
        gt=0,
        lt=1,
        description="Disorder lambda: apertures uniform in [(1-lambda) r_mean, (1+lambda) r_mean]."
        " Required unless apertures_file is given.",
    ),
]
MeanAperture = Annotated[
    float | None, Field(gt=0, description="Mean aperture r_mean (m). Default: the pore size a.")
]
AreaFactor = Annotated[float, Field(gt=0, description="c_A in throat area A = c_A r^2 (-).")]
PermeabilityFactor = Annotated[
    float, Field(gt=0, description="c_k in throat permeability k = c_k r^2 (-).")
]
VolumeFactor = Annotated[float, Field(gt=0, description="c_V in pore volume V = c_V a^3 (-).")]
AperturesFile = Annotated[
    Path | None,
    Field(
        description=".npz file with an 'apertures' array, or .npy file of the array: the "
        "throat apertures (m) in canonical throat order; a relative path is read from the "
        "scene file's directory.",
    ),
]


def scene_relative(value: Path | str, info: ValidationInfo) -> Path:
    """A path given in a scene, relative to the scene file's directory (the validation
    context's ``base_dir``) unless absolute; ``~`` expanded."""
    base = (info.context or {}).get("base_dir")
    path = Path(value).expanduser()
    if not path.is_absolute() and base is not None:
        path = Path(base) / path
    return path


def resolve_input_file(value: Path | None, info: ValidationInfo, what: str) -> Path | None:
    """An input file of a lattice config, relative to the scene file's directory
    (:func:`scene_relative`), checked to exist; ``what`` names it in the errors."""
    if value is None:
        return None
    path = scene_relative(value, info)
    if path.is_dir():
        raise ValueError(f"{path} is a directory; give the {what}")
    if not path.is_file():
        raise ValueError(f"file not found: {path}")
    return path.resolve()


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
        return _needs_disorder(self)

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


def _needs_disorder(config: Any) -> Any:
    if config.apertures_file is None and config.disorder is None:
        raise ValueError("'disorder' is required (or give 'apertures_file')")
    return config


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
        return _needs_disorder(self)

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


def load_cubic_apertures_file(path: Path, shape: tuple[int, int, int]) -> np.ndarray:
    """The apertures (m) of an ``nx x ny x nz`` cubic lattice from a NumPy file, as
    :func:`load_apertures_file` (canonical order: x throats, then y, then z, each in pore
    order)."""
    nx, ny, nz = shape
    formula = "(nx-1) ny nz + nx (ny-1) nz + nx ny (nz-1)"
    order = "canonical order: x throats, then y, then z, each in pore order"
    size = f"shape = [{nx}, {ny}, {nz}]"
    return read_apertures(path, cubic_throat_count(shape), formula, size, order)
