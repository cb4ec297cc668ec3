"""Fields and input files shared by lattice configs: the annotated fields of a lattice of
drawn apertures (:data:`PoreSize`, :data:`Disorder`, ...), the reader of aperture files
(:func:`read_apertures`, never unpickling) and scene-relative paths. numpy, pydantic and
porenet's light modules only: the built-in lattice configs (``porenet/kinds/square``,
``cubic``, ``network``) and a plugin's may use them.
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Any

import numpy as np
from pydantic import Field, ValidationInfo

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


def needs_disorder(config: Any) -> Any:
    """``config`` if it has drawn apertures (``disorder``) or a file of them; a ValueError
    otherwise (for a lattice config's ``model_validator``)."""
    if config.apertures_file is None and config.disorder is None:
        raise ValueError("'disorder' is required (or give 'apertures_file')")
    return config
