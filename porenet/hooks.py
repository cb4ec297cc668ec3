"""Plugin hooks and the plugin loading policy.

A plugin is a module (usually named by an entry point in the ``porenet.plugins`` group) that
implements some of the hooks below with :data:`hookimpl`. Every hook only *registers* things:
it receives a ``register`` callback and calls it once per kind::

    from porenet.hooks import hookimpl

    @hookimpl
    def porenet_register_lattices(register):
        register(MyLatticeConfig, "mypackage.lattice:MyLattice")

``register(config, implementation)`` takes the pydantic config class (whose ``kind`` field is a
single ``Literal``) and the implementation class, or a ``"module:Class"`` string imported only
when a scene selects the kind. Third-party kinds must be namespaced (``"mypackage.kind"``).
Keywords give what else the kind answers (docs/architecture.md, "What a kind answers"), each
an object or a lazy ``"module:name"`` string: ``cost=`` its cost estimate
(:mod:`porenet.core.cost`), ``warm_ups=`` the scenes ``porenet compile`` runs to compile its
kernels (:class:`porenet.core.kinds.WarmUp`); ``default=True`` makes it the family's default
kind, which only porenet's own kinds may be.

Loading policy
--------------
* Built-in kinds are registered through these same hooks by the ``plugin`` module of each
  kind's folder (``porenet/kinds/<kind>/plugin.py``), loaded by name (:data:`DEFAULT_PLUGINS`) in
  the same loop as the entry points.
* Entry points of the group ``porenet.plugins`` are loaded one by one; a plugin that fails to
  import or to register is reported and skipped, unless loading is strict (``strict=True``, or
  the environment variable ``PORENET_STRICT_PLUGINS=1``, or ``CI=true``), in which case the
  failure is an error.
* ``PORENET_PLUGINS`` restricts which entry points load: a comma-separated list of entry-point
  names; an empty string loads none (built-ins are always loaded).
* A hook implementation whose name matches no hook specification is an error (pluggy's
  ``check_pending``), so a misspelt hook never fails silently.
* Nothing is loaded at ``import porenet``; the registry is built on first use.

Hooks are never called in the simulation loop.
"""

from __future__ import annotations

import importlib
import logging
import os
from collections.abc import Callable
from importlib.metadata import EntryPoint, entry_points
from types import ModuleType
from typing import Any, Protocol

import pluggy

from porenet.core.errors import PluginError
from porenet.core.registry import BUILTIN_PACKAGE, FAMILIES, Entry, Registry

log = logging.getLogger(__name__)

PROJECT = "porenet"
ENTRY_POINT_GROUP = "porenet.plugins"
#: porenet's own plugins, one per kind: plugin name -> module, loaded by name first in
#: :func:`build_registry`'s loop, as pytest loads its default plugins (docs/architecture.md,
#: rule 1). The only place the core names a kind: everything else is asked of the kinds
#: through the registry (``tests/unit/test_core_names_no_kind.py`` checks both).
DEFAULT_PLUGINS: dict[str, str] = {
    "porenet.square": "porenet.kinds.square.plugin",
    "porenet.cubic": "porenet.kinds.cubic.plugin",
    "porenet.network": "porenet.kinds.network.plugin",
    "porenet.invasion": "porenet.kinds.invasion.plugin",
    "porenet.viscous": "porenet.kinds.viscous.plugin",
    "porenet.rigid": "porenet.kinds.rigid.plugin",
    "porenet.hertz": "porenet.kinds.hertz.plugin",
    "porenet.mindlin": "porenet.kinds.mindlin.plugin",
    "porenet.pressure_aperture": "porenet.kinds.pressure_aperture.plugin",
    "porenet.progress": "porenet.kinds.progress.plugin",
    "porenet.snapshots": "porenet.kinds.snapshots.plugin",
    "porenet.no_classifier": "porenet.kinds.no_classifier.plugin",
    "porenet.rules": "porenet.kinds.rules.plugin",
    "porenet.theory": "porenet.kinds.theory.plugin",
}

hookspec = pluggy.HookspecMarker(PROJECT)
hookimpl = pluggy.HookimplMarker(PROJECT)


class Register(Protocol):
    """The ``register`` callback handed to every hook."""

    def __call__(
        self,
        config: type,
        implementation: type | str | None,
        *,
        default: bool = False,
        cost: Callable[..., Any] | str | None = None,
        warm_ups: tuple[Any, ...] | str | None = None,
    ) -> None:
        """Register the kind of ``config`` (module docstring)."""


class HookSpecs:
    """The hook specifications (one per family)."""

    @hookspec
    def porenet_register_lattices(self, register: Register) -> None:
        """Register lattice kinds: ``register(LatticeConfig, LatticeClass)``.

        The class subclasses :class:`porenet.core.interfaces.Lattice` and is constructed as
        ``LatticeClass(config, rng)``.
        """

    @hookspec
    def porenet_register_fluid_models(self, register: Register) -> None:
        """Register fluid models: ``register(FluidConfig, FluidClass)``.

        The class subclasses :class:`porenet.core.interfaces.FluidModel` and is constructed as
        ``FluidClass(config, lattice, context)``.
        """

    @hookspec
    def porenet_register_solid_models(self, register: Register) -> None:
        """Register solid models: ``register(SolidConfig, SolidClass or None)``.

        ``None`` (with ``SolidConfig.builds_nothing = True``) declares a kind that needs no
        mechanics at all, like the built-in ``rigid``.
        """

    @hookspec
    def porenet_register_couplers(self, register: Register) -> None:
        """Register fluid-solid couplers: ``register(CouplerConfig, CouplerClass)``."""

    @hookspec
    def porenet_register_observers(self, register: Register) -> None:
        """Register observers: ``register(ObserverConfig, ObserverClass)``.

        The class subclasses :class:`porenet.core.interfaces.Observer` and is constructed as
        ``ObserverClass(config)``.
        """

    @hookspec
    def porenet_register_classifiers(self, register: Register) -> None:
        """Register pattern classifiers: ``register(ClassifierConfig, ClassifierClass)``."""


FAMILY_HOOKS: dict[str, str] = {
    "lattice": "porenet_register_lattices",
    "fluid": "porenet_register_fluid_models",
    "solid": "porenet_register_solid_models",
    "coupler": "porenet_register_couplers",
    "observer": "porenet_register_observers",
    "classifier": "porenet_register_classifiers",
}


def _env_strict() -> bool:
    if os.environ.get("PORENET_STRICT_PLUGINS", "") not in ("", "0"):
        return True
    return os.environ.get("CI", "").lower() in ("1", "true", "yes")


def _selected_entry_points() -> list[EntryPoint]:
    eps = sorted(entry_points(group=ENTRY_POINT_GROUP), key=lambda ep: ep.name)
    allowed = os.environ.get("PORENET_PLUGINS")
    if allowed is None:
        return eps
    names = {n.strip() for n in allowed.split(",") if n.strip()}
    return [ep for ep in eps if ep.name in names]


def build_registry(
    *, strict: bool | None = None, extra_plugins: dict[str, ModuleType] | None = None
) -> Registry:
    """Load the built-ins and every selected entry-point plugin into a new :class:`Registry`.

    Parameters
    ----------
    strict : bool, optional
        Turn a plugin's failure into an error instead of a warning. Default: from the
        environment (``PORENET_STRICT_PLUGINS`` or ``CI``).
    extra_plugins : dict, optional
        ``{name: module}`` registered as if they came from entry points (for tests and for
        authors trying a plugin before packaging it).
    """
    strict = _env_strict() if strict is None else strict
    registry = Registry()
    pm = pluggy.PluginManager(PROJECT)
    pm.add_hookspecs(HookSpecs)
    packages: dict[str, str] = {}

    def fail(name: str, message: str, exc: BaseException | None = None) -> None:
        if strict:
            raise PluginError(message) from exc
        log.warning("%s (plugin skipped)", message)
        registry.failures.append((name, message))

    # the built-ins first, by module name, in the same loop as any plugin (as pytest's default
    # plugins): nothing here imports them, so they may import this module
    candidates: list[tuple[str, str, Callable[[], Any]]] = [
        (name, BUILTIN_PACKAGE, lambda module=module: importlib.import_module(module))
        for name, module in DEFAULT_PLUGINS.items()
    ]
    for ep in _selected_entry_points():
        dist = ep.dist.name if ep.dist is not None else ep.value.split(":")[0]
        candidates.append((ep.name, dist, ep.load))
    for name, module in (extra_plugins or {}).items():
        candidates.append((name, name, lambda m=module: m))

    for name, dist, load in candidates:
        if pm.has_plugin(name):
            fail(name, f"two plugins are named {name!r} (packages {packages[name]!r} and {dist!r})")
            continue
        try:
            pm.register(load(), name=name)
        except Exception as exc:  # isolate one broken plugin from the others
            if dist == BUILTIN_PACKAGE:
                raise  # porenet itself is broken: no point going on
            fail(name, f"plugin {name!r} from package {dist!r} failed to load: {exc}", exc)
            continue
        packages[name] = dist

    try:
        pm.check_pending()
    except pluggy.PluginValidationError as exc:
        raise PluginError(f"plugin {exc.plugin!r} implements an unknown hook: {exc}") from exc

    for plugin_name in [n for n, _ in pm.list_name_plugin()]:
        _register_one(pm, registry, plugin_name, packages.get(plugin_name, plugin_name), fail)
    return registry


def _register_one(
    pm: pluggy.PluginManager,
    registry: Registry,
    plugin_name: str,
    package: str,
    fail: Callable[[str, str, BaseException | None], None],
) -> None:
    """Call one plugin's register hooks, committing its kinds only if all succeed."""
    plugin = pm.get_plugin(plugin_name)
    staged: list[tuple[str, type, Any, dict[str, Any]]] = []
    try:
        for family, hook_name in FAMILY_HOOKS.items():
            for impl in getattr(pm.hook, hook_name).get_hookimpls():
                if impl.plugin is not plugin:
                    continue
                impl.function(
                    register=lambda config, implementation, f=family, **options: staged.append(
                        (f, config, implementation, options)
                    )
                )
        for family, config, implementation, options in staged:
            registry.add(
                family, config, implementation, package=package, plugin=plugin_name, **options
            )
    except PluginError:
        raise
    except Exception as exc:
        fail(plugin_name, f"plugin {plugin_name!r} failed while registering: {exc}", exc)


_REGISTRY: Registry | None = None


def get_registry() -> Registry:
    """The process-wide registry, built on first use."""
    global _REGISTRY
    if _REGISTRY is None:
        _REGISTRY = build_registry()
    return _REGISTRY


#: The plugin name of the kinds registered from a script or notebook (:func:`register`).
SCRIPT_PLUGIN = "porenet.register"

#: The interface each family's implementation subclasses (for :func:`register`'s inference).
_INTERFACES = {
    "lattice": "Lattice",
    "fluid": "FluidModel",
    "solid": "SolidModel",
    "coupler": "Coupler",
    "observer": "Observer",
    "classifier": "Classifier",
}


def register(
    config: type,
    implementation: type | str | None = None,
    *,
    family: str | None = None,
    cost: Callable[..., Any] | str | None = None,
    warm_ups: tuple[Any, ...] | str | None = None,
    registry: Registry | None = None,
) -> Entry:
    """Register a kind defined in a script or a notebook, with no package or entry point.

    ::

        import porenet
        from porenet.kinds.square.config import SquareLatticeConfig
        from porenet.kinds.square.model import SquareLattice

        class WideConfig(SquareLatticeConfig):
            kind: Literal["mine.wide"] = "mine.wide"

        class Wide(SquareLattice):
            def draw_apertures(self, rng):
                return 2.0 * super().draw_apertures(rng)

        porenet.register(WideConfig, Wide)
        porenet.run({"lattice": {"kind": "mine.wide", "n": 50}, "fluid": {}})

    The kind joins the process's registry (the one :func:`porenet.run`, ``load_scene`` and
    :class:`~porenet.simulation.Simulation` use by default) under the same rules as a
    plugin's (docs/plugins.md): a namespaced ``kind`` (``"mine.wide"``), a
    :class:`~porenet.config.base.ModelConfig` with a single-literal ``kind``, never a
    family's default. Registering the same kind again with this function (running a
    notebook cell twice) replaces it; a kind a plugin or porenet registered is never
    replaced (the error names the package that holds the name). Check the kind with the
    contract suite: ``check_kind(family, kind)`` (:mod:`porenet.testing.contract`,
    docs/contract.md).

    The kind lives in this process only: a sweep's worker processes and a ``porenet resume``
    in another process do not know it; for those, package it as a plugin (docs/plugins.md).

    Parameters
    ----------
    config : type
        The kind's pydantic config class.
    implementation : type, str or None
        Its class (a subclass of the family's interface in :mod:`porenet.core.interfaces`), a
        lazy ``"module:Class"``, or None for a kind that builds nothing.
    family : str, optional
        ``lattice``, ``fluid``, ``solid``, ``coupler``, ``observer`` or ``classifier``.
        Default: the family whose interface ``implementation`` subclasses.
    cost, warm_ups : optional
        The kind's cost estimate and compile warm-ups, as for a plugin (docs/cost.md,
        docs/architecture.md "What a kind answers").
    registry : Registry, optional
        Where to register; default the process's (:func:`get_registry`).

    Returns
    -------
    Entry
        The registered entry.

    Raises
    ------
    PluginError
        The family cannot be told or is unknown, or the registry's rules refuse the kind
        (the message says which rule).
    """
    registry = registry or get_registry()
    if family is None:
        family = _family_of(implementation)
    package = getattr(config, "__module__", None) or SCRIPT_PLUGIN
    return registry.add(family, config, implementation, package=package, plugin=SCRIPT_PLUGIN,
                        cost=cost, warm_ups=warm_ups, replace=True)  # fmt: skip


def _family_of(implementation: Any) -> str:
    """The family whose interface ``implementation`` subclasses (:func:`register`)."""
    from porenet.core import interfaces

    if isinstance(implementation, type):
        for family, name in _INTERFACES.items():
            if issubclass(implementation, getattr(interfaces, name)):
                return family
    raise PluginError(
        f"porenet.register: cannot tell the family of {implementation!r}: give family= (one "
        f"of {', '.join(FAMILIES)}), or an implementation that subclasses "
        f"{', '.join(_INTERFACES.values())} (porenet.core.interfaces)"
    )
