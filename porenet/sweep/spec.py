"""Sweep files: the pydantic models, loading, and expansion into a list of validated runs.

A sweep file (TOML, docs/sweeps.md) names a base scene, axes over dotted scene keys (or derived
keys such as ``ca_star``), a number of replicates and a root seed. :func:`load_sweep` validates
it; :func:`expand` turns it into :class:`RunSpec` objects whose scenes have all been validated
before anything runs.

Seeds (decision): replicate ``r`` gets the seed
``int(np.random.SeedSequence([root_seed, r]).generate_state(1)[0])`` at *every* point (common
random numbers): two points differ by their parameters, not by their media, so differences
between neighbouring points of a phase diagram are not blurred by sample-to-sample noise.
"""

from __future__ import annotations

import copy
import difflib
import itertools
import math
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Literal

import numpy as np
from pydantic import BaseModel, ConfigDict, Field, ValidationError, field_validator, model_validator

from porenet.config.loading import format_validation_error, get_dotted, read_toml, set_dotted
from porenet.core.errors import ConfigError
from porenet.sweep.layout import RUNS_DIR


class RangeSpec(BaseModel):
    """``range = { start, stop, num, scale }``: ``num`` values from ``start`` to ``stop``."""

    model_config = ConfigDict(extra="forbid", frozen=True)
    start: float = Field(description="First value (included).")
    stop: float = Field(description="Last value (included).")
    num: int = Field(ge=1, description="Number of values.")
    scale: Literal["linear", "log"] = Field(
        "linear", description="'linear': evenly spaced; 'log': evenly spaced in log10."
    )

    @model_validator(mode="after")
    def _positive_for_log(self) -> RangeSpec:
        if self.scale == "log" and (self.start <= 0 or self.stop <= 0):
            raise ValueError(
                f"a log range needs start > 0 and stop > 0 (got {self.start:g}, {self.stop:g})"
            )
        if not (math.isfinite(self.start) and math.isfinite(self.stop)):
            raise ValueError("start and stop must be finite")
        return self

    def values(self) -> list[float]:
        """The range's values as Python floats (endpoints exact)."""
        if self.scale == "log":
            return [float(v) for v in np.geomspace(self.start, self.stop, self.num)]
        return [float(v) for v in np.linspace(self.start, self.stop, self.num)]


class AxisSpec(BaseModel):
    """One ``[[axes]]`` table: a dotted scene key (or a derived key) and its values."""

    model_config = ConfigDict(extra="forbid", frozen=True)
    key: str = Field(
        description="Dotted scene key, as for `porenet run --set` (e.g. 'lattice.disorder'), "
        "or a derived key (see DERIVED)."
    )
    values: list[Any] | None = Field(None, description="The values, in order.")
    range: RangeSpec | None = Field(None, description="Evenly spaced values instead of a list.")

    @field_validator("key")
    @classmethod
    def _dotted(cls, key: str) -> str:
        key = key.strip()
        if not key or any(not part.strip() for part in key.split(".")):
            raise ValueError("expected a dotted scene key such as 'lattice.disorder'")
        if key == "seed":
            raise ValueError("seeds are not an axis: they come from 'replicates' and 'root_seed'")
        return key

    @model_validator(mode="after")
    def _one_source(self) -> AxisSpec:
        if (self.values is None) == (self.range is None):
            raise ValueError("give exactly one of 'values' and 'range'")
        if self.values is not None and not self.values:
            raise ValueError("'values' is empty")
        return self

    def points(self) -> list[Any]:
        """The axis's values."""
        return list(self.values) if self.values is not None else self.range.values()  # type: ignore[union-attr]


class SweepSpec(BaseModel):
    """A sweep file (docs/sweeps.md)."""

    model_config = ConfigDict(extra="forbid", frozen=True)
    name: str = Field("", description="Free text.")
    base: str | dict[str, Any] = Field(
        description="The base scene: a scene file (relative to the sweep file) or an inline "
        "[base] table."
    )
    replicates: int = Field(1, ge=1, description="Seeds per point.")
    root_seed: int = Field(0, ge=0, description="Root of the replicates' seeds.")
    mode: Literal["grid", "zip"] = Field(
        "grid", description="'grid': cartesian product of the axes; 'zip': taken together."
    )
    axes: list[AxisSpec] = Field(default_factory=list, description="[[axes]] tables.")

    @field_validator("base", mode="before")
    @classmethod
    def _base_kind(cls, value: Any) -> Any:
        if not isinstance(value, str | dict):
            raise ValueError("must be a scene file (a string) or a [base] table")
        return value

    @model_validator(mode="after")
    def _consistent(self) -> SweepSpec:
        keys = [a.key for a in self.axes]
        for key in keys:
            if keys.count(key) > 1:
                raise ValueError(f"key {key!r} is swept by more than one axis")
        for i, axis in enumerate(self.axes):
            derived = DERIVED.get(axis.key)
            for target in derived.sets if derived else ():
                if target in keys:
                    raise ValueError(
                        f"axes[{i}] {axis.key!r} sets {target!r}, which axes[{keys.index(target)}] "
                        "also sweeps"
                    )
        if self.mode == "zip" and self.axes:
            lengths = [len(a.points()) for a in self.axes]
            if len(set(lengths)) > 1:
                shown = ", ".join(f"{a.key}: {n}" for a, n in zip(self.axes, lengths, strict=True))
                raise ValueError(f"mode 'zip' needs axes of equal length (got {shown})")
        return self


# --------------------------------------------------------------------------- derived keys


@dataclass(frozen=True)
class DerivedKey:
    """A sweep key that is not a scene field: ``apply(scene_dict, value)`` returns the scene
    dict with the fields listed in ``sets`` filled in. ``scene_dict`` is the point's scene after
    the ordinary axes were applied, each section with its defaults filled in where it
    validates on its own (:func:`resolved_view`); the result is validated afterwards."""

    apply: Callable[[dict[str, Any], Any], dict[str, Any]]
    sets: tuple[str, ...]
    description: str

    def __call__(self, scene: dict[str, Any], value: Any) -> dict[str, Any]:
        return self.apply(scene, value)


def _ca_star(scene: dict[str, Any], value: Any) -> dict[str, Any]:
    from porenet.analysis.numbers import capillary_number_at

    if isinstance(value, bool) or not isinstance(value, int | float) or not value > 0:
        raise ConfigError(f"ca_star = {value!r}: must be a number > 0")
    lattice = scene.get("lattice", {})
    n, disorder = lattice.get("n"), lattice.get("disorder")
    if not isinstance(n, int) or not isinstance(disorder, int | float) or not disorder > 0:
        raise ConfigError(
            f"ca_star needs a lattice with 'n' and 'disorder' > 0 (got n = {n!r}, "
            f"disorder = {disorder!r})"
        )
    fluid = dict(scene.get("fluid", {}))
    fluid["capillary_number"] = capillary_number_at(float(value), n, float(disorder))
    return {**scene, "fluid": fluid}


#: Derived sweep keys, by name. Add an entry to support a new one.
DERIVED: dict[str, DerivedKey] = {
    "ca_star": DerivedKey(
        _ca_star,
        ("fluid.capillary_number",),
        "modified capillary number Ca* = Ca (L/a) / [λ/(1-λ²)]; sets fluid.capillary_number "
        "from the point's lattice.n and lattice.disorder",
    ),
}


# --------------------------------------------------------------------------- loading


def format_sweep_error(exc: ValidationError, source: str, data: Any) -> ConfigError:
    """One line per problem: ``source: dotted.field = value: what is wrong``."""
    lines = []
    for err in exc.errors(include_url=False):
        parts: list[str] = []
        node: Any = data
        for item in err["loc"]:
            if isinstance(item, int) and parts:
                parts[-1] = f"{parts[-1]}[{item}]"
            else:
                parts.append(str(item))
            if isinstance(node, dict):
                node = node.get(item)
            elif isinstance(node, list) and isinstance(item, int) and item < len(node):
                node = node[item]
            else:
                node = None
        if parts and parts[-1] in ("str", "dict[str,any]"):
            parts.pop()  # the member of the `base` union
        dotted = ".".join(parts) or "(sweep)"
        msg = err["msg"].removeprefix("Value error, ")
        if err["type"] == "extra_forbidden":
            allowed = _allowed(parts)
            close = difflib.get_close_matches(parts[-1].split("[")[0], allowed, n=1)
            hint = f"; did you mean {close[0]!r}?" if close else ""
            lines.append(f"{source}: {dotted}: unknown field{hint} (allowed: {', '.join(allowed)})")
        elif err["type"] == "missing":
            lines.append(f"{source}: {dotted}: required field is missing")
        else:
            shown = f" = {node!r}" if node is not None and not isinstance(node, dict) else ""
            lines.append(f"{source}: {dotted}{shown}: {msg}")
    unique = list(dict.fromkeys(lines))
    return ConfigError("invalid sweep\n  " + "\n  ".join(unique))


def _allowed(parts: list[str]) -> list[str]:
    model: type[BaseModel] = SweepSpec
    if len(parts) >= 2 and parts[0].startswith("axes"):
        model = AxisSpec
        if len(parts) >= 3 and parts[1] == "range":
            model = RangeSpec
    return list(model.model_fields)


@dataclass
class Sweep:
    """A validated sweep file with its base scene."""

    spec: SweepSpec
    source: Path  # the sweep file (or "<sweep>" for a dict)
    base_scene: dict[str, Any]
    base_dir: Path  # where relative paths of the base scene are read from
    base_source: str  # the base scene's file, or "<sweep file> [base]"


def load_sweep(sweep: str | Path | dict[str, Any], *, base_dir: Path | None = None) -> Sweep:
    """Read and validate a sweep file (or a dict with the same structure).

    Raises
    ------
    ConfigError
        Naming the file, the dotted field and the bad value.
    """
    if isinstance(sweep, dict):
        data, source, where = sweep, Path("<sweep>"), base_dir or Path.cwd()
    else:
        source = Path(sweep)
        data = read_toml(source)
        where = source.resolve().parent
    try:
        spec = SweepSpec.model_validate(data)
    except ValidationError as exc:
        raise format_sweep_error(exc, str(source), data) from None
    if isinstance(spec.base, str):
        base_path = Path(spec.base).expanduser()
        if not base_path.is_absolute():
            base_path = where / base_path
        if not base_path.is_file():
            raise ConfigError(f"{source}: base = {spec.base!r}: no such scene file ({base_path})")
        base_scene = read_toml(base_path)
        return Sweep(spec, source, base_scene, base_path.resolve().parent, str(base_path))
    return Sweep(spec, source, copy.deepcopy(spec.base), where, f"{source} [base]")


# --------------------------------------------------------------------------- expansion


@dataclass
class RunSpec:
    """One run of a sweep: a point (its swept values) and a replicate (its seed)."""

    run_id: str
    point: int
    replicate: int
    seed: int
    params: dict[str, Any]  # swept key (and keys set by derived keys) -> value, in axis order
    scene: dict[str, Any] = field(repr=False)  # validated scene, model_dump(mode="json")

    @property
    def run_file(self) -> str:
        """The run file, relative to the sweep's output directory."""
        return f"{RUNS_DIR}/{self.run_id}.h5"


def replicate_seed(root_seed: int, replicate: int) -> int:
    """The seed of replicate ``replicate`` (the same at every point)."""
    return int(np.random.SeedSequence([root_seed, replicate]).generate_state(1)[0])


def run_id(point: int, replicate: int) -> str:
    """``p{point:04d}-r{replicate:02d}``."""
    return f"p{point:04d}-r{replicate:02d}"


def columns(spec: SweepSpec) -> list[str]:
    """The swept columns of the summary, in axis order (derived keys followed by the keys
    they set)."""
    cols: list[str] = []
    for axis in spec.axes:
        cols.append(axis.key)
        derived = DERIVED.get(axis.key)
        cols.extend(derived.sets if derived else ())
    return cols


def points(spec: SweepSpec) -> list[dict[str, Any]]:
    """The sweep's points as ``{axis key: value}`` dicts, in order (grid: the last axis
    varies fastest)."""
    if not spec.axes:
        return [{}]
    values = [a.points() for a in spec.axes]
    combos = itertools.product(*values) if spec.mode == "grid" else zip(*values, strict=True)
    keys = [a.key for a in spec.axes]
    return [dict(zip(keys, combo, strict=True)) for combo in combos]


def resolved_view(
    data: dict[str, Any], registry: Any, context: dict[str, Any] | None = None
) -> dict[str, Any]:
    """``data`` with each model section (lattice, fluid, solid, classifier) replaced by its
    validated dump (every default filled in) where that section validates on its own; other
    sections are left as given. What a derived key reads its inputs from: a section may be
    incomplete until the derived key fills it (a viscous fluid without its Ca)."""
    from pydantic import ValidationError

    view = copy.deepcopy(data)
    for family, default in registry.defaults().items():
        section = view.get(family)
        if section is None and family != "lattice" and family != "fluid":
            section = {}
        if not isinstance(section, dict):
            continue
        kind = section.get("kind", default)
        if (family, kind) not in registry:
            continue
        config = registry.get(family, kind).config
        try:
            view[family] = config.model_validate(
                {"kind": kind, **section}, context=context
            ).model_dump(mode="json")
        except (ValidationError, ValueError):
            continue
    return view


def _describe(params: dict[str, Any]) -> str:
    return ", ".join(f"{k} = {v!r}" for k, v in params.items()) or "(no axes)"


def expand(sweep: Sweep) -> list[RunSpec]:
    """Every run of the sweep, each scene validated (``load_scene``'s schema and messages).

    Raises
    ------
    ConfigError
        For the first invalid point, naming the sweep file, the point's parameters and the
        scene's message. Nothing has run.
    """
    from porenet.config.scene import scene_model
    from porenet.hooks import get_registry

    registry = get_registry()
    model = scene_model(registry)
    spec = sweep.spec
    context = {"base_dir": sweep.base_dir}

    def validate(data: dict[str, Any], where: str) -> dict[str, Any]:
        try:
            scene = model.model_validate(data, context=context)
        except ValidationError as exc:
            raise format_validation_error(exc, where, data, model, registry) from None
        return scene.model_dump(mode="json")

    runs: list[RunSpec] = []
    for p, point in enumerate(points(spec)):
        try:
            data = copy.deepcopy(sweep.base_scene)
            for key, value in point.items():
                if key not in DERIVED:
                    set_dotted(data, key, copy.deepcopy(value))
            data.pop("seed", None)
            for key, value in point.items():
                if key in DERIVED:
                    data = DERIVED[key](resolved_view(data, registry, context), value)
            scene = validate(data, sweep.base_source)
        except ConfigError as exc:
            raise ConfigError(
                f"{sweep.source}: point {p} ({_describe(point)}) is not a valid scene: {exc}"
            ) from None
        params: dict[str, Any] = {}
        for key, value in point.items():
            params[key] = value if key in DERIVED else get_dotted(scene, key)
            for target in DERIVED[key].sets if key in DERIVED else ():
                params[target] = get_dotted(scene, target)
        for r in range(spec.replicates):
            seed = replicate_seed(spec.root_seed, r)
            # validated twice so that the stored scene is exactly what a worker's run records
            final = validate({**scene, "seed": seed}, sweep.base_source)
            runs.append(RunSpec(run_id(p, r), p, r, seed, params, final))
    return runs
