"""Reading scenes from TOML, dicts or objects, with overrides and readable errors."""

from __future__ import annotations

import copy
import difflib
import tomllib
from pathlib import Path
from typing import Any

from pydantic import BaseModel, ValidationError

from porenet.config.scene import SceneBase, scene_model
from porenet.core.errors import ConfigError
from porenet.core.registry import Registry

EXAMPLES_DIR = Path(__file__).resolve().parent.parent / "examples"


def example_path(name: str) -> Path:
    """Path of a scene shipped inside the package (``porenet run --example NAME``)."""
    path = EXAMPLES_DIR / f"{name}.toml"
    if not path.is_file():
        known = sorted(p.stem for p in EXAMPLES_DIR.glob("*.toml"))
        raise ConfigError(f"unknown example {name!r}; available: {', '.join(known)}")
    return path


def read_toml(path: str | Path) -> dict[str, Any]:
    """Parse a TOML file; a missing or malformed file is a ConfigError naming it."""
    path = Path(path)
    try:
        with path.open("rb") as fh:
            return tomllib.load(fh)
    except FileNotFoundError:
        raise ConfigError(f"{path}: no such file") from None
    except IsADirectoryError:
        raise ConfigError(f"{path}: is a directory, not a scene file") from None
    except PermissionError:
        raise ConfigError(
            f"{path}: permission denied; make the scene file readable (chmod u+r)"
        ) from None
    except OSError as exc:
        raise ConfigError(f"{path}: cannot read the scene file: {exc.strerror or exc}") from None
    except tomllib.TOMLDecodeError as exc:
        raise ConfigError(f"{path}: not valid TOML: {exc}; fix the scene file") from None
    except UnicodeDecodeError as exc:
        raise ConfigError(f"{path}: not a text file: {exc}") from None


#: The value of an override that removes its key (``--set KEY=``).
UNSET = object()


def parse_override(item: str) -> tuple[list[str], Any]:
    """Split ``"lattice.n=64"`` into ``(["lattice", "n"], 64)``; values are TOML literals.

    A value that is not a TOML literal (``--set name=run1``) is taken as a string. An empty
    value (``--set fluid.capillary_number=``) removes the key, so the field takes its default
    (TOML has no null).
    """
    key, sep, raw = item.partition("=")
    key = key.strip()
    if not sep or not key or any(not part for part in key.split(".")):
        raise ConfigError(
            f"--set {item!r}: expected KEY=VALUE with a dotted KEY, e.g. lattice.n=64"
        )
    if not raw.strip():
        return key.split("."), UNSET
    try:
        value = tomllib.loads(f"v = {raw.strip()}")["v"]
    except tomllib.TOMLDecodeError:
        value = raw.strip()
    return key.split("."), value


def get_dotted(data: dict[str, Any], key: str) -> Any:
    """The value at dotted ``key`` (``"lattice.n"``) of nested dicts, or None if absent."""
    node: Any = data
    for part in key.split("."):
        if not isinstance(node, dict) or part not in node:
            return None
        node = node[part]
    return node


def set_dotted(data: dict[str, Any], key: str, value: Any, label: str | None = None) -> None:
    """Set dotted ``key`` of nested dicts in place, making missing tables; ``UNSET`` removes
    the key. A part that is not a table is a ConfigError naming ``label`` (default: the key)."""
    node = data
    parts = key.split(".")
    for part in parts[:-1]:
        child = node.setdefault(part, {})
        if not isinstance(child, dict):
            raise ConfigError(f"{label or key}: {part!r} is not a table")
        node = child
    if value is UNSET:
        node.pop(parts[-1], None)
    else:
        node[parts[-1]] = value


def apply_overrides(data: dict[str, Any], overrides: list[str] | tuple[str, ...]) -> dict[str, Any]:
    """Return a copy of ``data`` with dotted ``KEY=VALUE`` overrides applied."""
    data = copy.deepcopy(data)
    for item in overrides:
        path, value = parse_override(item)
        set_dotted(data, ".".join(path), value, label=f"--set {item!r}")
    return data


def _walk_loc(data: Any, loc: tuple[Any, ...], defaults: dict[str, str]) -> tuple[list[str], Any]:
    """Dotted path and offending value for a pydantic error location.

    Discriminated unions insert the tag (the section's kind, or its family's default kind in
    ``defaults``) into ``loc``; it is dropped here.
    """
    parts: list[str] = []
    node = data
    missing = object()
    for item in loc:
        if isinstance(node, dict) and item not in node:
            section_default = defaults.get(parts[-1]) if len(parts) == 1 else None
            if item in (node.get("kind"), section_default):
                continue  # the union tag (given, or the section's default kind)
        if isinstance(item, int):
            parts[-1:] = [f"{parts[-1]}[{item}]"] if parts else [f"[{item}]"]
        else:
            parts.append(str(item))
        if isinstance(node, dict):
            node = node.get(item, missing)
        elif isinstance(node, list) and isinstance(item, int) and item < len(node):
            node = node[item]
        else:
            node = missing
    return parts, (None if node is missing else node)


def _allowed_fields(
    model: type[BaseModel], data: Any, parts: list[str], registry: Registry
) -> list[str]:
    """Field names allowed in the table that holds the unknown field ``parts[-1]``."""
    if len(parts) == 1:
        return list(model.model_fields)
    section = parts[0].split("[")[0]
    family = {"observers": "observer"}.get(section, section)
    table = data.get(section) if isinstance(data, dict) else None
    if isinstance(table, list):
        index = int(parts[0].split("[")[1].rstrip("]")) if "[" in parts[0] else 0
        table = table[index] if index < len(table) else None
    if family in ("injection", "stop"):
        return list(SceneBase.model_fields[family].annotation.model_fields)  # type: ignore[union-attr]
    kind = table.get("kind", registry.default(family)) if isinstance(table, dict) else None
    if (family, kind) in registry:
        return list(registry.get(family, kind).config.model_fields)
    return []


def format_validation_error(
    exc: ValidationError, source: str, data: Any, model: type[BaseModel], registry: Registry
) -> ConfigError:
    """One line per problem: ``source: field = value: what is wrong``."""
    lines = []
    for err in exc.errors(include_url=False):
        parts, value = _walk_loc(data, tuple(err["loc"]), registry.defaults())
        if err["type"] == "union_tag_invalid" and (not parts or parts[-1] != "kind"):
            # pydantic >= 2.12 reports a bad discriminator at the table, not at its `kind`
            parts, value = [*parts, "kind"], err.get("ctx", {}).get("tag", value)
        dotted = ".".join(parts) or "(scene)"
        msg = err["msg"]
        if err["type"] == "extra_forbidden":
            allowed = _allowed_fields(model, data, parts, registry)
            close = difflib.get_close_matches(parts[-1], allowed, n=1)
            hint = f"; did you mean {close[0]!r}?" if close else ""
            listed = f" (allowed: {', '.join(sorted(allowed))})" if allowed else ""
            lines.append(f"{source}: {dotted}: unknown field{hint}{listed}")
            continue
        if parts and parts[-1] == "kind" and err["type"] in ("literal_error", "union_tag_invalid"):
            family = {"observers": "observer"}.get(parts[0].split("[")[0], parts[0])
            try:
                registry.get(family, str(value))
            except ConfigError as unknown:
                lines.append(f"{source}: {dotted} = {value!r}: {unknown}")
                continue
        if err["type"] == "missing":
            lines.append(f"{source}: {dotted}: required field is missing")
            continue
        if msg.startswith("Value error, "):
            msg = msg[len("Value error, ") :]
        if err["type"] == "finite_number":
            msg = "must be a finite number (nan and inf are not allowed here)"
        shown = f" = {value!r}" if value is not None and not isinstance(value, dict) else ""
        lines.append(f"{source}: {dotted}{shown}: {msg}")
    return ConfigError("invalid scene\n  " + "\n  ".join(lines))


def load_scene(
    scene: Any,
    overrides: list[str] | tuple[str, ...] = (),
    *,
    registry: Registry | None = None,
) -> SceneBase:
    """Validate a scene given as a TOML path, a dict, or an existing ``SceneConfig``.

    Relative paths inside a scene file (``apertures_file``) are resolved against the file's
    directory; inside a dict, against the current directory.

    Raises
    ------
    ConfigError
        Naming the file, the dotted field and the bad value.
    """
    from porenet.hooks import get_registry

    registry = registry or get_registry()
    model = scene_model(registry)
    base_dir = Path.cwd()
    if isinstance(scene, SceneBase):
        if not overrides:
            return scene
        data, source = scene.model_dump(mode="json"), "<scene>"
    elif isinstance(scene, dict):
        data, source = scene, "<scene>"
    elif isinstance(scene, str | Path):
        data, source = read_toml(scene), str(scene)
        base_dir = Path(scene).resolve().parent
    else:
        raise ConfigError(f"a scene is a TOML path, a dict or a SceneConfig, not {type(scene)!r}")
    data = apply_overrides(data, overrides)
    try:
        context = {"base_dir": base_dir, "couplers": tuple(registry.kinds("coupler"))}
        validated = model.model_validate(data, context=context)
    except ValidationError as exc:
        raise format_validation_error(exc, source, data, model, registry) from None
    _check_site(validated, source)
    return validated


def _check_site(scene: SceneBase, source: str) -> None:
    """Refuse an injection site the lattice's config knows it lacks (``site_names``: its
    sites, or None when only the built lattice knows them, as an imported network's labels;
    then the run checks it)."""
    names = getattr(scene.lattice, "site_names", None)
    at = scene.injection.at
    known = names() if callable(names) else None
    if known is None or not isinstance(at, str) or at in known:
        return
    raise ConfigError(
        f"invalid scene\n  {source}: injection.at = {at!r}: not a site of the "
        f"{scene.lattice.kind!r} lattice; expected one of {', '.join(known)}, or a list of pore "
        'indices (docs/lattices.md, "Injection sites and outlets")'
    )
