"""Config of the progress display, kind ``progress``.

Pure Python, so that the scene schema imports no observer; the display,
:mod:`porenet.io.progress`, is imported only when a run builds it.
"""

from __future__ import annotations

from typing import Any, Literal

from pydantic import Field

from porenet.config.base import ModelConfig


class ProgressConfig(ModelConfig):
    """Show drained pores, rate and elapsed time while a run goes on."""

    kind: Literal["progress"] = "progress"
    every_seconds: float = Field(0.5, gt=0, description="Refresh interval (s of wall time).")

    @classmethod
    def example_scene(cls) -> dict[str, Any]:
        """A small scene with this observer (the contract suite runs it)."""
        from porenet.kinds.scenes import INVASION, tiny_scene

        return tiny_scene(INVASION, observers=[{"kind": "progress"}])
