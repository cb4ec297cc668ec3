"""Config of the ``linear.springs`` solid: pydantic and porenet's light config base only.

porenet imports this module whenever it builds the scene schema (``porenet validate``, ``plan``,
``schema``, ``plugins``), so it imports no numerics; the solid, :mod:`porenet_linear.solid`,
and scipy with it, are imported only when a scene selects the kind.
"""

from __future__ import annotations

from typing import Any, ClassVar, Literal

from pydantic import Field, model_validator

from porenet.config.base import CouplerKind, ModelConfig

#: The kind a scene selects: ``[solid] kind = "linear.springs"``.
KIND = "linear.springs"


class LinearSpringsConfig(ModelConfig):
    """Block-and-spring network with linear (Hookean) contacts: normal force ``F = k h`` for an
    overlap ``h > 0``, prestressed in compression, no tension.

    Give the stiffness either as ``stiffness`` (k, N/m) or as ``fracturing_number``
    (N_f = 2 gamma / (lambda k)), not both.
    """

    kind: Literal["linear.springs"] = "linear.springs"
    stiffness: float | None = Field(
        None,
        gt=0,
        allow_inf_nan=False,
        description="Contact stiffness k of every spring (N/m): normal force F = k h for an "
        "overlap h > 0.",
    )
    fracturing_number: float | None = Field(
        None,
        gt=0,
        allow_inf_nan=False,
        description="N_f = 2 gamma / (lambda k) (-), from which k is derived (needs the "
        "lattice's disorder lambda): the compression 2 gamma / k (units of a) that the entry "
        "pressure of a mean throat, 2 gamma / a on an area a^2, causes in one contact, "
        "relative to the aperture disorder lambda. Equal to the Hertz solid's N_f (Eq. 2) "
        "when k equals its prestress stiffness K_0.",
    )
    prestrain: float = Field(
        0.05,
        gt=0,
        lt=1,
        description="Initial overlap of every contact, eps_0 = h_0 / 2a (-): the prestress "
        "F_0 = k h_0 that a contact loses before it opens.",
    )
    pressure_area_factor: float = Field(
        1.0, gt=0, description="c_p in the pressure force f_p = p A_p, A_p = c_p a^2 (-)."
    )
    cohesion: float = Field(
        1e-6,
        gt=0,
        le=1e-2,
        description="Stiffness of an open contact (h <= 0) relative to k (-): the weak spring "
        "that keeps a particle that lost its contacts solvable.",
    )
    aperture_floor: float = Field(
        0.01,
        gt=0,
        lt=1,
        description="Smallest aperture, as a fraction of the mean aperture (-).",
    )
    aperture_cap: float = Field(
        2.0, gt=1, description="Largest aperture, as a multiple of the mean aperture (-)."
    )
    max_contact_iterations: int = Field(
        50,
        ge=1,
        description="Most solves per update while contacts open and close (-); an update "
        "whose contacts still change after them is counted in the summary as unsettled.",
    )
    coupler: CouplerKind = Field(
        "pressure-aperture",
        description="Coupler kind that passes pore pressures to the solid and apertures back "
        "(porenet's built-in 'pressure-aperture', named, not imported, or a plugin's).",
    )
    coupling: Literal["every-step", "interval", "adaptive"] = Field(
        "adaptive",
        description="When the solid is updated (the coupler's schedule, as for the 'hertz' "
        "solid): after every fluid step, every coupling_interval steps, or when a pressure "
        "change could deform a contact by more than coupling_tolerance.",
    )
    coupling_interval: int = Field(
        1, ge=1, description="Fluid steps between updates for coupling = 'interval' (-)."
    )
    coupling_tolerance: float = Field(
        3e-3,
        gt=0,
        description="'adaptive' coupling: deformation dp A_p / k (units of the pore size a, -) "
        "a pressure change dp may cause before the solid is updated.",
    )

    builds_nothing: ClassVar[bool] = False

    @model_validator(mode="after")
    def _exactly_one_stiffness(self) -> LinearSpringsConfig:
        if (self.stiffness is None) == (self.fracturing_number is None):
            raise ValueError(
                "give exactly one of 'stiffness' (k, N/m) and 'fracturing_number' (N_f)"
                + (" (both were given)" if self.stiffness is not None else "")
            )
        return self

    def effects(self) -> dict[str, bool]:
        """The effects the Plan lists (``porenet plan``)."""
        return {"deformation": True, "contact_loss": True}

    @classmethod
    def example_scene(cls) -> dict[str, Any]:
        """A small scene of invasion percolation in this solid, for porenet's contract suite
        (docs/contract.md)."""
        solid = {"kind": KIND, "fracturing_number": 1.0}
        return {"seed": 1, "lattice": {"n": 12, "disorder": 0.3}, "fluid": {}, "solid": solid}
