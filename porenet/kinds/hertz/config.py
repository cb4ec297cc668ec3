"""Config of the Hertzian solid, kind ``hertz``.

Pure Python (pydantic and porenet's light modules), so that the scene schema, ``porenet
validate`` and ``porenet plan`` import no numerics; the solid,
:mod:`porenet.kinds.hertz.model`, is imported only when a scene builds it.
"""

from __future__ import annotations

from typing import Any, ClassVar, Literal

from pydantic import Field, model_validator

from porenet.config.base import CouplerKind, ModelConfig


class HertzConfig(ModelConfig):
    """Block-and-spring network with Hertzian contacts, prestressed in compression, no tension.

    Give the stiffness either as ``modulus`` (E*, Pa) or as ``fracturing_number``
    (N_f = gamma / (lambda a E* eps_0^(1/2)), Eq. 2 of the paper), not both.
    """

    kind: Literal["hertz"] = "hertz"
    modulus: float | None = Field(
        None, gt=0, description="Constrained Young modulus E* of the particles (Pa)."
    )
    fracturing_number: float | None = Field(
        None,
        gt=0,
        description="Fracturing number N_f = gamma / (lambda a E* eps_0^(1/2)) (-), from which "
        "E* is derived (needs the lattice's disorder lambda). Fracturing dominates for "
        "N_f >~ 1.",
    )
    prestrain: float = Field(
        0.05,
        gt=0,
        lt=1,
        description="Initial strain eps_0 = h_0 / 2a of every spring (-). Paper: 0.05.",
    )
    pressure_area_factor: float = Field(
        1.0, gt=0, description="c_p in the pressure force f_p = p A_p, A_p = c_p a^2 (-)."
    )
    cohesion: float = Field(
        1e-6,
        gt=0,
        le=1e-2,
        description="Stiffness of an open (removed) spring relative to the prestress stiffness "
        "K_0 = 2 E* sqrt(R* h_0) (-): the small cohesive regularisation that keeps a particle "
        "that lost its contacts solvable. Results do not depend on it (docs/model.md).",
    )
    foundation: float = Field(
        0.0,
        ge=0,
        le=100,
        description="Stiffness of an elastic support (Winkler foundation) that holds every free "
        "particle to its initial position, in x and in y, relative to the prestress stiffness "
        "K_0 (-). 0 is the paper's model: a frictionless square lattice carries a particle's "
        "load along its line of springs to the fixed ring. A positive value makes the response "
        "local (it decays over ~1/sqrt(foundation) springs); not in the paper "
        "(docs/model.md, docs/paper.md).",
    )
    boundary: Literal["fixed-ring"] = Field(
        "fixed-ring",
        description="Mechanical boundary: 'fixed-ring', the outer ring of particles (the "
        "lattice's fixed_particles) never moves (confinement).",
    )
    recontact: Literal["restore", "never"] = Field(
        "restore",
        description="'restore': a removed spring whose particles touch again (h > 0) is a "
        "contact again; 'never': a removed spring stays removed (particles may then overlap, "
        "bounded only by the aperture floor).",
    )
    aperture_floor: float = Field(
        0.01,
        gt=0,
        lt=1,
        description="Smallest aperture, as a fraction of the mean aperture (-): compaction "
        "that would close a throat further stops there and is counted in the summary.",
    )
    aperture_cap: float = Field(
        2.0,
        gt=1,
        description="Largest aperture, as a multiple of the mean aperture (-): particles may "
        "separate further, but the throat the fluid sees stops widening there (its "
        "conductance grows like r^4 and would stall the flow solver); counted in the summary.",
    )
    solver: Literal["auto", "chains", "sparse-direct"] = Field(
        "auto",
        description="Linear solver of each update: 'chains' (x and y decouple when every spring "
        "lies along x or y; each line of springs between fixed particles is a tridiagonal "
        "system, O(N)), 'sparse-direct' (any lattice: scipy SuperLU of the 2-D stiffness "
        "matrix) or 'auto' (chains when the lattice allows them).",
    )
    max_contact_iterations: int = Field(
        50,
        ge=1,
        description="Most solves per update while contacts open and close (-); an update that "
        "still changes after them is counted in the summary as unsettled.",
    )
    coupler: CouplerKind = Field(
        "pressure-aperture",
        description="Coupler kind that passes pore pressures to the solid and apertures back: "
        "'pressure-aperture' (porenet's), or a plugin's.",
    )
    coupling: Literal["every-step", "interval", "adaptive"] = Field(
        "adaptive",
        description="When the solid is updated: 'every-step' (after every fluid step; for "
        "invasion percolation every drained pore, the quasi-static rule), 'interval' (every "
        "coupling_interval fluid steps) or 'adaptive' (after a fluid step whose pressure "
        "changes since the last update could deform a spring by more than "
        "coupling_tolerance).",
    )
    coupling_interval: int = Field(
        1, ge=1, description="Fluid steps between updates for coupling = 'interval' (-)."
    )
    coupling_tolerance: float = Field(
        3e-3,
        gt=0,
        description="'adaptive' coupling updates the solid after a fluid step when the "
        "largest pore-pressure change since the last update, dp, could change a spring's "
        "compression by more than this: dp A_p / K_0 > tolerance, in units of the pore size "
        "a (-); K_0 is the prestress stiffness.",
    )

    builds_nothing: ClassVar[bool] = False

    @model_validator(mode="after")
    def _exactly_one_stiffness(self) -> HertzConfig:
        if (self.modulus is None) == (self.fracturing_number is None):
            raise ValueError(
                "give exactly one of 'modulus' (E*, Pa) and 'fracturing_number' (N_f)"
                + (" (both were given)" if self.modulus is not None else "")
            )
        return self

    def effects(self) -> dict[str, bool]:
        return {"deformation": True, "contact_loss": True}

    @classmethod
    def example_scene(cls) -> dict[str, Any]:
        """A small scene of invasion percolation in this solid (the contract suite runs it)."""
        from porenet.kinds.scenes import HERTZ, INVASION, tiny_scene

        return tiny_scene(INVASION, solid=HERTZ)
