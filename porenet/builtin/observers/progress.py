"""Progress display on a terminal (stderr), quiet elsewhere."""

from __future__ import annotations

import sys
import time
from typing import Any, Literal, TextIO

from pydantic import Field

from porenet.config.base import ModelConfig
from porenet.core.interfaces import Observer
from porenet.core.state import State
from porenet.core.triggers import EverySeconds


class ProgressConfig(ModelConfig):
    """Show drained pores, rate and elapsed time while a run goes on."""

    kind: Literal["progress"] = "progress"
    every_seconds: float = Field(0.5, gt=0, description="Refresh interval (s of wall time).")


class Progress(Observer):
    """Writes a one-line status to a terminal; writes nothing when the stream is not a TTY."""

    def __init__(self, config: ProgressConfig | None = None, stream: TextIO | None = None) -> None:
        super().__init__(config or ProgressConfig())
        self.stream = stream if stream is not None else sys.stderr
        self.trigger = EverySeconds(self.config.every_seconds)
        self._t0 = time.perf_counter()
        self._total = 0
        self._time_scale: float | None = None
        self._active = bool(getattr(self.stream, "isatty", lambda: False)())

    def attach(self, run: Any) -> None:
        self._t0 = time.perf_counter()
        self._total = run.lattice.n_pores
        self._time_scale = run.scales.time

    def observe(self, state: State) -> None:
        if not self._active:
            return
        elapsed = time.perf_counter() - self._t0
        rate = state.n_drained / elapsed if elapsed > 0 else 0.0
        model_time = ""
        if self._time_scale is not None:
            model_time = f"  t = {state.time * self._time_scale:.3e} s, step {state.step}"
        self.stream.write(
            f"\r  drained {state.n_drained:>9d} / {self._total} pores"
            f"  {rate:9.0f} pores/s  {elapsed:7.1f} s{model_time}"
        )
        self.stream.flush()

    def close(self, state: State, result: Any) -> None:
        if self._active:
            self.observe(state)
            self.stream.write("\n")
            self.stream.flush()
