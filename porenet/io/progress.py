"""Progress on stderr: a status line on a terminal, a line now and then elsewhere.

On a terminal, one status line rewritten in place (every ``every_seconds``); in a Jupyter
notebook (stderr is ipykernel's stream) the same line, rewritten with a carriage return and
no terminal escape codes, which the notebook shows as one line updated in place; elsewhere (a
batch job, ``nohup``) a line every :data:`LOG_SECONDS` of wall time or each time
another :data:`LOG_FRACTION` of the expected drained pores is reached (up to the expected
count), whichever comes first. Either shows drained pores, drainage rate, elapsed wall time, model
time and step (time-dependent models), and an ETA. The number of pores a run will drain is
not known in advance: the ETA divides the pores still expected by the rate so far, with the
expected count from the plan's cost estimate (:mod:`porenet.core.cost`: ``stop.max_drained``
when given, otherwise the model of docs/cost.md). It is labelled an estimate, shown only once
the run has gone on for a few seconds and drained a few percent of what is expected, and
dropped once the run passes the expected count.
"""

from __future__ import annotations

import sys
import time
from typing import Any, TextIO

from porenet.config.base import ModelConfig
from porenet.core.interfaces import Observer, RunView
from porenet.core.state import State
from porenet.core.triggers import EverySeconds

#: Refresh interval (s of wall time) without a config that sets one.
EVERY_SECONDS = 0.5
#: The ETA is shown only after this much wall time (s) ...
ETA_MIN_ELAPSED = 2.0
#: ... and this fraction of the expected drained pores.
ETA_MIN_FRACTION = 0.02
#: Not on a terminal: a line at least this often (s of wall time) ...
LOG_SECONDS = 30.0
#: ... and each time this fraction of the expected drained pores is passed.
LOG_FRACTION = 0.1


def format_duration(seconds: float) -> str:
    """``42 s``, ``3.5 min``, ``2.1 h``."""
    if seconds < 90:
        return f"{seconds:.0f} s"
    if seconds < 5400:
        return f"{seconds / 60:.1f} min"
    return f"{seconds / 3600:.1f} h"


def eta_text(drained: int, expected: int | None, elapsed: float) -> str:
    """``"ETA ~ 2.5 min (est.)"``, or ``""`` when an ETA would mean nothing (no expected
    count, too early, or past the expected count)."""
    if expected is None or expected <= 0 or drained <= 0:
        return ""
    if elapsed < ETA_MIN_ELAPSED or drained < ETA_MIN_FRACTION * expected:
        return ""
    remaining = expected - drained
    if remaining <= 0:
        return ""
    return f"ETA ~ {format_duration(remaining * elapsed / drained)} (est.)"


class Progress(Observer):
    """Writes a one-line status to a terminal, rewritten in place; on any other stream a
    line every :data:`LOG_SECONDS` or :data:`LOG_FRACTION` of the expected drained pores.

    Parameters
    ----------
    config : ModelConfig, optional
        The scene's ``progress`` observer section, if it has one: its ``every_seconds`` is
        the refresh interval (default :data:`EVERY_SECONDS`).
    stream : text stream, optional
        Where to write (default ``sys.stderr``).
    expected_drained : int, optional
        Pores the run is expected to drain, for the ETA. Default: the plan's cost estimate
        (``run.expected_drained``), read at :meth:`attach`.
    """

    def __init__(
        self,
        config: ModelConfig | None = None,
        stream: TextIO | None = None,
        expected_drained: int | None = None,
    ) -> None:
        super().__init__(config)
        self.stream = stream if stream is not None else sys.stderr
        self.trigger = EverySeconds(float(getattr(config, "every_seconds", EVERY_SECONDS)))
        self._t0 = time.perf_counter()
        self._total = 0
        self._expected = expected_drained
        self._time_scale: float | None = None
        #: A terminal or a notebook: the status line is rewritten in place; otherwise lines
        #: are logged.
        self.terminal, self.notebook = _in_place(self.stream)
        self._logged_at = 0.0  # elapsed wall time of the last logged line
        self._logged_fraction = 0  # tenths of the expected pores already logged
        self._wrote = False
        self._width = 0  # length of the last status line written in place

    def __getstate__(self) -> dict[str, Any]:
        """A checkpoint keeps no stream: a resumed run shows progress as it is asked to."""
        out = dict(self.__dict__)
        out["stream"] = None
        return out

    def resumed(self, run: RunView) -> None:
        if self.stream is None:
            self.stream = sys.stderr
            self.terminal, self.notebook = _in_place(self.stream)

    @property
    def expected_drained(self) -> int | None:
        """The drained pores the ETA counts on (None: no ETA)."""
        return self._expected

    def attach(self, run: RunView) -> None:
        self._t0 = time.perf_counter()
        self._total = run.lattice.n_pores
        self._time_scale = run.scales.time
        if self._expected is None:
            self._expected = run.expected_drained
        if self._expected is not None:
            self._expected = min(int(self._expected), self._total)

    def status(self, state: State, elapsed: float) -> str:
        """The status line (without the carriage return)."""
        rate = state.n_drained / elapsed if elapsed > 0 else 0.0
        parts = [
            f"drained {state.n_drained:>9d} / {self._total} pores",
            f"{rate:9.0f} pores/s",
            f"{format_duration(elapsed):>7}",
        ]
        if self._time_scale is not None:
            parts.append(f"t = {state.time * self._time_scale:.3e} s, step {state.step}")
        eta = eta_text(state.n_drained, self._expected, elapsed)
        if eta:
            parts.append(eta)
        return "  ".join(parts)

    def observe(self, state: State) -> None:
        elapsed = time.perf_counter() - self._t0
        if self.terminal:
            line = f"  {self.status(state, elapsed)}"
            # what a longer previous line left behind: "\x1b[K" clears it on a terminal;
            # a notebook shows escape codes as text, so spaces cover it there
            tail = " " * max(self._width - len(line), 0) if self.notebook else "\x1b[K"
            self.stream.write(f"\r{line}{tail}")
            self.stream.flush()
            self._width = len(line)
            self._wrote = True
            return
        passed = 0
        if self._expected and state.n_drained <= self._expected:  # past it: the clock only
            passed = int(state.n_drained / (LOG_FRACTION * self._expected))
        if elapsed - self._logged_at >= LOG_SECONDS or passed > self._logged_fraction:
            self._logged_at = elapsed
            self._logged_fraction = max(passed, self._logged_fraction)
            self.stream.write(f"porenet: {self.status(state, elapsed)}\n")
            self.stream.flush()

    def close(self, state: State, result: Any) -> None:
        if self.terminal and self._wrote:
            self.observe(state)
            self.stream.write("\n")
            self.stream.flush()


def _in_place(stream: Any) -> tuple[bool, bool]:
    """(rewrite the status line in place, the stream is a Jupyter notebook's): a terminal, or
    ipykernel's output stream (whose ``isatty`` is False, but whose carriage returns the
    notebook honours)."""
    notebook = type(stream).__module__.split(".")[0] == "ipykernel"
    terminal = bool(getattr(stream, "isatty", lambda: False)())
    return terminal or notebook, notebook
