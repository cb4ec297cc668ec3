"""What the plan and the cost model know of a lattice before it is built.

A lattice's config describes its size through a method ``extent()`` returning a
:class:`LatticeExtent` (the built-in ``square`` and ``cubic`` configs do; a plugin lattice
whose config has none is planned without a size, and its cost is reported unknown). The
plan (docs/model.md section 6) and the cost model (docs/cost.md) read only this, never a
particular config's fields (docs/lattices.md, "The lattice contract").
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any


@dataclass(frozen=True)
class LatticeExtent:
    """The size of a lattice, from its config.

    Attributes
    ----------
    pores, throats : int
        How many.
    dimension : int
        2 or 3.
    side : int
        Pores along the longest side: the ``L / a`` of Ca* and N_f (docs/model.md section 6).
    outlet_links : dict
        Half throats joining the lattice to the outlet reservoir, per site geometry
        (``"centre"``, ``"face"``, :func:`porenet.core.sites.site_geometry`): the boundary
        cross-section ``A_b / a^2`` of the capillary number (``4 n`` and ``n`` on the
        square lattice).
    canonical_grid : bool
        A square ``n x n`` grid in canonical order (stencil sweeps, local time steps).
    disorder : float or None
        ``lambda`` when the apertures are drawn uniformly with that disorder.
    size_field : str
        The scene field that sets the size, with its value (``"lattice.n = 400"``), for
        messages that ask to reduce it.
    """

    pores: int
    throats: int
    dimension: int
    side: int
    outlet_links: dict[str, int]
    canonical_grid: bool
    disorder: float | None
    size_field: str

    def cross_section(self, geometry: str) -> int:
        """``A_b / a^2`` for a site geometry (a label or pore list drains through the
        boundary, as the centre does)."""
        return self.outlet_links["face" if geometry == "face" else "centre"]


def lattice_extent(config: Any) -> LatticeExtent | None:
    """The extent a lattice config describes, or None if it describes none."""
    extent = getattr(config, "extent", None)
    return extent() if callable(extent) else None
