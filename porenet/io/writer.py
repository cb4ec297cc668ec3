"""Writes the run file at the end of a run (an observer like any other)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from porenet.core.interfaces import Observer
from porenet.core.state import State


class RunFileWriter(Observer):
    """Writes ``result.data`` to ``path`` atomically when the run closes."""

    def __init__(self, path: str | Path) -> None:
        super().__init__(None)
        self.path = Path(path)

    def close(self, state: State, result: Any) -> None:
        from porenet.io.runfile import write_run

        result.path = write_run(self.path, result.data)
