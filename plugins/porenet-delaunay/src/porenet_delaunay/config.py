"""Config of the ``delaunay.random`` lattice: pydantic and porenet's light modules only.

porenet imports this module whenever it builds the scene schema (``porenet validate``,
``plan``, ``schema``, ``plugins``), so it imports no numerics; the lattice,
:mod:`porenet_delaunay.model`, and scipy with it, are imported only when a scene selects
the kind.
"""

from __future__ import annotations

import math
from typing import Any, Literal

from pydantic import Field

from porenet.config.base import ModelConfig
from porenet.config.lattice_fields import PoreSize
from porenet.core.extent import LatticeExtent

#: The kind a scene selects: ``[lattice] kind = "delaunay.random"``.
KIND = "delaunay.random"
#: Most pores (40 000 take about 3 s to draw and tessellate, a million over a minute).
MAX_PORES = 1_000_000
#: The sites of a 2-D network: the centre and the four sides of its square.
SITES = ("centre", "x-", "x+", "y-", "y+", "left-edge")
#: Pores on one side of the square, per ``sqrt(N)``: 0.94-0.95 measured over 5 seeds at
#: N = 150, 400 and 4 000 and 2 at 40 000 with ``min_distance = 1``. The boundary holds the
#: four sides' pores less the four corners', within 2 % (the exact counts are known once the
#: points are drawn; the plan's numbers are estimates).
FACE_PORES = 0.95


class DelaunayLatticeConfig(ModelConfig):
    """A 2-D random pore network: ``n_pores`` pores at random points of a square, joined by
    throats along the edges of their Delaunay triangulation; not a grid underneath.

    Apertures are uniform in ``[(1-lambda) a, (1+lambda) a]`` (``disorder`` lambda), as on the
    square lattice; throat lengths are the distances between the pores' centres; pore volumes
    are proportional to the pores' Voronoi cells.
    """

    kind: Literal["delaunay.random"] = "delaunay.random"
    n_pores: int = Field(
        ...,
        ge=16,
        le=MAX_PORES,
        description="Number of pores N (-). They are drawn in a square of side L = 2 sqrt(N) a, "
        "one pore per 4 a^2 as on the square lattice (node spacing 2a).",
    )
    disorder: float = Field(
        ...,
        gt=0,
        lt=1,
        allow_inf_nan=False,
        description="Disorder lambda (-): apertures uniform in [(1-lambda) a, (1+lambda) a].",
    )
    pore_size: PoreSize = 1e-7
    min_distance: float = Field(
        1.0,
        ge=0,
        le=1.2,
        allow_inf_nan=False,
        description="Smallest distance between two pore centres, in units of the pore size a "
        "(-): a point closer than this to one drawn before it is drawn again. 0 gives "
        "independent uniform points, whose closest pairs are joined by very short throats.",
    )

    def side(self) -> float:
        """The side ``L / a`` of the square the pores are drawn in: ``2 sqrt(N)``."""
        return 2.0 * math.sqrt(self.n_pores)

    def site_names(self) -> tuple[str, ...]:
        """The named injection sites of this lattice (docs/lattices.md)."""
        return SITES

    def extent(self) -> LatticeExtent:
        """The size the plan and the cost model read (:mod:`porenet.core.extent`): the pores
        exactly; the throats ``3N - 3 - b`` of a triangulation whose outer boundary has ``b``
        pores, and the outlet's pores, from the measured ``b`` and face counts (estimates)."""
        n = self.n_pores
        root = math.sqrt(n)
        boundary = round(4 * FACE_PORES * root) - 4
        return LatticeExtent(
            pores=n, throats=3 * n - 3 - boundary, dimension=2, side=round(root),
            outlet_links={"centre": boundary, "face": round(FACE_PORES * root)},
            canonical_grid=False, disorder=self.disorder, size_field=f"lattice.n_pores = {n}",
        )  # fmt: skip

    @classmethod
    def example_scene(cls) -> dict[str, Any]:
        """A small scene on this lattice, for porenet's contract suite (docs/contract.md)."""
        return {
            "seed": 1,
            "lattice": {"kind": KIND, "n_pores": 200, "disorder": 0.3, "pore_size": 1e-4},
            "fluid": {"kind": "invasion-percolation"},
            "classifier": {"kind": "none"},  # ~30 pores at breakthrough: too few to classify
        }
