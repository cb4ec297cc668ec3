"""Compiling every kernel ahead of time (``porenet compile``), by running each kind's warm-ups.

Each kind names the tiny scenes that call its kernels (``register(..., warm_ups=...)``,
:class:`porenet.core.kinds.WarmUp`); this runner asks every registered kind, built-in or from
a plugin, and runs them. For an install on a cluster or in a container image: afterwards no
run on the machine compiles (``tests/verification/test_compile_all.py``). Apart from
:mod:`porenet.jit.compilation` because it runs simulations, and the simulation uses that
module's compile notices.
"""

from __future__ import annotations

from collections.abc import Callable
from contextlib import nullcontext

from porenet.core.kinds import WarmUp
from porenet.core.registry import Registry
from porenet.jit.compilation import watch


def kind_warm_ups(registry: Registry | None = None) -> tuple[WarmUp, ...]:
    """Every registered kind's warm-ups, in the registry's order (the process's registry by
    default: built-ins and the installed plugins)."""
    if registry is None:
        from porenet.hooks import get_registry

        registry = get_registry()
    return tuple(warm for entry in registry for warm in entry.load_warm_ups())


def warm_up(warm: WarmUp) -> float:
    """Run one warm-up scene, once inside each of its variants; return the seconds this
    process spent compiling for it."""
    from porenet.simulation import Simulation

    w = watch()
    before = w.seconds
    for variant in warm.variants or (nullcontext,):
        with variant():
            Simulation.from_scene(warm.scene).run()
    return w.seconds - before


def compile_all(
    on_done: Callable[[str, float], None] | None = None,
    warm_ups: tuple[WarmUp, ...] | None = None,
    jobs: int = 1,
) -> float:
    """Compile (or load from the cache) every kernel of the registered kinds by running their
    warm-ups (:func:`kind_warm_ups` unless ``warm_ups`` is given), in ``jobs`` processes at
    once (numba writes its cache atomically, so processes may share it); calls
    ``on_done(name, seconds_compiling)`` after each. Returns the seconds spent compiling in
    all (0 when the cache held everything)."""
    if warm_ups is None:
        warm_ups = kind_warm_ups()
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
