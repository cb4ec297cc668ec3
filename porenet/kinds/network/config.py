"""Config of the ``network`` lattice, networks imported from files (docs/lattices.md,
"Imported networks (kind `network`)").

numpy, pydantic and the file headers only (:func:`porenet.kinds.network.files.
describe`): validation reads an ``.npz``'s array headers and coordinates, or the first lines
of the Statoil files, never the whole network; the lattice
(:mod:`porenet.kinds.network.model`) reads it when a scene builds it.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any, Literal

from pydantic import Field, ValidationInfo, field_validator

from porenet.config.base import ModelConfig
from porenet.config.lattice_fields import scene_relative
from porenet.core.extent import LatticeExtent
from porenet.core.sites import FACES, face_of
from porenet.kinds.network.files import (
    SHAPE_FACTOR_KEY,
    NetworkHeader,
    describe,
    locate,
    missing_length,
)

#: The faces of a 2-D network's bounding box.
FACES_2D = ("x-", "x+", "y-", "y+")


class NetworkLatticeConfig(ModelConfig):
    """A pore network read from a file: an OpenPNM or PoreSpy network dict saved as ``.npz``,
    or the Statoil files of pnextract and pnflow (docs/lattices.md, "Imported networks (kind
    `network`)")."""

    kind: Literal["network"] = "network"
    file: Path = Field(
        ...,
        description="The network: an .npz of an OpenPNM/PoreSpy network dict (pore.coords, "
        "throat.conns, throat.inscribed_diameter or throat.diameter, throat.total_length, "
        "pore.volume, labels pore.<name>), or a Statoil network by one of its files "
        "<prefix>_node1.dat (node2, link1, link2 beside it) or its prefix; a relative path is "
        "read from the scene file's directory.",
    )
    pore_size: float = Field(
        ...,
        gt=0,
        description="Length unit a (m) of the run (pressures in gamma/a, the outlet's half "
        "throats of length a, Ca); no default, as networks differ in scale by orders of "
        "magnitude: take the file's mean throat radius for the paper's r_mean = a.",
    )
    throat_length: Literal["total", "throat", "centres"] = Field(
        "total",
        validate_default=True,
        description="Length of a throat, over which it conducts and holds fluid: 'total', "
        "pore centre to pore centre as the file gives it (throat.total_length, else OpenPNM "
        "3's throat.spacing; Statoil: link1's length), 'throat', the throat's own part "
        "(throat.length; Statoil: link2's throat length), or 'centres', the distance between "
        "the two pore centres.",
    )
    cross_sections: Literal["auto", "circle"] = Field(
        "auto",
        description="Throat cross-sections: 'auto' from the file's shape factor G where it "
        "has one (Statoil, throat.shape_factor: area r^2/(4G), triangle, square or circle by "
        "pnflow's thresholds), else circles; 'circle': every throat a circular cylinder.",
    )
    entry_pressure: Literal["cylinder", "shape-factor"] = Field(
        "cylinder",
        description="Capillary entry pressure of a throat of radius r: 'cylinder', 2 gamma/r; "
        "'shape-factor', (1 + 2 sqrt(pi G)) gamma/r (Mayer-Stowe-Princen, zero contact "
        "angle; needs the file's shape factor G).",
    )
    face_tolerance: float | None = Field(
        None,
        gt=0,
        description="Distance (m) from a face of the bounding box within which a pore lies on "
        "that face (sites 'x-', ..., and the boundary when the file has no pore.surface "
        "label). Default: half the median distance between joined pore centres.",
    )
    outlet: str | None = Field(
        None,
        description="The outlet, where the defender leaves: a label of the file "
        "('pore.right', Statoil 'outlet'), a face ('x+', ...) or 'boundary'. Default: the "
        "face opposite an injection face, else the boundary pores that are not inlets.",
    )

    @field_validator("file")
    @classmethod
    def _resolve(cls, value: Path, info: ValidationInfo) -> Path:
        path = scene_relative(value, info)
        if path.is_dir():
            raise ValueError(f"{path} is a directory; give the .npz file or a Statoil file")
        _, found = locate(path)
        describe(found)  # the required keys and their shapes
        return found.resolve()

    @field_validator("throat_length")
    @classmethod
    def _has_length(cls, value: str, info: ValidationInfo) -> str:
        header = _header(info)
        if header is not None and not header.has_length(value):
            raise ValueError(missing_length(header.path, value))
        return value

    @field_validator("entry_pressure")
    @classmethod
    def _has_shape_factor(cls, value: str, info: ValidationInfo) -> str:
        header = _header(info)
        if value == "shape-factor" and header is not None and not header.has_shape_factor:
            raise ValueError(f"{header.path}: no array {SHAPE_FACTOR_KEY!r} (the shape factor G)")
        return value

    @field_validator("outlet")
    @classmethod
    def _known_outlet(cls, value: str | None, info: ValidationInfo) -> str | None:
        header = _header(info)
        if value is None or header is None:
            return value
        known = ("boundary", *_faces(header), *header.labels)
        if value not in known and face_of(value) not in known:
            raise ValueError(
                f"not an outlet of {header.path.name}: expected one of {', '.join(known)}"
            )
        return value

    def site_names(self) -> tuple[str, ...]:
        """The named injection sites: the centre, the faces (z faces unless the network is
        known to be 2-D) and the file's labels."""
        header = describe(self.file)
        return ("centre", *_faces(header), "left-edge", *header.labels)

    def extent(self) -> LatticeExtent:
        """The size the plan and the cost model read (:mod:`porenet.core.extent`), from the
        file's header: pores and throats exactly; the side and the outlet cross-section as
        those of a cubic (or square) lattice of as many pores, an estimate (the file's
        geometry is known only once it is read)."""
        header = describe(self.file)
        d = header.dimension or 3
        side = max(1, round(header.n_pores ** (1.0 / d)))
        face = side ** (d - 1)
        return LatticeExtent(
            pores=header.n_pores, throats=header.n_throats, dimension=d, side=side,
            outlet_links={"centre": 2 * d * face, "face": face}, canonical_grid=False,
            disorder=None, size_field=f"lattice.file = {self.file.name}",
        )  # fmt: skip

    @classmethod
    def example_scene(cls) -> dict[str, Any]:
        """A small scene on a network shipped with porenet (OpenPNM's ``Cubic(shape=[8, 6, 1])``
        with its ``spheres_and_cylinders`` geometry, written by
        ``tests/data/networks/make_reference_networks.py``), from its left face to its right
        one (the contract suite runs it)."""
        from porenet.kinds.scenes import INVASION

        network = Path(__file__).resolve().parent / "data" / "openpnm-cubic-8x6.npz"
        return {
            "seed": 1,
            "lattice": {
                "kind": "network",
                "file": str(network),
                "pore_size": 9.93e-6,  # the file's mean throat radius (m)
                "outlet": "pore.right",
            },
            "fluid": INVASION,
            "injection": {"at": "pore.left"},
            "classifier": {"kind": "none"},  # 20 pores: too few to classify
        }


def _header(info: ValidationInfo) -> NetworkHeader | None:
    """The description of the validated ``file`` (None if it failed: reported on its own)."""
    path = (info.data or {}).get("file")
    return None if path is None else describe(path)


def _faces(header: NetworkHeader) -> tuple[str, ...]:
    return FACES_2D if header.dimension == 2 else tuple(FACES)
