"""Numba's compilation of porenet's kernels: announced while it happens, or done ahead of time.

Numba compiles a kernel the first time a process calls it on a machine and caches the machine
code on disk (next to the kernel's source, or under ``NUMBA_CACHE_DIR``); later processes load
it in milliseconds. A first run therefore spends seconds to a minute compiling before it
steps (docs/performance.md, "First run"). So that this is never a silent wait:

* :class:`CompileWatch` (one per process, a numba event listener) counts and times the
  compilations;
* :class:`CompileNotice` wraps each phase of a run (building the lattice, each model's setup
  and steps, the analysis at the end) and writes to stderr, terminal or not, when a phase
  starts compiling (what is compiled, that it happens once per machine, where the cache is)
  and how long it took;
* :func:`porenet.jit.warmup.compile_all` (``porenet compile``) compiles every kernel a scene can
  call by running tiny scenes of every model, for an install on a cluster or in a container
  image (a separate module: it runs simulations, which use this one).
"""

from __future__ import annotations

import logging
import sys
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from typing import Any, TextIO

log = logging.getLogger(__name__)


class CompileWatch:
    """Counts numba's compilations in this process and their wall time (outermost only: a
    kernel compiles the kernels it calls inside its own compilation).

    Attributes
    ----------
    count : int
        Outermost compilations finished so far.
    seconds : float
        Their wall time in all.
    cache_dir : str or None
        Where numba caches the last kernel it compiled.
    on_first : callable or None
        Called with no argument when an outermost compilation starts.
    """

    def __init__(self) -> None:
        self.count = 0
        self.seconds = 0.0
        self.cache_dir: str | None = None
        self.on_first: Callable[[], None] | None = None
        self._depth = 0
        self._t0 = 0.0

    @property
    def compiling(self) -> bool:
        """True while a compilation runs."""
        return self._depth > 0

    def started(self, dispatcher: Any) -> None:
        if self._depth == 0:
            self._t0 = time.perf_counter()
            if self.cache_dir is None:
                self.cache_dir = _cache_dir(dispatcher)
            if self.on_first is not None:
                self.on_first()
        self._depth += 1

    def ended(self) -> None:
        self._depth = max(self._depth - 1, 0)
        if self._depth == 0:
            self.count += 1
            self.seconds += time.perf_counter() - self._t0


def _cache_dir(dispatcher: Any) -> str | None:
    """Numba's cache directory of a dispatcher (None if it has none or numba changed)."""
    cache = getattr(dispatcher, "_cache", None)
    path = getattr(cache, "_cache_path", None)
    return str(path) if path else None


_WATCH: CompileWatch | None = None


def watch() -> CompileWatch:
    """The process's :class:`CompileWatch`, registered with numba on first use."""
    global _WATCH
    if _WATCH is None:
        _WATCH = CompileWatch()
        try:
            from numba.core import event
        except ImportError:  # pragma: no cover - numba is a core dependency
            return _WATCH

        class _Listener(event.Listener):  # type: ignore[misc]
            def on_start(self, ev: Any) -> None:
                _WATCH.started(ev.data.get("dispatcher"))  # type: ignore[union-attr]

            def on_end(self, ev: Any) -> None:
                _WATCH.ended()  # type: ignore[union-attr]

        event.register("numba:compile", _Listener())
    return _WATCH


class CompileNotice:
    """Says on ``stream`` when a phase of a run compiles kernels, and for how long.

    ``with notice.phase("the viscous fluid model (rkc integrator)"): ...`` writes one line
    when the first compilation of the phase starts and one when the phase ends, if it
    compiled; nothing otherwise (a machine whose cache holds the kernels sees nothing).
    ``enabled=False`` writes nothing but still counts (:attr:`compiled_seconds`).
    """

    def __init__(self, stream: TextIO | None = None, enabled: bool = True) -> None:
        self.stream = stream if stream is not None else sys.stderr
        self.enabled = enabled
        self.watch = watch()
        #: Seconds spent compiling in this run's phases.
        self.compiled_seconds = 0.0

    def _write(self, text: str) -> None:
        if not self.enabled:
            log.info("%s", text)
            return
        # on a terminal, first clear a progress line that may be showing
        clear = "\r\x1b[K" if getattr(self.stream, "isatty", lambda: False)() else ""
        self.stream.write(f"{clear}porenet: {text}\n")
        self.stream.flush()

    @contextmanager
    def phase(self, what: str) -> Iterator[None]:
        w = self.watch
        count, seconds = w.count, w.seconds

        announced = False

        def announce() -> None:  # once per phase, however many kernels it compiles
            nonlocal announced
            if announced:
                return
            announced = True
            where = f"; cached in {w.cache_dir}" if w.cache_dir else ""
            self._write(
                f"compiling the kernels of {what} for this machine (once per machine{where}; "
                "`porenet compile` does it ahead of time) ..."
            )

        previous, w.on_first = w.on_first, announce
        try:
            yield
        finally:
            w.on_first = previous
            if w.count > count:
                spent = w.seconds - seconds
                self.compiled_seconds += spent
                self._write(f"compiled the kernels of {what} in {spent:.1f} s")

    def counter(self) -> int:
        """Compilations finished so far in this process (to tell whether a call compiled)."""
        return self.watch.count
