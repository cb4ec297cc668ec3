"""Triggers decide when an observer runs (after HOOMD-blue's triggers).

The simulation asks every trigger how many drainage events may pass before it must fire
(:meth:`Trigger.events_until_due`) and at which model time it must fire
(:meth:`Trigger.next_time`), and never lets the fluid model advance further than either in one
call, so an observer sees exactly the states it asked for and nothing is computed for an
observer that never fires.
"""

from __future__ import annotations

import time
from abc import ABC, abstractmethod

from porenet.core.state import State


class Trigger(ABC):
    """Decides, after each advance of the fluid model, whether an observer runs."""

    @abstractmethod
    def fires(self, state: State) -> bool:
        """True if the observer should see ``state`` now."""

    def events_until_due(self, state: State) -> int | None:
        """Largest number of drainage events that may pass before the next firing, or None."""
        return None

    def next_time(self, state: State) -> float | None:
        """The model time (scaled) of the next firing, or None: the fluid model's call then
        ends there (:attr:`porenet.core.interfaces.FluidModel.stop_time`)."""
        return None

    def reset(self) -> None:  # noqa: B027 - optional hook
        """Called once when the run starts."""


class Never(Trigger):
    """Fires only at the end of the run (observers are always closed at the end)."""

    def fires(self, state: State) -> bool:
        return False


class Schedule(Trigger):
    """Fires when the drained pores reach each of ``counts`` and when the model time reaches
    each of ``times`` (scaled; within 1e-12 relative: the fluid model's call ends at that
    time exactly), in order."""

    def __init__(self, counts: list[int] | tuple[int, ...] = (),
                 times: list[float] | tuple[float, ...] = ()) -> None:  # fmt: skip
        self.counts = sorted(int(c) for c in counts)
        self.times = sorted(float(t) for t in times)
        self.reset()

    def reset(self) -> None:
        self._counts = list(self.counts)
        self._times = list(self.times)

    def fires(self, state: State) -> bool:
        due = False
        while self._counts and state.n_drained >= self._counts[0]:
            self._counts.pop(0)
            due = True
        while self._times and state.time >= self._times[0] * (1 - 1e-12):
            self._times.pop(0)
            due = True
        return due

    def events_until_due(self, state: State) -> int | None:
        if not self._counts:
            return None
        return max(self._counts[0] - state.n_drained, 0)

    def next_time(self, state: State) -> float | None:
        return self._times[0] if self._times else None


class EverySeconds(Trigger):
    """Fires when at least ``seconds`` of wall time passed since the last firing.

    ``chunk`` bounds the number of events between checks of the clock.
    """

    def __init__(self, seconds: float, chunk: int = 2000) -> None:
        self.seconds = seconds
        self.chunk = chunk
        self._last = time.perf_counter()

    def reset(self) -> None:
        self._last = time.perf_counter()

    def fires(self, state: State) -> bool:
        now = time.perf_counter()
        if now - self._last >= self.seconds:
            self._last = now
            return True
        return False

    def events_until_due(self, state: State) -> int | None:
        return self.chunk
