"""What the core asks of a kind (docs/architecture.md, "What a kind answers").

The core names no kind. What differs between kinds it asks of the kind, in two ways:

* through its **registration** (``porenet/kinds/<kind>/plugin.py``, or a plugin's), for what
  lives in modules of its own and is imported only when used: the implementation, the cost
  estimate and the compile warm-ups, each an object or a lazy ``"module:name"``::

      register(ViscousConfig, "porenet.kinds.viscous.model:ViscousDrainage",
               cost="porenet.kinds.viscous.cost:estimate",
               warm_ups="porenet.kinds.viscous.warmups:WARM_UPS")

* through optional methods of its **config**, the light object a scene validates (importing
  it imports no numerics), for what follows from the settings. Each has a default in the
  functions below, so a plugin implements only what applies to it.

=========  ======================================  ================================================
role       what                                    used by; default when absent
=========  ======================================  ================================================
every      ``warm_ups=`` (registration)            ``porenet compile`` runs these :class:`WarmUp`
                                                   scenes; none
every      config ``example_scene()`` (classmeth)  the contract suite (:mod:`porenet.testing.
                                                   contract`); none: the kind is uncovered
lattice    config ``extent()``                     the plan's numbers, every cost estimate; None:
                                                   no size, cost unknown
fluid,     config ``effects()``                    the plan's effects and the cost request's
solid                                              ``fractures``; none
fluid      ``cost=`` (registration):               the plan's cost (:mod:`porenet.core.cost`);
           ``estimate(config, request)``           none: "provides no cost estimate"
fluid      config ``implied_observers()``          observers its shorthand fields ask for; none
fluid      config ``predict_regime(numbers)``      the plan's predicted regime; the paper's phase
                                                   diagram (docs/model.md section 6)
solid      ``cost=`` (registration):               the plan's cost; none, as above
           ``estimate(config, request, fluid)``
solid      config ``builds_nothing`` (class attr)  no solid and no coupler are built (rigid)
solid      config ``coupler`` (field)              the coupler kind the solid is exchanged by
coupler    config ``feeds_back`` (class attr)      False: the coupler never changes the fluid's
                                                   apertures (one-way coupling); the plan's
                                                   ``aperture_feedback``; default True
=========  ======================================  ================================================

The models answer the rest through the interfaces of :mod:`porenet.core.interfaces` (what a
fluid, solid or observer writes into the run data, which analysis applies: the plan's record
``plan_deformable``).
"""

from __future__ import annotations

from collections.abc import Callable
from contextlib import AbstractContextManager
from dataclasses import dataclass
from typing import Any


@dataclass(frozen=True)
class WarmUp:
    """A tiny scene whose run calls a group of a kind's kernels (``porenet compile``).

    Attributes
    ----------
    name : str
        What it compiles, for the command's report ("viscous model, rkc integrator").
    scene : dict
        The scene, as a dict (small: a warm-up is about compiling, not simulating).
    variants : tuple of callables
        Context manager factories: the scene runs once inside each (none: once as it is).
        Each makes the run take code that a tiny scene would not (a kernel variant of large
        lattices, local time steps). Module-level functions, or ``functools.partial`` of
        one, so that a warm-up pickles for ``porenet compile --jobs``.
    """

    name: str
    scene: dict[str, Any]
    variants: tuple[Callable[[], AbstractContextManager[Any]], ...] = ()


def effects(config: Any) -> dict[str, bool]:
    """The physics a fluid or solid config switches on (``capillarity``,
    ``viscous_dissipation``, ``trapping``, ``deformation``, ``contact_loss``); none for a
    config without ``effects()``."""
    method = getattr(config, "effects", None)
    return dict(method()) if callable(method) else {}


def builds_nothing(config: Any) -> bool:
    """True for a kind whose config says a run builds no object for it (the rigid solid, no
    classifier)."""
    return bool(getattr(config, "builds_nothing", False))


def feeds_back(config: Any) -> bool:
    """Whether a coupler kind changes the apertures the fluid sees (default True); False is
    one-way coupling: the solid responds to the fluid's pressures, the fluid sees the rigid
    medium, and fluid models may precompute from the initial apertures."""
    return bool(getattr(config, "feeds_back", True))


def example_scene(config_class: type) -> dict[str, Any] | None:
    """A small scene that uses the kind (for the contract suite), or None."""
    method = getattr(config_class, "example_scene", None)
    return method() if callable(method) else None


def implied_observers(config: Any) -> list[Any]:
    """Observer configs that a fluid config's shorthand fields ask for (none by default)."""
    method = getattr(config, "implied_observers", None)
    return list(method()) if callable(method) else []
