"""Base classes of every scene section and model config (docs/architecture.md, rule 4).

Numbers are checked the same way in every section (docs/reliability.md, "Numbers in a
scene"): a float must be finite (``nan`` and ``inf`` are refused, naming the field), and 0 or
between :data:`SMALLEST` and :data:`LARGEST` in magnitude; an integer must fit in 64 bits. In a
field that accepts ``None`` but defaults to something else, ``inf`` is read as ``None`` (TOML
has no null), e.g. ``pressure_step = inf`` of the viscous model.
"""

from __future__ import annotations

import difflib
import functools
import math
import types
from typing import Annotated, Any, ClassVar, Union, get_args, get_origin

from pydantic import (
    AfterValidator,
    BaseModel,
    ConfigDict,
    ValidationInfo,
    field_validator,
    model_validator,
)
from pydantic_core import PydanticUndefined

#: Largest magnitude of a float in a scene: far above any SI value of the problem (moduli
#: ~1e10 Pa, capillary numbers up to ~1e6), low enough that products of a few inputs stay
#: finite in double precision.
LARGEST = 1e30
#: Smallest non-zero magnitude of a float in a scene (below it, products underflow to 0).
SMALLEST = 1e-30
#: Integers must fit in a signed 64-bit integer (the kernels' and HDF5's integers).
INT_MAX = 2**63 - 1


def _check_number(value: Any) -> None:
    if isinstance(value, bool):
        return
    if isinstance(value, int):
        if abs(value) > INT_MAX:
            raise ValueError(f"must be at most {INT_MAX} in magnitude (a 64-bit integer)")
    elif isinstance(value, float):
        if math.isfinite(value) and value != 0 and not SMALLEST <= abs(value) <= LARGEST:
            raise ValueError(
                f"must be 0 or between {SMALLEST:g} and {LARGEST:g} in magnitude (SI units; "
                "beyond that products of the inputs overflow or vanish)"
            )
    elif isinstance(value, list | tuple):
        for item in value:
            _check_number(item)


@functools.cache
def _none_when_infinite(cls: type[BaseModel]) -> frozenset[str]:
    """Fields of ``cls`` that accept None but default to something else: there ``inf``
    stands for None."""
    names = set()
    for name, info in cls.model_fields.items():
        annotation = info.annotation
        optional = get_origin(annotation) in (Union, types.UnionType) and type(None) in get_args(
            annotation
        )
        if optional and info.default is not None and info.default is not PydanticUndefined:
            names.add(name)
    return frozenset(names)


class CheckedModel(BaseModel):
    """A frozen pydantic model that forbids unknown fields and checks every number (module
    docstring)."""

    model_config = ConfigDict(extra="forbid", frozen=True, allow_inf_nan=False)

    @model_validator(mode="before")
    @classmethod
    def _infinite_means_none(cls, data: Any) -> Any:
        if isinstance(data, dict):
            unlimited = _none_when_infinite(cls)
            replace = {
                k: None
                for k, v in data.items()
                if k in unlimited and isinstance(v, float) and v == math.inf
            }
            if replace:
                data = {**data, **replace}
        return data

    @field_validator("*", mode="after")
    @classmethod
    def _numbers_in_range(cls, value: Any) -> Any:
        _check_number(value)
        return value


class ModelConfig(CheckedModel):
    """Config of one model, selected in a scene by its ``kind``.

    Subclasses declare ``kind: Literal["their-kind"]`` and their parameters in SI units, with the
    unit in each field's description. Configs are frozen and forbid unknown fields, so a typo is
    an error, never a silently ignored parameter; their numbers are checked as the module
    docstring says.

    Class attributes
    ----------------
    builds_nothing : bool
        True for kinds that the Plan satisfies by building no object at all (e.g. the rigid
        solid: no mechanics is ever simulated).
    """

    kind: str
    builds_nothing: ClassVar[bool] = False

    @classmethod
    def kind_name(cls) -> str:
        """The single literal value of this config's ``kind`` field."""
        annotation: Any = cls.model_fields["kind"].annotation
        args = get_args(annotation)
        if get_origin(annotation) is None or len(args) != 1 or not isinstance(args[0], str):
            raise TypeError(f"{cls.__name__}.kind must be annotated Literal['one-kind']")
        return args[0]


def registered_coupler(value: str, info: ValidationInfo) -> str:
    """``value`` if it names a coupler kind of the registry the scene is validated with
    (:func:`porenet.config.loading.load_scene` passes the registered couplers in the
    validation context); any name when validated without one (the Simulation then looks it
    up)."""
    known = (info.context or {}).get("couplers")
    if known is not None and value not in known:
        close = difflib.get_close_matches(value, list(known), n=1)
        hint = f" (did you mean {close[0]!r}?)" if close else ""
        raise ValueError(
            f"unknown coupler kind {value!r}{hint}; registered: {', '.join(sorted(known))}"
        )
    return value


#: The type of a solid config's ``coupler`` field: the kind of a registered coupler, built-in
#: or from a plugin (docs/architecture.md, "What a kind answers").
CouplerKind = Annotated[str, AfterValidator(registered_coupler)]
