"""The registry owns the names of every kind (docs/architecture.md, rule 3).

Kinds are grouped in families (``lattice``, ``fluid``, ``solid``, ``coupler``, ``observer``,
``classifier``). Each entry ties a ``kind`` to its config class and to the implementation, which
may be a class or a ``"module:Class"`` string imported only when a scene selects the kind.
"""

from __future__ import annotations

import difflib
import importlib
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from typing import Any

from porenet.core.errors import ConfigError, PluginError

FAMILIES: tuple[str, ...] = ("lattice", "fluid", "solid", "coupler", "observer", "classifier")
BUILTIN_PACKAGE = "porenet"


@dataclass(frozen=True)
class Entry:
    """One registered kind.

    Attributes
    ----------
    family, kind : str
        Where the name lives and the name itself.
    config : type
        The pydantic config class (a :class:`~porenet.config.base.ModelConfig` subclass).
    implementation : type, str or None
        The class, a lazy ``"module:Class"`` path, or None for kinds that build nothing.
    package : str
        Distribution that provides it (``porenet`` for built-ins).
    plugin : str
        Name of the plugin (entry point) that registered it.
    default : bool
        The family's default kind: the kind of a scene section that names none.
    cost : callable, str or None
        The kind's cost estimate (:mod:`porenet.core.cost`), or a lazy ``"module:function"``;
        None: the kind provides none.
    warm_ups : tuple, str or None
        The kind's compile warm-ups (:class:`porenet.core.kinds.WarmUp`), or a lazy
        ``"module:NAME"``; None: none.
    """

    family: str
    kind: str
    config: type
    implementation: type | str | None
    package: str
    plugin: str
    default: bool = False
    cost: Callable[..., Any] | str | None = None
    warm_ups: tuple[Any, ...] | str | None = None

    def load(self) -> type | None:
        """Return the implementation class, importing it if it was given as a string."""
        return self._resolve(self.implementation, "implementation")  # type: ignore[no-any-return]

    def load_cost(self) -> Callable[..., Any] | None:
        """The kind's cost estimate function, imported if given as a string (None: none)."""
        return self._resolve(self.cost, "cost estimate")  # type: ignore[no-any-return]

    def load_warm_ups(self) -> tuple[Any, ...]:
        """The kind's compile warm-ups, imported if given as a string (empty: none)."""
        return tuple(self._resolve(self.warm_ups, "warm-ups") or ())

    def _resolve(self, value: Any, what: str) -> Any:
        if not isinstance(value, str):
            return value
        module_name, _, attr = value.partition(":")
        try:
            return getattr(importlib.import_module(module_name), attr)
        except (ImportError, AttributeError) as exc:
            raise PluginError(
                f"{self.family} kind {self.kind!r} from package {self.package!r}: cannot import "
                f"{what} {value!r}: {exc}"
            ) from exc


class Registry:
    """All registered kinds, by family."""

    def __init__(self) -> None:
        self._entries: dict[str, dict[str, Entry]] = {f: {} for f in FAMILIES}
        #: (plugin name, message) of plugins that failed to load (non-strict mode).
        self.failures: list[tuple[str, str]] = []

    def add(
        self,
        family: str,
        config: type,
        implementation: type | str | None,
        *,
        package: str = BUILTIN_PACKAGE,
        plugin: str = BUILTIN_PACKAGE,
        default: bool = False,
        cost: Callable[..., Any] | str | None = None,
        warm_ups: tuple[Any, ...] | str | None = None,
        replace: bool = False,
    ) -> Entry:
        """Register ``config``/``implementation`` under the config's ``kind``, with the
        kind's optional ``cost`` estimate and compile ``warm_ups`` (each an object or a lazy
        ``"module:name"``); ``default`` makes it the family's default kind (only porenet's own
        kinds may be: what a scene means must not depend on the plugins installed);
        ``replace`` lets a kind the same ``plugin`` registered before be registered again
        (:func:`porenet.hooks.register`, a notebook cell run twice).

        Raises
        ------
        PluginError
            Unknown family, a config that is not a ModelConfig with a single-literal ``kind``, a
            third-party kind without a namespace (``"pkg.name"``), a duplicate kind (the
            message names both packages), a third-party default or a second default.
        """
        from porenet.config.base import ModelConfig

        if family not in self._entries:
            raise PluginError(f"plugin {plugin!r}: unknown family {family!r}; one of {FAMILIES}")
        if not (isinstance(config, type) and issubclass(config, ModelConfig)):
            raise PluginError(
                f"plugin {plugin!r}: {family} config {config!r} must subclass "
                "porenet.config.base.ModelConfig"
            )
        try:
            kind = config.kind_name()
        except TypeError as exc:
            raise PluginError(f"plugin {plugin!r}: {exc}") from exc
        existing = self._entries[family].get(kind)
        if existing is not None and not (replace and existing.plugin == plugin):
            raise PluginError(
                f"{family} kind {kind!r} is registered twice: by package {existing.package!r} "
                f"(plugin {existing.plugin!r}) and by package {package!r} (plugin {plugin!r})"
            )
        if package != BUILTIN_PACKAGE and "." not in kind:
            raise PluginError(
                f"plugin {plugin!r} (package {package!r}): third-party {family} kind {kind!r} "
                "must be namespaced, e.g. 'mypackage.mykind'"
            )
        if not (implementation is None or isinstance(implementation, type | str)):
            raise PluginError(f"plugin {plugin!r}: implementation of {kind!r} must be a class")
        for what, value in (("implementation", implementation), ("cost", cost),
                            ("warm_ups", warm_ups)):  # fmt: skip
            if isinstance(value, str) and ":" not in value:
                raise PluginError(f"plugin {plugin!r}: {what} {value!r} must read 'module:name'")
        if not (cost is None or isinstance(cost, str) or callable(cost)):
            raise PluginError(f"plugin {plugin!r}: cost of {kind!r} must be a function")
        if default:
            if package != BUILTIN_PACKAGE:
                raise PluginError(
                    f"plugin {plugin!r} (package {package!r}): only porenet's own kinds may be a "
                    f"family's default kind ({family} kind {kind!r}): a scene's meaning must not "
                    "depend on the plugins installed"
                )
            current = self.default(family)
            if current is not None:
                raise PluginError(
                    f"{family} kinds {current!r} and {kind!r} are both registered as the default"
                )
        entry = Entry(
            family, kind, config, implementation, package, plugin, default, cost, warm_ups
        )
        self._entries[family][kind] = entry
        return entry

    def get(self, family: str, kind: str) -> Entry:
        """The entry for ``kind``; a ConfigError listing the known kinds if there is none."""
        try:
            return self._entries[family][kind]
        except KeyError:
            known = sorted(self._entries.get(family, {}))
            close = difflib.get_close_matches(kind, known, n=1)
            hint = f" (did you mean {close[0]!r}?)" if close else ""
            raise ConfigError(
                f"unknown {family} kind {kind!r}{hint}; registered: {', '.join(known) or 'none'}"
            ) from None

    def default(self, family: str) -> str | None:
        """The family's default kind (the kind of a scene section that names none), or None."""
        for entry in self._entries.get(family, {}).values():
            if entry.default:
                return entry.kind
        return None

    def defaults(self) -> dict[str, str]:
        """``{family: default kind}`` for the families that have one."""
        return {f: kind for f in FAMILIES if (kind := self.default(f)) is not None}

    def kinds(self, family: str) -> list[str]:
        """Registered kinds of a family, sorted."""
        return sorted(self._entries[family])

    def configs(self, family: str) -> list[type]:
        """Config classes of a family, in registration order."""
        return [e.config for e in self._entries[family].values()]

    def __iter__(self) -> Iterator[Entry]:
        for family in FAMILIES:
            yield from self._entries[family].values()

    def __contains__(self, item: Any) -> bool:
        family, kind = item
        return kind in self._entries.get(family, {})
