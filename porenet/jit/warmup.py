"""Compiling every kernel ahead of time (``porenet compile``), by running tiny scenes.

For an install on a cluster or in a container image: afterwards no run on the machine compiles
(``tests/verification/test_compile_all.py``). Apart from :mod:`porenet.jit.compilation` because it
runs simulations, and the simulation uses that module's compile notices.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from porenet.jit.compilation import watch


@dataclass(frozen=True)
class WarmUp:
    """A tiny scene whose run calls a group of kernels (for :func:`compile_all`)."""

    name: str
    scene: dict[str, Any]
    #: Take macro steps of local time steps even where their cost model prefers single-rate
    #: steps (a tiny lattice), so that their kernels compile too.
    macro_steps: bool = False


def _scene(fluid: dict[str, Any], n: int = 12, **sections: Any) -> dict[str, Any]:
    scene: dict[str, Any] = {
        "seed": 1,
        "lattice": {"kind": "square", "n": n, "disorder": 0.3, "pore_size": 1e-7},
        "fluid": fluid,
    }
    scene.update(sections)
    return scene


_VISCOUS = {"kind": "viscous", "capillary_number": 1e-3}
_HERTZ = {"kind": "hertz", "fracturing_number": 1.0}
_MINDLIN = {"kind": "hertz-mindlin", "fracturing_number": 10.0, "shear_stiffness_ratio": 0.5}
_CUBIC = {"kind": "cubic", "shape": [6, 6, 6], "disorder": 0.3, "pore_size": 1e-7}

#: Scenes that together call every kernel of the built-in kinds.
WARM_UPS: tuple[WarmUp, ...] = (
    WarmUp("invasion percolation", _scene({"kind": "invasion-percolation"})),
    WarmUp(
        "invasion percolation without trapping",
        _scene({"kind": "invasion-percolation", "trapping": False}, stop={"at": "complete"}),
    ),
    WarmUp("viscous model, explicit integrator", _scene(_VISCOUS | {"integrator": "explicit"})),
    WarmUp("viscous model, rkc integrator", _scene(_VISCOUS | {"integrator": "rkc"})),
    WarmUp(
        "viscous model, rkc integrator with local time steps",
        _scene(
            _VISCOUS | {"capillary_number": 1e-5, "integrator": "rkc", "local_steps": "on"},
            n=32,
            stop={"max_drained": 40},
        ),
        macro_steps=True,
    ),
    WarmUp("viscous model, implicit integrator", _scene(_VISCOUS | {"integrator": "implicit"})),
    WarmUp(
        "viscous model on a 3-D lattice, explicit integrator",
        _scene(_VISCOUS | {"integrator": "explicit"}) | {"lattice": _CUBIC},
    ),
    WarmUp(
        "viscous model on a 3-D lattice, rkc integrator",
        _scene(_VISCOUS | {"integrator": "rkc"}) | {"lattice": _CUBIC},
    ),
    WarmUp(
        "invasion percolation in a Hertz solid",
        _scene({"kind": "invasion-percolation"}, solid=_HERTZ),
    ),
    WarmUp("viscous model in a Hertz solid", _scene(_VISCOUS, solid=_HERTZ)),
    WarmUp(
        "Hertz solid, sparse direct solver",
        _scene({"kind": "invasion-percolation"}, solid=_HERTZ | {"solver": "sparse-direct"}),
    ),
    WarmUp(
        "viscous model in a frictional solid (multigrid)",
        _scene(_VISCOUS, n=40, solid=_MINDLIN, stop={"max_drained": 40}),
    ),
    WarmUp(
        "frictional solid with sliding",
        _scene(
            {"kind": "invasion-percolation"},
            n=40,
            solid=_MINDLIN | {"friction": 0.3},
            stop={"max_drained": 40},
        ),
    ),
    WarmUp(
        "frictional solid with free rotations (sparse direct)",
        _scene({"kind": "invasion-percolation"}, solid=_MINDLIN | {"rotation": "free"}),
    ),
)


def _switches(warm: WarmUp) -> list[dict[str, bool] | None]:
    """The capability switches (:func:`porenet.jit.jit.variant`) of the kernel variants
    that runs like ``warm`` call on lattices of any size: with and without threads on the
    square grid, and for the RKC integrator also with threads and the windows of local time
    steps (which ``local_steps = "auto"`` takes on 40 000 pores or more; a smaller lattice
    with ``local_steps = "on"`` compiles its variant on its first run); lists, without
    threads or windows, on other lattices. None: as the scene's own run (a fluid other than
    the viscous model)."""
    fluid = warm.scene["fluid"]
    if fluid["kind"] != "viscous":
        return [None]
    if warm.scene["lattice"].get("kind", "square") != "square":
        return [{"THREADS": False, "LISTS": True, "WINDOWS": False}]
    out = [{"THREADS": threads, "LISTS": False, "WINDOWS": False} for threads in (False, True)]
    if fluid.get("integrator") == "rkc":  # local time steps: lattices of 40 000 pores or more
        out.append({"THREADS": True, "LISTS": False, "WINDOWS": True})
    return out


def warm_up(warm: WarmUp) -> float:
    """Run one warm-up scene; return the seconds this process spent compiling for it.

    A viscous scene runs once per kernel variant that runs of its kind call on lattices of
    any size (:func:`_switches`; :meth:`porenet.kinds.viscous.model.ViscousDrainage.sized`)."""
    from porenet.kinds.viscous.local_steps import LocalSteps
    from porenet.kinds.viscous.model import ViscousDrainage
    from porenet.simulation import Simulation

    w = watch()
    before = w.seconds
    gain, switches = LocalSteps.gain, ViscousDrainage.switches
    try:
        if warm.macro_steps:
            LocalSteps.gain = float("inf")
        for forced in _switches(warm):
            ViscousDrainage.switches = forced
            Simulation.from_scene(warm.scene).run()
    finally:
        LocalSteps.gain, ViscousDrainage.switches = gain, switches
    return w.seconds - before


def compile_all(
    on_done: Callable[[str, float], None] | None = None,
    warm_ups: tuple[WarmUp, ...] = WARM_UPS,
    jobs: int = 1,
) -> float:
    """Compile (or load from the cache) every kernel of the built-in kinds by running
    :data:`WARM_UPS`, in ``jobs`` processes at once (numba writes its cache atomically, so
    processes may share it); calls ``on_done(name, seconds_compiling)`` after each. Returns
    the seconds spent compiling in all (0 when the cache held everything)."""
    total = 0.0
    if jobs <= 1:
        for warm in warm_ups:
            spent = warm_up(warm)
            total += spent
            if on_done is not None:
                on_done(warm.name, spent)
        return total
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor, as_completed

    context = multiprocessing.get_context("spawn")  # numba's threads are not fork-safe
    with ProcessPoolExecutor(max_workers=jobs, mp_context=context) as pool:
        futures = {pool.submit(warm_up, warm): warm.name for warm in warm_ups}
        for future in as_completed(futures):
            spent = future.result()
            total += spent
            if on_done is not None:
                on_done(futures[future], spent)
    return total
