"""Ctrl-C while the ``porenet`` command runs: the exit status 130 and the message
"interrupted", whatever the command was doing when it came (docs/reliability.md, "Exit
status"), also early in a first run, while numba imports and compiles: an interrupt that
ctypes dropped in an LLVM callback is raised again (:class:`CtrlC`), one that numpy cleared is
reported when the command ends (:func:`porenet.cli.main.main`), and CPython's note of an interrupt
that escaped a string ``exec`` is cleared (:func:`forget_escaped_interrupts`).

Light: the standard library only.
"""

from __future__ import annotations

import sys
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from typing import Any


@contextmanager
def interrupts() -> Iterator[Callable[[], bool]]:
    """Notes whether Ctrl-C (SIGINT) arrived, and raises KeyboardInterrupt as Python does.

    A KeyboardInterrupt raised while numba compiles can land in a callback that LLVM calls
    (through ctypes, which drops exceptions raised in callbacks and reports them to
    ``sys.unraisablehook``): the compilation then either fails later with an unrelated error
    (numba's "no compiled object yet") or succeeds, and the run went on to its end as if
    Ctrl-C had not been pressed. So the interrupt is raised again at the first Python call
    or return outside the callback (:class:`CtrlC`); :func:`porenet.cli.main.main` reports any
    error after Ctrl-C as the interruption (exit 130), not as an internal error."""
    import signal
    import threading

    # signals reach only the main thread; an ignored SIGINT (a job started with & by a
    # script) stays ignored
    if (
        threading.current_thread() is not threading.main_thread()
        or signal.getsignal(signal.SIGINT) is signal.SIG_IGN
    ):
        try:
            yield lambda: False
        finally:
            forget_escaped_interrupts()  # a KeyboardInterrupt raised by the code itself
        return
    ctrl_c = CtrlC()
    previous = signal.signal(signal.SIGINT, ctrl_c.handler)
    sys.unraisablehook = ctrl_c.unraisable
    try:
        yield lambda: ctrl_c.received
    finally:
        ctrl_c.active = False
        sys.unraisablehook = ctrl_c.previous_hook
        signal.signal(signal.SIGINT, previous)
        forget_escaped_interrupts()


class CtrlC:
    """Ctrl-C while ``main`` runs a command: the SIGINT handler, and the raising again of an
    interrupt that a ctypes callback dropped (:func:`interrupts`)."""

    def __init__(self) -> None:
        self.received = False  # a SIGINT arrived
        self.active = True  # the command runs: a dropped interrupt is raised again
        self.previous_hook = sys.unraisablehook  # every other unraisable exception goes there
        self._previous_profile: Any = None

    def handler(self, signum: int, frame: Any) -> None:
        self.received = True
        raise KeyboardInterrupt

    def unraisable(self, report: Any) -> None:
        """A KeyboardInterrupt that ctypes dropped: raise it again at the next Python call or
        return (:meth:`_raise_again`), without the "Exception ignored" traceback."""
        if (
            self.active
            and report.exc_type is not None
            and issubclass(report.exc_type, KeyboardInterrupt)
        ):
            self._previous_profile = sys.getprofile()
            sys.setprofile(self._raise_again)
            return
        self.previous_hook(report)

    def _raise_again(self, frame: Any, event: str, arg: Any) -> None:
        if frame.f_code is CtrlC.unraisable.__code__:  # still in the hook, inside ctypes
            return
        sys.setprofile(self._previous_profile)
        if self.active:
            raise KeyboardInterrupt


def forget_escaped_interrupts() -> None:
    """Let the status ``main`` returns be the process's exit status after a caught Ctrl-C.

    CPython notes a KeyboardInterrupt that escapes any ``exec`` or ``eval`` of a string
    (numba, dataclasses and namedtuple build code that way, so an interrupt during imports or
    a first compilation often passes through one) and, when it ran a module with ``-m``, kills
    the process with SIGINT at exit, whatever status the program chose: ``python -m
    porenet`` printed "interrupted" and still ended as killed by SIGINT (status -2 to a
    parent process) instead of 130, in 5 of 40 interrupts about 1 s into a first run
    (docs/reliability.md, "Exit status"; the ``porenet`` script exits through another path).
    The next string ``exec`` that completes clears the note. An interrupt that ``main`` does
    not catch is noted again by the interpreter as it leaves the program."""
    exec("pass")  # the string form is the point (see above)
