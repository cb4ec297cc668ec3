"""Generate the configuration reference (docs/configuration.md) from the registered schemas."""

from __future__ import annotations

import inspect
from typing import Any, Literal, get_args, get_origin

from pydantic import BaseModel
from pydantic_core import PydanticUndefined

from porenet.config.base import LARGEST, SMALLEST
from porenet.config.scene import InjectionConfig, SceneBase, StopConfig
from porenet.core.registry import Registry

HEADER = f"""# Configuration reference

Generated from the registered config classes by
`python examples/scripts/make_config_reference.py` (a test checks it is current). Units are SI.
Each model section picks its class by `kind`; omitting `kind` selects the default shown. Unknown
fields are errors. Kinds provided by plugins appear here only when the plugin is installed.
Every number must be finite (`nan` and `inf` are refused, naming the field); a float is 0 or
between {SMALLEST:g} and {LARGEST:g} in magnitude, an integer fits in 64 bits. In a field that
takes `None` but defaults to a number, `inf` stands for `None` (TOML has no null)
(docs/reliability.md, "Numbers in a scene").
"""


def _type_name(annotation: Any) -> str:
    if get_origin(annotation) is Literal:
        return " or ".join(repr(a) for a in get_args(annotation))
    text = str(annotation) if get_args(annotation) else getattr(annotation, "__name__", "")
    text = text.replace("typing.", "").replace("pathlib.", "").replace("NoneType", "None")
    return text.replace("|", "or")


def _default(field: Any) -> str:
    if field.default is PydanticUndefined and field.default_factory is None:
        return "**required**"
    if field.default_factory is not None:
        return "(table)"
    return f"`{field.default!r}`"


def _table(model: type[BaseModel], skip: tuple[str, ...] = ()) -> list[str]:
    lines = ["| field | type | default | meaning |", "|---|---|---|---|"]
    for name, field in model.model_fields.items():
        if name in skip:
            continue
        desc = (field.description or "").replace("|", "\\|")
        lines.append(
            f"| `{name}` | `{_type_name(field.annotation)}` | {_default(field)} | {desc} |"
        )
    return lines


def config_reference(registry: Registry) -> str:
    """Markdown for every scene field and every registered kind."""
    out = [HEADER, "## Top level", ""]
    out += _table(SceneBase, skip=("injection", "stop"))
    out += ["", "## `[injection]`", "", inspect.cleandoc(InjectionConfig.__doc__ or ""), ""]
    out += _table(InjectionConfig)
    out += ["", "## `[stop]`", "", inspect.cleandoc(StopConfig.__doc__ or ""), ""]
    out += _table(StopConfig)
    sections = {
        "lattice": "[lattice]",
        "fluid": "[fluid]",
        "solid": "[solid]",
        "classifier": "[classifier]",
        "observer": "[[observers]]",
    }
    for family, title in sections.items():
        for entry in sorted(registry, key=lambda e: e.kind):
            if entry.family != family:
                continue
            doc = (entry.config.__doc__ or "").strip().splitlines()[0]
            out += ["", f'## `{title}` kind = `"{entry.kind}"` ({entry.package})', "", doc, ""]
            out += _table(entry.config, skip=("kind",))
    return "\n".join(out) + "\n"
