"""Base class of every model config (docs/architecture.md, rule 4)."""

from __future__ import annotations

from typing import Any, ClassVar, get_args, get_origin

from pydantic import BaseModel, ConfigDict


class ModelConfig(BaseModel):
    """Config of one model, selected in a scene by its ``kind``.

    Subclasses declare ``kind: Literal["their-kind"]`` and their parameters in SI units, with the
    unit in each field's description. Configs are frozen and forbid unknown fields, so a typo is
    an error, never a silently ignored parameter.

    Class attributes
    ----------------
    builds_nothing : bool
        True for kinds that the Plan satisfies by building no object at all (e.g. the rigid
        solid: no mechanics is ever simulated).
    """

    model_config = ConfigDict(extra="forbid", frozen=True)

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
