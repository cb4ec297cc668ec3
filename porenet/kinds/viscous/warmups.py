"""The scenes ``porenet compile`` runs to compile the viscous model's kernels, and the kernel
variants (:func:`porenet.jit.jit.variant`) a scene of this fluid calls on lattices of any size.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any

from porenet.core.kinds import WarmUp
from porenet.kinds.scenes import VISCOUS, tiny_scene


@contextmanager
def forced(switches: dict[str, bool] | None, macro_steps: bool = False) -> Iterator[None]:
    """Runs inside take the kernel variant of ``switches`` (the capability switches of
    :func:`porenet.jit.jit.variant`) whatever the lattice's size, and, with ``macro_steps``,
    macro steps of local time steps even where their cost model prefers single-rate steps (a
    tiny lattice), so that their kernels compile too."""
    from porenet.kinds.viscous.local_steps import LocalSteps
    from porenet.kinds.viscous.model import ViscousDrainage

    gain, before = LocalSteps.gain, ViscousDrainage.switches
    try:
        if macro_steps:
            LocalSteps.gain = math.inf
        ViscousDrainage.switches = switches
        yield
    finally:
        LocalSteps.gain, ViscousDrainage.switches = gain, before


def variants(scene: dict[str, Any], macro_steps: bool = False) -> tuple[Any, ...]:
    """One :func:`forced` per kernel variant that runs like ``scene`` call on lattices of any
    size: with and without threads on the square grid, and for the RKC integrator also with
    threads and the windows of local time steps (which ``local_steps = "auto"`` takes on
    40 000 pores or more; a smaller lattice with ``local_steps = "on"`` compiles its variant
    on its first run); lists, without threads or windows, on other lattices."""
    if scene["lattice"].get("kind", "square") != "square":
        switches = [{"THREADS": False, "LISTS": True, "WINDOWS": False}]
    else:
        switches = [{"THREADS": t, "LISTS": False, "WINDOWS": False} for t in (False, True)]
        if scene["fluid"].get("integrator") == "rkc":
            switches.append({"THREADS": True, "LISTS": False, "WINDOWS": True})
    return tuple(functools.partial(forced, s, macro_steps) for s in switches)


def warm_up(name: str, scene: dict[str, Any], macro_steps: bool = False) -> WarmUp:
    """A warm-up of a viscous scene, run once per kernel variant (:func:`variants`)."""
    return WarmUp(name, scene, variants(scene, macro_steps))


WARM_UPS: tuple[WarmUp, ...] = (
    warm_up("viscous model, explicit integrator", tiny_scene(VISCOUS | {"integrator": "explicit"})),
    warm_up("viscous model, rkc integrator", tiny_scene(VISCOUS | {"integrator": "rkc"})),
    warm_up(
        "viscous model, rkc integrator with local time steps",
        tiny_scene(
            VISCOUS | {"capillary_number": 1e-5, "integrator": "rkc", "local_steps": "on"},
            n=32,
            stop={"max_drained": 40},
        ),
        macro_steps=True,
    ),
    warm_up("viscous model, implicit integrator", tiny_scene(VISCOUS | {"integrator": "implicit"})),
)
