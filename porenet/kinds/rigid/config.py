"""The rigid medium: apertures never change and no mechanics object is ever built."""

from __future__ import annotations

from typing import Any, ClassVar, Literal

from porenet.config.base import ModelConfig


class RigidConfig(ModelConfig):
    """Rigid solid skeleton (docs/model.md section 5, first bullet)."""

    kind: Literal["rigid"] = "rigid"
    builds_nothing: ClassVar[bool] = True

    def effects(self) -> dict[str, bool]:
        return {"deformation": False, "contact_loss": False}

    @classmethod
    def example_scene(cls) -> dict[str, Any]:
        """A small scene in a rigid medium (the contract suite runs it)."""
        from porenet.kinds.scenes import INVASION, tiny_scene

        return tiny_scene(INVASION, solid={"kind": "rigid"})
