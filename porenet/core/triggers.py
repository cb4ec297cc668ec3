"""Triggers decide when an observer runs (after HOOMD-blue's triggers).

The simulation asks every trigger how many drainage events may pass before it must fire
(:meth:`Trigger.events_until_due`) and never lets the fluid model advance further than that in
one call, so an observer sees exactly the states it asked for and nothing is computed for an
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

    def reset(self) -> None:  # noqa: B027 - optional hook
        """Called once when the run starts."""


class Never(Trigger):
    """Fires only at the end of the run (observers are always closed at the end)."""

    def fires(self, state: State) -> bool:
        return False


class EveryEvents(Trigger):
    """Fires whenever at least ``period`` drainage events happened since the last firing."""

    def __init__(self, period: int) -> None:
        if period < 1:
            raise ValueError("period must be >= 1")
        self.period = period
        self._last = 0

    def reset(self) -> None:
        self._last = 0

    def fires(self, state: State) -> bool:
        if state.n_drained - self._last >= self.period:
            self._last = state.n_drained
            return True
        return False

    def events_until_due(self, state: State) -> int | None:
        return max(1, self.period - (state.n_drained - self._last))


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
