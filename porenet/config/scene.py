"""The scene schema: top-level fields plus one section per model family.

The model sections are discriminated unions over the registered config classes, so the schema
can only be built after plugins have loaded: :func:`scene_model` builds (and caches) it for a
registry.
"""

from __future__ import annotations

import functools
from typing import Annotated, Any, ClassVar, Literal, Union

from pydantic import Field, create_model, field_validator, model_validator

from porenet.config.base import CheckedModel
from porenet.core.registry import Registry
from porenet.core.sites import site_geometry

#: Sections filled with their default kind when a scene omits them.
DEFAULT_SECTIONS: tuple[str, ...] = ("solid", "classifier")


class InjectionConfig(CheckedModel):
    """Where the invading fluid enters.

    ``centre``: the pore nearest the centre (on the square lattice (i, j) = (n//2, n//2)), with
    the outlet along the whole outer boundary (the paper's geometry). A face of the lattice's
    bounding box, ``x-``, ``x+``, ``y-``, ``y+`` (and ``z-``, ``z+`` in 3-D): every pore of
    that face, with the outlet at the opposite face and the other faces closed (linear
    geometry); ``left-edge`` is ``x-``. A label of the lattice (an imported network's
    ``pore.inlet``, docs/lattices.md) or a list of pore indices: those pores, with the outlet
    the lattice's boundary (or its ``outlet`` setting).
    """

    at: str | list[int] = Field(
        "centre",
        description="Injection site: 'centre' (paper), a face ('x-', 'x+', 'y-', 'y+', 'z-', "
        "'z+'; 'left-edge' = 'x-'), a label of the lattice, or a list of pore indices.",
    )

    @field_validator("at")
    @classmethod
    def _site(cls, value: str | list[int]) -> str | list[int]:
        if isinstance(value, str):
            if not value.strip():
                raise ValueError("must name a site: 'centre', a face, a label or pore indices")
            return value
        if not value or min(value) < 0:
            raise ValueError("a list of pores must be non-empty and hold indices >= 0")
        return value

    @property
    def geometry(self) -> str:
        """:func:`site_geometry` of :attr:`at`."""
        return site_geometry(self.at)


class StopConfig(CheckedModel):
    """When a run ends (whichever comes first)."""

    at: Literal["breakthrough", "complete"] = Field(
        "breakthrough",
        description="'breakthrough': when the first pore connected to the outlet drains; "
        "'complete': when nothing more can be invaded.",
    )
    max_drained: int | None = Field(
        None, gt=0, description="Stop after this many drained pores (inlets included)."
    )


class SceneBase(CheckedModel):
    """Top-level fields of a scene. All physical inputs are SI."""

    #: The kind of a section that names none, by family: the registry's defaults
    #: (:meth:`porenet.core.registry.Registry.defaults`), set by :func:`scene_model`.
    default_kinds: ClassVar[dict[str, str]] = {}

    seed: int = Field(0, ge=0, description="Seed of the run's numpy Generator (the only RNG).")
    name: str = Field("", description="Free-text label copied into outputs.")
    injection: InjectionConfig = Field(default_factory=InjectionConfig)
    stop: StopConfig = Field(default_factory=StopConfig)

    @model_validator(mode="before")
    @classmethod
    def _default_kinds(cls, data: Any) -> Any:
        if isinstance(data, dict):
            data = dict(data)
            for section, kind in cls.default_kinds.items():
                value = data.get(section)
                if value is None and section in DEFAULT_SECTIONS:
                    data[section] = {"kind": kind}
                elif isinstance(value, dict) and "kind" not in value:
                    data[section] = {"kind": kind, **value}
        return data


def _union(configs: list[type]) -> Any:
    if len(configs) == 1:
        return configs[0]
    return Annotated[Union[tuple(configs)], Field(discriminator="kind")]  # noqa: UP007


@functools.cache
def scene_model(registry: Registry) -> type[SceneBase]:
    """Build the ``SceneConfig`` pydantic model for the kinds in ``registry``."""
    fields: dict[str, Any] = {
        "lattice": (_union(registry.configs("lattice")), Field(description="[lattice] section")),
        "fluid": (_union(registry.configs("fluid")), Field(description="[fluid] section")),
        "solid": (_union(registry.configs("solid")), Field(description="[solid] section")),
        "classifier": (
            _union(registry.configs("classifier")),
            Field(description="[classifier] section: labels the pattern at the end"),
        ),
        "observers": (
            list[_union(registry.configs("observer"))],  # type: ignore[misc]
            Field(default_factory=list, description="[[observers]] tables"),
        ),
    }
    model = create_model("SceneConfig", __base__=SceneBase, **fields)
    model.default_kinds = registry.defaults()
    return model
