"""The registry owns the names of every kind (docs/architecture.md, rule 3).

Kinds are grouped in families (``lattice``, ``fluid``, ``solid``, ``coupler``, ``observer``,
``classifier``). Each entry ties a ``kind`` to its config class and to the implementation, which
may be a class or a ``"module:Class"`` string imported only when a scene selects the kind.
"""

from __future__ import annotations

import difflib
import importlib
from collections.abc import Iterator
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
    """

    family: str
    kind: str
    config: type
    implementation: type | str | None
    package: str
    plugin: str

    def load(self) -> type | None:
        """Return the implementation class, importing it if it was given as a string."""
        impl = self.implementation
        if impl is None or isinstance(impl, type):
            return impl
        module_name, _, attr = impl.partition(":")
        try:
            return getattr(importlib.import_module(module_name), attr)  # type: ignore[no-any-return]
        except (ImportError, AttributeError) as exc:
            raise PluginError(
                f"{self.family} kind {self.kind!r} from package {self.package!r}: cannot import "
                f"implementation {impl!r}: {exc}"
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
    ) -> Entry:
        """Register ``config``/``implementation`` under the config's ``kind``.

        Raises
        ------
        PluginError
            Unknown family, a config that is not a ModelConfig with a single-literal ``kind``, a
            third-party kind without a namespace (``"pkg.name"``), or a duplicate kind (the
            message names both packages).
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
        if existing is not None:
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
        if isinstance(implementation, str) and ":" not in implementation:
            raise PluginError(
                f"plugin {plugin!r}: implementation {implementation!r} must read 'module:Class'"
            )
        entry = Entry(family, kind, config, implementation, package, plugin)
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
