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


#: The first bytes of a NumPy .npy file and of an .npz (zip) archive.
NPY_MAGIC = b"\x93NUMPY"
NPZ_MAGICS = (b"PK\x03\x04", b"PK\x05\x06")


def _expected(n: int) -> str:
    return (
        f"expected an .npz file with an array named 'apertures' (numpy.savez(path, "
        f"apertures=a)) or an .npy file (numpy.save(path, a)) of 2 n (n-1) = {2 * n * (n - 1)} "
        f"positive, finite floats, the apertures in metres for n = {n}"
    )


def _read_array(path: Path, n: int) -> np.ndarray:
    """The raw array of an .npy or .npz file, never unpickling anything."""
    try:
        with path.open("rb") as fh:
            magic = fh.read(6)
    except OSError as exc:
        raise ValueError(f"cannot read {path}: {exc.strerror or exc}") from None
    npz = magic.startswith(NPZ_MAGICS)
    if not npz and magic != NPY_MAGIC:
        raise ValueError(f"{path} is not a NumPy file ({_what_it_is(magic)}); {_expected(n)}")
    try:
        if not npz:
            return np.load(path, allow_pickle=False)
        with np.load(path, allow_pickle=False) as data:
            if "apertures" not in data.files:
                found = ", ".join(data.files) or "none"
                raise ValueError(
                    f"{path} has no array named 'apertures' (found: {found}); {_expected(n)}"
                )
            return data["apertures"]
    except ValueError as exc:
        if str(exc).startswith(str(path)):
            raise
        if "pickle" in str(exc).lower() or "object arrays" in str(exc).lower():
            raise ValueError(f"{path} holds Python objects, not numbers; {_expected(n)}") from None
        raise ValueError(f"{path} is damaged ({exc}); {_expected(n)}") from None
    except Exception as exc:  # a damaged zip or header: zipfile, EOF, OSError
        raise ValueError(f"{path} is damaged ({exc}); {_expected(n)}") from None


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
    raw = _read_array(path, n)
    expected = 2 * n * (n - 1)
    if raw.dtype.kind != "f":
        raise ValueError(f"{path} holds {raw.dtype} values, not floats; {_expected(n)}")
    if raw.shape != (expected,):
        raise ValueError(
            f"{path}: 'apertures' has shape {raw.shape}, expected ({expected},) = "
            f"2 n (n-1) throats for n = {n} (canonical order: horizontal then vertical, row-major)"
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
        description=".npz file with an 'apertures' array, or .npy file of the array: the "
        "throat apertures (m) in canonical throat order; a relative path is read from the "
        "scene file's directory.",
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
        if path.is_dir():
            raise ValueError(f"{path} is a directory; give the .npz or .npy file of apertures")
        if not path.is_file():
            raise ValueError(f"file not found: {path}")
        path = path.resolve()
        n = (info.data or {}).get("n")
        if n is not None:  # (an invalid n is reported on its own)
            load_apertures_file(path, n)
        return path

    @model_validator(mode="after")
    def _check(self) -> SquareLatticeConfig:
        if self.apertures_file is None and self.disorder is None:
            raise ValueError("'disorder' is required (or give 'apertures_file')")
        return self
