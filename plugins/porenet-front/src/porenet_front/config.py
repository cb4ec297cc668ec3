"""Config of the ``front.interface`` observer: pydantic and porenet's light config base only.

porenet imports this module whenever it builds the scene schema (``porenet validate``, ``plan``,
``schema``, ``plugins``), so it imports no numerics; the observer,
:mod:`porenet_front.observer`, is imported only when a scene asks for it.
"""

from __future__ import annotations

from typing import Any, Literal

from pydantic import Field

from porenet.config.base import ModelConfig

#: The kind a scene asks for: ``[[observers]] kind = "front.interface"``.
KIND = "front.interface"


class FrontConfig(ModelConfig):
    """Record the invasion front (its menisci, mean position and width) as the run goes on.

    A record each time the drained pores reach a multiple of ``ceil(every x n_pores)``, and
    one of the final state; stored in the run file under ``/observers/front.interface``.
    """

    kind: Literal["front.interface"] = "front.interface"
    every: float = Field(
        0.01,
        gt=0,
        le=1,
        allow_inf_nan=False,
        description="Drained fraction of the pores between two records (-): a record each "
        "time the drained pores (inlets included) reach a multiple of ceil(every x n_pores), "
        "and one of the final state.",
    )

    @classmethod
    def example_scene(cls) -> dict[str, Any]:
        """A small scene recording the front, for porenet's contract suite (docs/contract.md)."""
        observers = [{"kind": KIND, "every": 0.05}]
        return {"lattice": {"n": 12, "disorder": 0.3}, "fluid": {}, "observers": observers}
