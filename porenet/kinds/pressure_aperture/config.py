"""Config of the built-in coupler, kind ``pressure-aperture``.

Pure Python, so that the scene schema imports no numerics; the coupler,
:mod:`porenet.kinds.pressure_aperture.model`, is imported only when a scene builds it.
"""

from __future__ import annotations

from typing import Any, Literal

from porenet.config.base import ModelConfig


class PressureApertureConfig(ModelConfig):
    """Names the coupler; its schedule is set in the solid's section (``coupling``,
    ``coupling_interval``, ``coupling_tolerance``)."""

    kind: Literal["pressure-aperture"] = "pressure-aperture"

    @classmethod
    def example_scene(cls) -> dict[str, Any]:
        """A small scene of a deformable medium, which this coupler couples (the contract suite runs
        it)."""
        from porenet.kinds.scenes import HERTZ, INVASION, tiny_scene

        return tiny_scene(INVASION, solid=HERTZ)
