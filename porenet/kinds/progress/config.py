"""Config of the progress display, kind ``progress``.

Pure Python, so that the scene schema imports no observer; the display,
:mod:`porenet.io.progress`, is imported only when a run builds it.
"""

from __future__ import annotations

from typing import Literal

from pydantic import Field

from porenet.config.base import ModelConfig


class ProgressConfig(ModelConfig):
    """Show drained pores, rate and elapsed time while a run goes on."""

    kind: Literal["progress"] = "progress"
    every_seconds: float = Field(0.5, gt=0, description="Refresh interval (s of wall time).")
