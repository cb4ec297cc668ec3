"""Config of the snapshots observer, kind ``snapshots``.

Pure Python, so that the scene schema imports no observer; the observer,
:mod:`porenet.kinds.snapshots.model`, is imported only when a run builds it.
"""

from __future__ import annotations

from typing import Any, Literal

from pydantic import Field, model_validator

from porenet.config.base import ModelConfig


class SnapshotsConfig(ModelConfig):
    """Record the pressure field (and, in a deformable medium, the solid's fields) at given
    saturations and model times: the ``/snapshots`` of the run file (docs/run-file.md)."""

    kind: Literal["snapshots"] = "snapshots"
    saturations: list[float] = Field(
        default_factory=list,
        description="Drained fractions of the pores (0, 1] at which to record (-).",
    )
    times: list[float] = Field(
        default_factory=list,
        description="Model times at which to record (s); the fluid model's steps end there "
        "exactly (models without a time record nothing for them).",
    )

    @model_validator(mode="after")
    def _in_range(self) -> SnapshotsConfig:
        if any(not 0 < s <= 1 for s in self.saturations):
            raise ValueError("'saturations' must lie in (0, 1]")
        if any(not t > 0 for t in self.times):
            raise ValueError("'times' must be positive (s)")
        return self

    @classmethod
    def example_scene(cls) -> dict[str, Any]:
        """A small scene with this observer (the contract suite runs it)."""
        from porenet.kinds.scenes import VISCOUS, tiny_scene

        return tiny_scene(VISCOUS, observers=[{"kind": "snapshots", "saturations": [0.01, 0.02]}])
