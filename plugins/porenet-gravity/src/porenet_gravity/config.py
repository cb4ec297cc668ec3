"""Config of ``gravity.invasion-percolation``: pydantic and porenet's light config base only.

porenet imports this module whenever it builds the scene schema (``porenet validate``, ``plan``,
``schema``, ``plugins``), so it imports no numerics; the model, :mod:`porenet_gravity.model`,
is imported only when a scene selects the kind.

Why a Bond number and not a density difference
----------------------------------------------
The model is invasion percolation whose throat thresholds are, in porenet's scaled pressure
unit ``gamma / a``, ``p_t = 2 / (r_t / a) + Bo z_t / a`` (see :mod:`porenet_gravity.model`).
The pattern therefore depends on the physical inputs only through ``Bo = delta_rho g a^2 /
gamma``: two scenes with the same ``Bo`` (and the same disorder) give the same invasion
whatever ``delta_rho``, ``g``, ``a`` and ``gamma`` are. Asking for ``Bo`` makes that explicit,
keeps the scene self-describing and comparable with the literature (Wilkinson 1984;
Birovljev et al. 1991 state their results in ``Bo``), and avoids a cross-section dependency:
``a`` is the lattice's ``pore_size``, which a fluid config cannot see when it is validated.
The SI gradient ``delta_rho g = Bo gamma / a^2`` (Pa/m) is reported in the run's summary as
``hydrostatic_gradient``.
"""

from __future__ import annotations

from typing import Any, Literal

from pydantic import Field

from porenet.config.base import ModelConfig

#: The kind a scene selects: ``[fluid] kind = "gravity.invasion-percolation"``.
KIND = "gravity.invasion-percolation"


class GravityInvasionConfig(ModelConfig):
    """Invasion percolation in a gravity field along x, injection from the left edge.

    Each throat's invasion threshold is its capillary entry pressure plus the hydrostatic
    pressure difference between the throat and the injection edge, ``p_t = 2 gamma / r_t +
    delta_rho g z_t`` (Wilkinson 1984), in units of ``gamma / a``: ``2 a / r_t + Bo z_t / a``.
    """

    kind: Literal["gravity.invasion-percolation"] = "gravity.invasion-percolation"
    bond_number: float = Field(
        ...,
        ge=0,
        allow_inf_nan=False,
        description="Bond number Bo = delta_rho g a^2 / gamma (-): |density difference| "
        "delta_rho (kg/m^3) between the two fluids, gravity g (m/s^2), pore size a (m, the "
        "lattice's pore_size), interfacial tension gamma (N/m). The hydrostatic term raises "
        "(stabilising) or lowers (destabilising) a throat's threshold by Bo z / a in units of "
        "gamma / a, z (m) being the throat's distance from the injection edge along x. Bo >= 0; "
        "Bo = 0 is ordinary invasion percolation.",
    )
    gravity: Literal["stabilising", "destabilising"] = Field(
        "stabilising",
        description="Sign of the hydrostatic term. 'stabilising' (+Bo z / a): the invader "
        "is the lighter fluid entering from above (gravity points from the injection edge "
        "to the outlet), or the denser one entering from below; the front is flattened. "
        "'destabilising' (-Bo z / a): the opposite orientation; the invader migrates in "
        "fingers.",
    )
    trapping: bool = Field(
        True,
        description="A defending cluster cut off from the outlet can no longer be invaded "
        "(incompressible defender), as in porenet's invasion-percolation.",
    )
    interfacial_tension: float = Field(
        0.07,
        gt=0,
        allow_inf_nan=False,
        description="Interfacial tension gamma (N/m): sets porenet's pressure scale gamma / a "
        "(the run's pressures in Pa) and the reported hydrostatic gradient Bo gamma / a^2 "
        "(Pa/m). Default 0.07 N/m, as porenet's invasion-percolation.",
    )

    def effects(self) -> dict[str, bool]:
        """The effects the Plan lists (``porenet plan``)."""
        return {
            "capillarity": True,
            "viscous_dissipation": False,
            "trapping": self.trapping,
            "gravity": self.bond_number > 0,
        }

    @property
    def sign(self) -> float:
        """+1 for a stabilising gravity field, -1 for a destabilising one."""
        return 1.0 if self.gravity == "stabilising" else -1.0

    @classmethod
    def example_scene(cls) -> dict[str, Any]:
        """A small scene of this model, for porenet's contract suite (docs/contract.md)."""
        fluid = {"kind": KIND, "bond_number": 0.02}
        lattice = {"n": 12, "disorder": 0.3, "pore_size": 1e-4}
        return {"seed": 1, "lattice": lattice, "injection": {"at": "left-edge"}, "fluid": fluid}
