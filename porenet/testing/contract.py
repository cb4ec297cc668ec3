"""The contract suite every kind passes, built-in or from a plugin (docs/contract.md).

As scikit-learn's ``check_estimator`` does for estimators, this module turns the promises of a
role's interface (:mod:`porenet.core.interfaces`) into checks that any kind runs in its own
tests::

    from porenet.testing.contract import contract_checks, plugin_registry

    REGISTRY = plugin_registry({"gravity": porenet_gravity.plugin})

    @pytest.mark.parametrize(
        "check",
        contract_checks("fluid", "gravity.invasion-percolation", registry=REGISTRY),
        ids=str,
    )
    def test_contract(check):
        check()

:func:`contract_checks` gives the checks of one kind as :class:`Check` objects (a name and a
callable; ``str(check)`` is the test id ``family:kind:name``); :func:`contract_test` is that
test in one line (``test_contract = contract_test("fluid", KIND, registry=REGISTRY)``);
:func:`check_kind` runs them all and raises one AssertionError naming the kind and every
promise it breaks; :func:`covered_kinds` says which kinds of a registry the suite can check.
:func:`plugin_registry` builds the registry a plugin's tests check in (porenet's kinds and the
plugin's, no installed plugin) and :func:`registry_fixture` gives it to them from their
``conftest.py``.

The scene
---------
Each kind is checked on a small scene that uses it: its config's classmethod
``example_scene()`` (:func:`porenet.core.kinds.example_scene`), or the ``scene`` given. A kind
with neither is *uncovered*: its only check, ``uncovered``, fails and says how to give it one;
so a test that runs the suite over a whole registry covers 100 % of its kinds or fails.

The checks
----------
Every kind:

* ``config-strict``: the config is frozen, forbids unknown fields and names its kind with a
  single ``Literal`` (docs/architecture.md, rule 4).
* ``config-errors``: what a user can get wrong in the kind's section of the example scene is a
  :class:`~porenet.core.errors.ConfigError` from :func:`porenet.config.loading.load_scene`
  whose message names the dotted field (``fluid.bond_number``, ``observers[0].every``): a
  misspelt field (and the message suggests the right one), each required field left out, and
  for each scalar field a value beyond each bound of its pydantic metadata (``gt``, ``ge``,
  ``lt``, ``le``), a word where a number or a boolean is wanted, a word that is none of a
  ``Literal``'s options, and ``nan`` where the field refuses non-finite numbers. The cases come
  from the pydantic model; fields with no generic bad value (paths, lists, nested models,
  unions) give none. Couplers have no section (the coupler is built from the solid's config),
  so no case.
* ``implementation``: the registered implementation imports and subclasses the role's
  interface (``None`` only for a config that ``builds_nothing``).
* ``light-import`` (kinds registered with a lazy ``"module:Class"``): importing the config's
  module and the plugin's module, in a fresh interpreter, imports none of :data:`HEAVY`
  (numba, scipy) and not the implementation's module (docs/architecture.md, rule 3).
* ``runs``: the example scene validates, selects the kind, builds the role's object (none for a
  kind that builds nothing) and runs; the summary has ``stop_reason`` and ``n_drained``.
* ``deterministic``: a second run with the same seed gives the same run data to the bit: the
  invasion record, the final masks and fields, time series, snapshots, the solid's fields and
  series, the observers' records and the summary (docs/architecture.md, rule 10).
* ``finite``: no ``nan`` or ``inf`` in any float array of the run data (a field that is
  ``None`` is fine; the summary's scalars are not arrays: a ``nan`` D_f of a tiny pattern is
  a measurement).
* ``run-file``: a run with ``output=`` writes a run file that :func:`porenet.io.runfile.
  read_run` gives back equal to the run's data, with every summary value that is not None;
  every observer's records are under ``observers[<name>]``, each with a unit
  (:attr:`Observer.output_units <porenet.core.interfaces.Observer.output_units>`).
* ``checkpoint``: the run is interrupted once about half of its pores past the inlets have
  drained (a trigger that asks the fluid model to stop there), written to a checkpoint,
  resumed with :meth:`Simulation.resume <porenet.simulation.Simulation.resume>` and finished:
  its data equal the uninterrupted run's, to the bit.

By role (a check that does not apply to a role is not generated for it; one whose records a
kind does not keep is skipped, with the reason):

* fluid, ``invaded-cluster``: ``n_drained`` is the drained mask's count; the invasion order
  lists distinct pores, exactly the drained ones, the inlets first (entered through no throat,
  ``-1``, at pressure 0); each later pore was entered through a throat from a pore drained
  before it; drained and trapped are disjoint; every drained pore is joined to the inlets
  through drained pores and the lattice's throats.
* fluid, ``volume-balance`` (a fluid whose effects include ``viscous_dissipation``, when its
  time series hold ``injected``, ``stored``, ``outflow`` and ``released``): ``injected =
  stored + outflow + released`` at every record, within
  :data:`VOLUME_BALANCE` of ``injected`` (the loosest integrator's bound in
  ``tests/verification/test_viscous_integrators.py``).
* solid, ``force-balance`` (when the per-update series hold ``balance_residual``): the largest
  residual is within :data:`FORCE_ROUND_OFF` of ``gamma a`` (the Hertz solid's tests), plus,
  for a solid that leaves force out of balance by design and says how much
  (:attr:`~porenet.core.interfaces.SolidModel.unresolved_deformation`, units of ``a``),
  :data:`TOLERANCE_FACTOR` times that deformation at the stiffness its
  :attr:`~porenet.core.interfaces.SolidModel.compliance` implies (the frictional solid's
  tests).
* solid, ``final-apertures``: the final apertures are finite and positive.
* lattice, ``lattice``: the lattice contract (docs/lattices.md): shapes and dtypes of the
  throats' pores and the pores' centres, throats join two distinct existing pores, positive
  finite apertures, volumes and lengths, a consistent grid, every site the config's
  ``site_names()`` lists is a non-empty pore set.
* classifier, ``classification``: ``classify`` of the run gives a regime of
  :data:`porenet.analysis.regimes.REGIMES` and a confidence in [0, 1], the same twice.
* a kind whose config ``builds_nothing``, ``builds-nothing``: the run built no object for it
  (docs/architecture.md, rule 7).
* couplers: the checks above on a deformable solid's scene.

Length (over the ~500 lines of docs/architecture.md's rule): by design: one suite, the
checks of every role on the runs they share and the comparisons of run data they all use;
split, each part would reach into the shared runs from outside.

Decisions
---------
* Timing is not a result: summary keys ending in ``_time_s`` or holding ``seconds`` or starting
  with ``thread`` (wall and compile times, thread counters) are left out of the comparisons.
* The checks of a kind share its runs (the first run is made once, when a check first needs
  it), so the suite costs a few runs of a tiny scene per kind; nothing runs when the checks are
  made (test collection) and nothing of numba is imported by this module.
* A checkpoint is resumed under the registry being checked
  (``Simulation.resume(path, registry=...)``), so kinds of a registry built by hand, not
  installed, resume too.
* Pure Python at import apart from numpy and porenet's light core; pytest is imported only to
  report a skipped check, and only when it is already loaded.
"""

from __future__ import annotations

import copy
import dataclasses
import importlib
import importlib.util
import json
import math
import os
import re
import subprocess
import sys
import tempfile
import types
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path
from typing import Annotated, Any, Literal, Union, get_args, get_origin

import numpy as np

from porenet.core.interfaces import Observer
from porenet.core.kinds import builds_nothing, effects, example_scene
from porenet.core.registry import BUILTIN_PACKAGE, Registry
from porenet.core.triggers import Schedule

#: Relative bound on ``injected - stored - outflow - released`` (of ``injected``).
VOLUME_BALANCE = 1e-10
#: Bound on the largest force balance residual of an exact solid, in units of ``gamma a``.
FORCE_ROUND_OFF = 1e-9
#: The residual may reach this many times the deformation a solid leaves unresolved by design
#: (``SolidModel.unresolved_deformation``) at its stiffness.
TOLERANCE_FACTOR = 10.0

#: Modules a kind's config and plugin modules must not import (``light-import``).
HEAVY = ("numba", "scipy")
#: The scene section of each family's kind (couplers have none: see the module docstring).
SECTIONS = {"lattice": "lattice", "fluid": "fluid", "solid": "solid",
            "classifier": "classifier", "observer": "observers"}  # fmt: skip
#: Run data fields that are arrays (or None), compared and checked for finite values.
ARRAY_FIELDS = ("throat_pores", "pore_coords", "apertures", "drained", "trapped", "order",
                "throat", "invasion_pressure", "pressure", "invasion_time", "final_apertures",
                "burst_sizes")  # fmt: skip
#: Run data fields that are ``{name: array}`` (observers' records: by observer, then name).
DICT_FIELDS = ("timeseries", "mechanics_final", "mechanics_series")


class NotApplicable(Exception):
    """Raised by a check whose records the kind does not keep (reported as a skip)."""


@dataclass(frozen=True)
class Check:
    """One promise of one kind: call it to check it.

    Attributes
    ----------
    family, kind : str
        The kind checked.
    name : str
        The promise (``deterministic``, ``run-file``, ...); ``str(check)`` is
        ``family:kind:name``, the test id.
    function : callable
        Raises AssertionError when the promise is broken, :class:`NotApplicable` when the
        kind keeps none of what it checks.
    """

    family: str
    kind: str
    name: str
    function: Callable[[], None]

    def __str__(self) -> str:
        return f"{self.family}:{self.kind}:{self.name}"

    def outcome(self) -> str | None:
        """Run the check: None if it holds, the reason if it does not apply.

        Raises
        ------
        AssertionError
            Naming the kind and the promise, when it is broken (any exception the check
            meets is reported so, chained).
        """
        try:
            self.function()
        except NotApplicable as reason:
            return str(reason)
        except Exception as exc:
            what = "" if isinstance(exc, AssertionError) else f"{type(exc).__name__}: "
            raise AssertionError(
                f"{self.family} kind {self.kind!r} breaks the contract's {self.name!r}: {what}{exc}"
            ) from exc
        return None

    def __call__(self) -> None:
        reason = self.outcome()
        if reason is not None and "pytest" in sys.modules:
            import pytest

            pytest.skip(f"{self}: {reason}")


def plugin_registry(plugins: dict[str, types.ModuleType] | None = None) -> Registry:
    """A strict registry of porenet's own kinds and the given plugin modules (``{name:
    module}``, as entry points would register them), without any installed plugin (as
    ``PORENET_PLUGINS=""``): the registry a plugin's tests check their kinds in."""
    from porenet.hooks import build_registry

    before = os.environ.get("PORENET_PLUGINS")
    os.environ["PORENET_PLUGINS"] = ""
    try:
        return build_registry(strict=True, extra_plugins=plugins)
    finally:
        if before is None:
            del os.environ["PORENET_PLUGINS"]
        else:
            os.environ["PORENET_PLUGINS"] = before


def contract_test(
    family: str,
    kind: str,
    *,
    scene: dict[str, Any] | None = None,
    registry: Registry | None = None,
) -> Callable[[Check], None]:
    """A pytest test of one kind, one case per check of :func:`contract_checks` (ids:
    ``str(check)``); give it a name starting with ``test`` in a test module::

        test_contract = contract_test("fluid", KIND, registry=plugin_registry({...}))
    """
    return parametrized(contract_checks(family, kind, scene=scene, registry=registry))


def parametrized(checks: list[Any]) -> Callable[[Any], None]:
    """A pytest test that calls each of ``checks`` (callables; ids: their ``str``)."""
    import pytest

    @pytest.mark.parametrize("check", checks, ids=str)
    def test(check: Any) -> None:
        check()

    return test


def registry_fixture(conftest: str | Path, plugins: dict[str, str], name: str = "reg") -> Any:
    """For a plugin's ``tests/conftest.py``: put the plugin's ``src/`` folder on ``sys.path``
    (its tests run from the checkout, without installing it) and return a session-scoped
    pytest fixture ``name`` giving :func:`plugin_registry` of ``plugins`` (``{name:
    "module"}``, imported when the fixture is first used)::

        reg = registry_fixture(__file__, {"gravity": "porenet_gravity.plugin"})
    """
    import pytest

    src = str(Path(conftest).resolve().parents[1] / "src")
    if src not in sys.path:
        sys.path.insert(0, src)

    @pytest.fixture(scope="session", name=name)
    def registry() -> Registry:
        return plugin_registry({k: importlib.import_module(m) for k, m in plugins.items()})

    return registry


def covered_kinds(registry: Registry) -> set[tuple[str, str]]:
    """``(family, kind)`` of the registry's kinds whose config gives an example scene."""
    return {(e.family, e.kind) for e in registry if example_scene(e.config) is not None}


def all_checks(registry: Registry) -> list[Check]:
    """The checks of every kind of ``registry``, in its order."""
    return [c for e in registry for c in contract_checks(e.family, e.kind, registry=registry)]


def check_kind(
    family: str,
    kind: str,
    *,
    scene: dict[str, Any] | None = None,
    registry: Registry | None = None,
) -> list[str]:
    """Run every check of a kind; return the names of those that did not apply.

    Raises
    ------
    AssertionError
        Naming the kind and each promise it breaks, with what was found.
    """
    skipped, broken = [], []
    for check in contract_checks(family, kind, scene=scene, registry=registry):
        try:
            if check.outcome() is not None:
                skipped.append(check.name)
        except AssertionError as exc:
            broken.append(f"{check.name}: {exc}")
    if broken:
        raise AssertionError(
            f"{family} kind {kind!r} breaks {len(broken)} promise(s) of the contract "
            "(docs/contract.md):\n  " + "\n  ".join(broken)
        )
    return skipped


def contract_checks(
    family: str,
    kind: str,
    *,
    scene: dict[str, Any] | None = None,
    registry: Registry | None = None,
) -> list[Check]:
    """The checks of one kind (module docstring), on ``scene`` or the kind's example scene.

    Nothing runs here: each check runs when called, sharing the kind's runs with the others.

    Parameters
    ----------
    family, kind : str
        The kind, as registered (``"fluid"``, ``"gravity.invasion-percolation"``).
    scene : dict, optional
        A small scene that uses the kind; default its config's ``example_scene()``.
    registry : Registry, optional
        Where the kind is registered; default porenet's process-wide registry.
    """
    if registry is None:
        from porenet.hooks import get_registry

        registry = get_registry()
    entry = registry.get(family, kind)
    scene = scene if scene is not None else example_scene(entry.config)
    if scene is None:

        def uncovered() -> None:
            raise AssertionError(
                f"uncovered: its config {entry.config.__qualname__} has no example_scene() "
                "classmethod giving a small scene that uses it (docs/contract.md, "
                '"Uncovered kinds")'
            )

        return [Check(family, kind, "uncovered", uncovered)]
    s = _Subject(family, kind, scene, registry)
    names: list[tuple[str, Callable[[], None]]] = [
        ("config-strict", s.check_config_strict),
        ("implementation", s.check_implementation),
    ]
    if family in SECTIONS:
        names.append(("config-errors", s.check_config_errors))
    if isinstance(entry.implementation, str):
        names.append(("light-import", s.check_light_import))
    names += [("runs", s.check_runs), ("deterministic", s.check_deterministic),
              ("finite", s.check_finite), ("run-file", s.check_run_file),
              ("checkpoint", s.check_checkpoint)]  # fmt: skip
    if builds_nothing(entry.config):
        names.append(("builds-nothing", s.check_builds_nothing))
    elif family == "fluid":
        names.append(("invaded-cluster", s.check_cluster))
        if s.moves_volumes:
            names.append(("volume-balance", s.check_volumes))
    elif family == "solid":
        names += [("force-balance", s.check_forces), ("final-apertures", s.check_apertures)]
    elif family == "lattice":
        names.append(("lattice", s.check_lattice))
    elif family == "classifier":
        names.append(("classification", s.check_classification))
    return [Check(family, kind, name, function) for name, function in names]


# -- the runs a kind's checks share ------------------------------------------------------------
class _Halt(Observer):
    """Observes nothing; its trigger makes the fluid model's call end at ``count`` drained
    pores, where the checkpoint check interrupts the run."""

    def __init__(self, count: int) -> None:
        super().__init__(None)
        self.trigger = Schedule([count])


class _Interrupted(Exception):
    """The run was stopped right after its checkpoint was written."""


class _CheckpointAt:
    """A checkpoint schedule (:meth:`Simulation.run`'s ``checkpoints``) that writes one when
    ``count`` pores have drained and stops the run there."""

    def __init__(self, path: Path, count: int) -> None:
        self.path, self.count = path, count

    def due(self, state: Any) -> bool:
        return bool(state.n_drained >= self.count)

    def write(self, simulation: Any) -> None:
        from porenet.io.checkpoint import write_checkpoint

        write_checkpoint(self.path, simulation, simulation.checkpoint_header())
        raise _Interrupted

    def remove(self) -> None:
        self.path.unlink(missing_ok=True)


class _Subject:
    """A kind, its example scene and its registry, with the runs its checks share."""

    def __init__(self, family: str, kind: str, scene: dict[str, Any], registry: Registry):
        self.family, self.kind, self.registry = family, kind, registry
        self.scene = scene
        self.entry = registry.get(family, kind)

    def simulate(self, **options: Any) -> tuple[Any, Any]:
        """``(simulation, result)`` of a fresh run of the scene (``options``: of
        :meth:`Simulation.from_scene`)."""
        from porenet.simulation import Simulation

        sim = Simulation.from_scene(copy.deepcopy(self.scene), registry=self.registry, **options)
        return sim, sim.run()

    @cached_property
    def first(self) -> tuple[Any, Any]:
        return self.simulate()

    @cached_property
    def section(self) -> tuple[str, dict[str, Any]] | None:
        """The dotted name and the table of the kind's section in the scene, if it has one."""
        name = SECTIONS.get(self.family)
        if name is None:
            return None
        tables = self.scene.get(name, [] if self.family == "observer" else {})
        if self.family != "observer":
            tables = [tables]
        default = self.registry.default(self.family)
        for i, table in enumerate(tables):
            if isinstance(table, dict) and table.get("kind", default) == self.kind:
                return (f"{name}[{i}]" if self.family == "observer" else name), table
        return None

    @cached_property
    def moves_volumes(self) -> bool:
        """The fluid drains by a pressure field it solves (its effect ``viscous_dissipation``;
        True where the scene does not validate or the config declares no effects, so that
        the check is made and says why not): only then does it book volumes to balance."""
        from porenet.config.loading import load_scene
        from porenet.core.errors import ConfigError

        try:
            config = load_scene(copy.deepcopy(self.scene), registry=self.registry).fluid
        except ConfigError:
            return True
        return bool(effects(config).get("viscous_dissipation", True))

    def role_objects(self, sim: Any) -> list[Any]:
        """The simulation's objects of the kind's family."""
        if self.family == "observer":
            return list(sim.observers)
        return [o for o in [getattr(sim, self.family)] if o is not None]

    # -- every kind ---------------------------------------------------------------------------
    def check_config_strict(self) -> None:
        config = self.entry.config
        settings = config.model_config
        assert settings.get("frozen") is True, f"{config.__qualname__} is not frozen"
        assert settings.get("extra") == "forbid", f"{config.__qualname__} allows unknown fields"
        assert config.kind_name() == self.kind, f"{config.__qualname__} names another kind"

    def check_implementation(self) -> None:
        from porenet.core import interfaces

        implementation = self.entry.load()
        if implementation is None:
            assert builds_nothing(self.entry.config), (
                "registered without an implementation, but its config does not say builds_nothing"
            )
            return
        role = {"lattice": interfaces.Lattice, "fluid": interfaces.FluidModel,
                "solid": interfaces.SolidModel, "coupler": interfaces.Coupler,
                "observer": interfaces.Observer,
                "classifier": interfaces.Classifier}[self.family]  # fmt: skip
        assert isinstance(implementation, type) and issubclass(implementation, role), (
            f"{implementation!r} does not subclass porenet.core.interfaces.{role.__name__}"
        )

    def check_config_errors(self) -> None:
        from porenet.config.loading import load_scene
        from porenet.core.errors import ConfigError

        found = self.section
        assert found is not None, "the example scene has no section of this kind"
        prefix, table = found
        problems = []
        for label, changed, dotted in _config_cases(self.entry.config, prefix, table):
            scene = copy.deepcopy(self.scene)
            target = scene.setdefault(SECTIONS[self.family], {})
            if self.family == "observer":
                target = target[int(prefix.split("[")[1].rstrip("]"))]
            for key, value in changed.items():
                if value is _DELETE:
                    del target[key]
                else:
                    target[key] = value
            try:
                load_scene(scene, registry=self.registry)
            except ConfigError as exc:
                if not all(re.search(re.escape(d) + r"(?!\w)", str(exc)) for d in dotted):
                    problems.append(f"{label}: the message does not name {dotted[0]}: {exc}")
                continue
            except Exception as exc:
                problems.append(f"{label}: {type(exc).__name__} instead of a ConfigError: {exc}")
                continue
            problems.append(f"{label}: accepted")
        assert not problems, "\n    ".join(["config errors that do not name the field:", *problems])

    def check_light_import(self) -> None:
        implementation = str(self.entry.implementation).partition(":")[0]
        modules = [self.entry.config.__module__]
        plugin = _plugin_module(self.entry)
        if plugin is not None:
            modules.append(plugin)
        code = (
            "import importlib, json, sys\n"
            f"for name in {modules!r}: importlib.import_module(name)\n"
            f"print(json.dumps([m for m in {[*HEAVY, implementation]!r} if m in sys.modules]))\n"
        )
        path = os.pathsep.join(p for p in sys.path if isinstance(p, str) and p)
        env = {**os.environ, "PYTHONPATH": path}
        out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True,
                             text=True, timeout=120, check=False)  # fmt: skip
        assert out.returncode == 0, f"importing {', '.join(modules)} failed: {out.stderr[-2000:]}"
        loaded = json.loads(out.stdout.strip().splitlines()[-1])
        assert not loaded, f"importing {' and '.join(modules)} imports {', '.join(loaded)}"

    def check_runs(self) -> None:
        from porenet.config.loading import load_scene

        config = load_scene(copy.deepcopy(self.scene), registry=self.registry)
        if self.family == "coupler":
            selected = getattr(config.solid, "coupler", None) == self.kind
        elif self.family == "observer":
            selected = any(o.kind == self.kind for o in config.observers)
        else:
            selected = getattr(config, self.family).kind == self.kind
        assert selected, "the example scene does not select this kind"
        sim, result = self.first
        for key in ("stop_reason", "n_drained"):
            assert key in result.summary, f"the summary has no {key!r}"
        if builds_nothing(self.entry.config):
            return
        implementation = self.entry.load()
        built = [o for o in self.role_objects(sim) if isinstance(o, implementation)]  # type: ignore[arg-type]
        assert built, f"the run built no {implementation.__name__}"  # type: ignore[union-attr]

    def check_deterministic(self) -> None:
        _, first = self.first
        _, again = self.simulate()
        differ = _differences(first.data, again.data)
        assert not differ, f"two runs with seed {self.scene.get('seed')} differ in {differ}"

    def check_finite(self) -> None:
        _, result = self.first
        bad = [name for name, values in _arrays(result.data)
               if values.dtype.kind in "fc" and not np.all(np.isfinite(values))]  # fmt: skip
        assert not bad, f"nan or inf in {', '.join(bad)}"

    def check_run_file(self) -> None:
        from porenet.io.runfile import read_run

        with tempfile.TemporaryDirectory() as folder:
            path = Path(folder) / "run.h5"
            sim, result = self.simulate(output=path)
            back = read_run(path)
        data = result.data
        summary = {k: v for k, v in data.summary.items() if v is not None}
        for key in ("stop_reason", "n_drained"):
            assert key in back.summary, f"the run file's summary has no {key!r}"
        missing = sorted(set(summary) - set(back.summary))
        assert not missing, f"the run file's summary lacks {missing}"
        differ = _differences(dataclasses.replace(data, summary=summary), back, timing=True)
        assert not differ, f"the run file gives back other {differ}"
        no_unit = [f"{group}/{key}" for group, records in back.observers.items()
                   for key in records if not back.observer_units[group].get(key)]  # fmt: skip
        assert not no_unit, f"observers' records without a unit: {no_unit}"
        if self.family == "observer":
            for obs in self.role_objects(sim):
                if isinstance(obs, self.entry.load()) and obs.output_units:  # type: ignore[arg-type]
                    assert obs.output_name in back.observers, (
                        f"no records under observers[{obs.output_name!r}]"
                    )

    def check_checkpoint(self) -> None:
        from porenet.config.loading import load_scene
        from porenet.core.plan import make_plan
        from porenet.simulation import Simulation

        _, reference = self.first
        data = reference.data
        start, end = int(np.sum(data.throat < 0)), len(data.order)
        count = start + (end - start) // 2
        assert start < count < end, (
            f"the example scene drains {end - start} pore(s) past its {start} inlet(s): too "
            "few to interrupt the run between them"
        )
        config = load_scene(copy.deepcopy(self.scene), registry=self.registry)
        sim = Simulation(make_plan(config, self.registry), self.registry, [_Halt(count)])
        with tempfile.TemporaryDirectory() as folder:
            path = Path(folder) / "run.h5.checkpoint"
            try:
                sim.run(_CheckpointAt(path, count))  # type: ignore[arg-type]
                raise AssertionError(f"the run ended before {count} drained pores")
            except _Interrupted:
                pass
            resumed = Simulation.resume(path, registry=self.registry)
        assert start < resumed.state.n_drained < end, "the checkpoint is not part way"
        differ = _differences(data, resumed.run().data)
        assert not differ, f"the resumed run differs from the uninterrupted one in {differ}"

    def check_builds_nothing(self) -> None:
        sim, _ = self.first
        built = [type(o).__name__ for o in self.role_objects(sim)]
        if self.family == "solid":
            built += [type(sim.coupler).__name__] if sim.coupler is not None else []
        assert not built, f"its config builds nothing, but the run built {built}"

    # -- by role --------------------------------------------------------------------------------
    def check_cluster(self) -> None:
        sim, result = self.first
        data, lattice = result.data, sim.lattice
        drained, trapped, order = data.drained, data.trapped, np.asarray(data.order)
        assert result.summary["n_drained"] == int(drained.sum()), "n_drained != drained.sum()"
        assert len(np.unique(order)) == len(order), "the invasion order repeats pores"
        assert set(order.tolist()) == set(np.flatnonzero(drained).tolist()), (
            "the invasion order and the drained mask list different pores"
        )
        assert len(data.throat) == len(order) == len(data.invasion_pressure), (
            "order, throat and invasion_pressure have different lengths"
        )
        assert not np.any(drained & trapped), "pores both drained and trapped"
        inlets = lattice.inlet_pores(sim.plan.scene.injection.at)
        k = len(inlets)
        assert set(order[:k].tolist()) == set(inlets.tolist()), (
            "the order starts not with the inlets"
        )
        assert np.all(data.throat[:k] < 0) and np.all(data.invasion_pressure[:k] == 0), (
            "the inlets are not recorded as entered through no throat (-1) at pressure 0"
        )
        rank = np.full(lattice.n_pores, -1)
        rank[order] = np.arange(len(order))
        pairs = np.asarray(lattice.throat_pores)
        for k, t in enumerate(np.asarray(data.throat)):
            if t < 0:
                continue
            a, b = (int(p) for p in pairs[t])
            other = b if a == order[k] else a
            assert order[k] in (a, b) and 0 <= rank[other] < k, (
                f"pore {order[k]} (step {k}) was not entered through throat {t} from a pore "
                "drained before it"
            )
        reached = _reachable(lattice, inlets, drained)
        cut_off = np.flatnonzero(drained & ~reached)
        assert cut_off.size == 0, f"drained pores not joined to the inlets: {cut_off[:10]}"

    def check_volumes(self) -> None:
        _, result = self.first
        series = result.data.timeseries
        names = ("injected", "stored", "outflow", "released")
        if not all(n in series for n in names):
            raise NotApplicable(f"the fluid records no time series {', '.join(names)}")
        injected, stored, outflow, released = (np.asarray(series[n]) for n in names)
        residual = np.abs(injected - stored - outflow - released)
        worst = int(np.argmax(residual - VOLUME_BALANCE * np.abs(injected)))
        assert residual[worst] <= VOLUME_BALANCE * abs(injected[worst]), (
            f"injected - stored - outflow - released = {residual[worst]:.3g} m^3 at record "
            f"{worst}, over {VOLUME_BALANCE:g} of injected = {injected[worst]:.3g} m^3"
        )

    def check_forces(self) -> None:
        sim, result = self.first
        residuals = result.data.mechanics_series.get("balance_residual")
        if residuals is None or len(residuals) == 0:
            raise NotApplicable("the solid records no balance_residual per update")
        sc = sim.scales
        force = sc.pressure * sc.area  # gamma a, N
        declared = float(getattr(sim.solid, "unresolved_deformation", 0.0))
        stiffness = sc.pressure * sc.length / sim.solid.compliance  # gamma / C, N/m
        bound = FORCE_ROUND_OFF * force + TOLERANCE_FACTOR * declared * sc.length * stiffness
        worst = float(np.max(residuals))
        assert worst <= bound, (
            f"force balance residual {worst:.3g} N over the bound {bound:.3g} N "
            f"({FORCE_ROUND_OFF:g} gamma a, plus the tolerances the solid declares)"
        )

    def check_apertures(self) -> None:
        _, result = self.first
        final = result.data.final_apertures
        assert final is not None, "the run data has no final apertures"
        assert np.all(np.isfinite(final)) and np.all(final > 0), (
            f"final apertures not positive and finite (min {np.min(final):.3g} m)"
        )

    def check_lattice(self) -> None:
        sim, _ = self.first
        lat = sim.lattice
        n, pairs, xy = lat.n_pores, np.asarray(lat.throat_pores), np.asarray(lat.pore_coords)
        m = len(pairs)
        assert pairs.ndim == 2 and pairs.shape[1] == 2, f"throat_pores has shape {pairs.shape}"
        assert pairs.dtype.kind in "iu", f"throat_pores has dtype {pairs.dtype}"
        assert xy.shape in ((n, 2), (n, 3)), f"pore_coords has shape {xy.shape} for {n} pores"
        assert xy.dtype.kind == "f" and lat.dimension == xy.shape[1], "pore_coords not float"
        assert np.all((pairs >= 0) & (pairs < n)), "a throat joins a pore that does not exist"
        assert np.all(pairs[:, 0] != pairs[:, 1]), "a throat joins a pore to itself"
        for name, values, size in (("initial_apertures", lat.initial_apertures, m),
                                   ("pore_volumes", lat.pore_volumes, n),
                                   ("throat_lengths", lat.throat_lengths, m)):  # fmt: skip
            values = np.asarray(values)
            assert values.shape == (size,), f"{name} has shape {values.shape}, not ({size},)"
            assert np.all(np.isfinite(values)) and np.all(values > 0), f"{name} not all > 0"
        boundary = np.asarray(lat.boundary_pores)
        assert boundary.shape == (n,) and boundary.dtype == bool, "boundary_pores not (n,) bool"
        shape = lat.grid_shape
        assert shape is None or shape[0] * shape[1] == n, f"grid_shape {shape} for {n} pores"
        if lat.canonical_grid:
            assert shape is not None and shape[0] == shape[1], "canonical_grid without n x n"
            k = shape[0]
            ids = np.arange(n).reshape(k, k)
            canonical = np.concatenate([
                np.stack([ids[:, :-1].ravel(), ids[:, 1:].ravel()], axis=1),
                np.stack([ids[:-1, :].ravel(), ids[1:, :].ravel()], axis=1),
            ])  # fmt: skip
            assert np.array_equal(pairs, canonical), "canonical_grid, but not in canonical order"
        site_names = getattr(lat.config, "site_names", None)
        for name in (site_names() if callable(site_names) else None) or []:
            mask = np.asarray(lat.sites(name))
            assert mask.shape == (n,) and mask.dtype == bool, f"sites({name!r}) not (n,) bool"
            assert mask.any(), f"site {name!r}, listed by site_names(), has no pore"

    def check_classification(self) -> None:
        from porenet.analysis.regimes import REGIMES
        from porenet.core.interfaces import Classification

        sim, result = self.first
        verdicts = [sim.classifier.classify(result.data) for _ in range(2)]
        for verdict in verdicts:
            assert isinstance(verdict, Classification), f"classify returned {verdict!r}"
            assert verdict.regime in REGIMES, f"regime {verdict.regime!r} not in {REGIMES}"
            assert 0.0 <= float(verdict.confidence) <= 1.0, f"confidence {verdict.confidence}"
        first, second = verdicts
        assert (first.regime, first.confidence) == (second.regime, second.confidence), (
            "two classifications of the same run differ"
        )


# -- config cases ------------------------------------------------------------------------------
_DELETE = object()


def _typo(name: str, taken: Any) -> str:
    """A misspelling of ``name`` (its last two letters swapped) that is no field's name."""
    typo = name[:-2] + name[-1] + name[-2] if len(name) > 2 else name + "x"
    while typo == name or typo in taken:
        typo += "x"
    return typo


def _scalar(annotation: Any) -> Any:
    """``int``, ``float``, ``bool``, the ``Literal``'s options (a tuple), or None."""
    origin, args = get_origin(annotation), get_args(annotation)
    if origin is Annotated:
        return _scalar(args[0])
    if origin in (Union, types.UnionType):
        members = [a for a in args if a is not type(None)]
        return _scalar(members[0]) if len(members) == 1 else None
    if origin is Literal:
        return tuple(args)
    return annotation if annotation in (int, float, bool) else None


def _outside(kind: type, bound: str, value: float) -> float:
    """A value of type ``kind`` (int or float) beyond the bound ``bound`` (``gt``...) of
    ``value``."""
    if kind is int:
        return {"gt": math.floor(value), "ge": math.ceil(value) - 1,
                "lt": math.ceil(value), "le": math.floor(value) + 1}[bound]  # fmt: skip
    step = max(1.0, abs(float(value)))
    return {"gt": float(value), "ge": float(value) - step,
            "lt": float(value), "le": float(value) + step}[bound]  # fmt: skip


def _config_cases(
    config: Any, prefix: str, table: dict[str, Any]
) -> list[tuple[str, dict[str, Any], tuple[str, ...]]]:
    """``(label, changes to the section, dotted names the message must hold)`` of every bad
    input the config's pydantic model says it refuses (module docstring)."""
    fields = {k: v for k, v in config.model_fields.items() if k != "kind"}
    typo_of = next(iter(fields), "field")
    typo = _typo(typo_of, fields)
    suggestion = (f"did you mean {typo_of!r}",) if fields else ()
    cases = [(f"misspelt {typo}", {typo: 1}, (f"{prefix}.{typo}", *suggestion))]
    finite_default = config.model_config.get("allow_inf_nan", True)
    for name, info in fields.items():
        dotted = (f"{prefix}.{name}",)
        if info.is_required() and name in table:
            cases.append((f"{name} missing", {name: _DELETE}, dotted))
        kind = _scalar(info.annotation)
        if kind is None:
            continue
        if isinstance(kind, tuple):
            if all(isinstance(option, str) for option in kind):
                cases.append((f"{name} = 'no-such-option'", {name: "no-such-option"}, dotted))
            continue
        if kind is bool:
            cases.append((f"{name} = 'maybe'", {name: "maybe"}, dotted))
            continue
        cases.append((f"{name} = 'not-a-number'", {name: "not-a-number"}, dotted))
        finite = finite_default
        for item in info.metadata:
            for bound in ("gt", "ge", "lt", "le"):
                value = getattr(item, bound, None)
                if isinstance(value, int | float) and not isinstance(value, bool):
                    bad = _outside(kind, bound, value)
                    cases.append((f"{name} = {bad!r} ({bound} {value})", {name: bad}, dotted))
            if getattr(item, "allow_inf_nan", None) is not None:
                finite = item.allow_inf_nan
        if kind is float and finite is False:
            cases.append((f"{name} = nan", {name: float("nan")}, dotted))
    return cases


# -- comparing run data --------------------------------------------------------------------------
def _timing(key: str) -> bool:
    """Summary keys that measure wall time or threads, not the run's result."""
    return key.endswith("_time_s") or "seconds" in key or key.startswith("thread")


def _same(x: Any, y: Any) -> bool:
    if x is None or y is None:
        return x is None and y is None
    try:
        a, b = np.asarray(x), np.asarray(y)
        if a.shape != b.shape:
            return False
        if a.dtype.kind in "fc" and b.dtype.kind in "fc":
            return bool(np.array_equal(a, b, equal_nan=True))
        return bool(np.array_equal(a, b))
    except (TypeError, ValueError):
        return bool(x == y)


def _same_dict(a: dict[str, Any], b: dict[str, Any]) -> bool:
    return set(a) == set(b) and all(_same(a[k], b[k]) for k in a)


def _differences(a: Any, b: Any, timing: bool = False) -> list[str]:
    """Names of the fields in which two runs' data differ (timing keys of the summary too
    when ``timing``)."""
    differ = [name for name in ARRAY_FIELDS if not _same(getattr(a, name), getattr(b, name))]
    differ += [name for name in DICT_FIELDS if not _same_dict(getattr(a, name), getattr(b, name))]
    if set(a.observers) != set(b.observers):
        differ.append("observers")
    else:
        differ += [f"observers[{k!r}]" for k in a.observers
                   if not _same_dict(a.observers[k], b.observers[k])]  # fmt: skip
    if a.observer_units != b.observer_units:
        differ.append("observer_units")
    snaps = [sorted(x.snapshots, key=lambda s: s.time) for x in (a, b)]
    if len(snaps[0]) != len(snaps[1]):
        differ.append(f"snapshots ({len(snaps[0])} against {len(snaps[1])})")
    for i, (s, t) in enumerate(zip(*snaps, strict=False)):
        same = _same(
            [s.time, s.saturation, s.invading_pressure], [t.time, t.saturation, t.invading_pressure]
        )
        if not (same and _same(s.pressure, t.pressure) and _same(s.drained, t.drained)):
            differ.append(f"snapshots[{i}]")
        elif not _same_dict(s.mechanics, t.mechanics):
            differ.append(f"snapshots[{i}].mechanics")
    keys = set(a.summary) | set(b.summary)
    compared = [k for k in sorted(keys) if timing or not _timing(k)]
    differ += [f"summary[{k!r}]" for k in compared if not _same(a.summary.get(k), b.summary.get(k))]
    for name in ("scene", "grid_shape", "pore_size"):
        if json.dumps(getattr(a, name), sort_keys=True, default=str) != json.dumps(
            getattr(b, name), sort_keys=True, default=str
        ):
            differ.append(name)
    return differ


def _arrays(data: Any) -> Iterator[tuple[str, np.ndarray]]:
    """``(name, array)`` of every array of a run's data."""
    for name in ARRAY_FIELDS:
        if getattr(data, name) is not None:
            yield name, np.asarray(getattr(data, name))
    for name in DICT_FIELDS:
        for key, values in getattr(data, name).items():
            yield f"{name}[{key!r}]", np.asarray(values)
    for group, records in data.observers.items():
        for key, values in records.items():
            yield f"observers[{group!r}][{key!r}]", np.asarray(values)
    for i, snap in enumerate(data.snapshots):
        yield f"snapshots[{i}].pressure", np.asarray(snap.pressure)
        for key, values in snap.mechanics.items():
            yield f"snapshots[{i}].mechanics[{key!r}]", np.asarray(values)


def _reachable(lattice: Any, inlets: np.ndarray, drained: np.ndarray) -> np.ndarray:
    """(n_pores,) bool: pores joined to ``inlets`` through drained pores (inlets included)."""
    indptr, neighbours, _ = lattice.adjacency
    seen = np.zeros(lattice.n_pores, dtype=bool)
    stack = [int(p) for p in inlets if drained[p]]
    seen[stack] = True
    while stack:
        p = stack.pop()
        for q in neighbours[indptr[p] : indptr[p + 1]]:
            if drained[q] and not seen[q]:
                seen[q] = True
                stack.append(int(q))
    return seen


def _plugin_module(entry: Any) -> str | None:
    """The module that registered a kind, where it can be found: a built-in's plugin module,
    an installed plugin's entry point, or a ``plugin`` module beside the config's."""
    from importlib.metadata import entry_points

    from porenet.hooks import DEFAULT_PLUGINS, ENTRY_POINT_GROUP

    if entry.package == BUILTIN_PACKAGE and entry.plugin in DEFAULT_PLUGINS:
        return DEFAULT_PLUGINS[entry.plugin]
    for point in entry_points(group=ENTRY_POINT_GROUP, name=entry.plugin):
        return str(point.module)
    guess = entry.config.__module__.rpartition(".")[0] + ".plugin"
    try:
        return guess if importlib.util.find_spec(guess) is not None else None
    except (ImportError, ValueError):
        return None
