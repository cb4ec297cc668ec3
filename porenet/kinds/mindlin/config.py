"""Config of the frictional solid, kind ``hertz-mindlin`` (docs/model.md, "Frictional solid").

Pure Python (pydantic and porenet's light modules); the solid, :mod:`porenet.kinds.mindlin.model`,
is imported only when a scene builds it.
"""

from __future__ import annotations

from typing import Any, Literal

from pydantic import Field, model_validator

from porenet.kinds.hertz.config import HertzConfig


def mindlin_ratio(poisson_ratio: float) -> float:
    """Mindlin's ``K_t / K_n = 2 (1 - nu) / (2 - nu)`` for two identical elastic spheres of
    Poisson's ratio ``nu`` (``K_t = 8 G* a_c``, ``K_n = 2 E* a_c``; docs/model.md)."""
    return 2.0 * (1.0 - poisson_ratio) / (2.0 - poisson_ratio)


class HertzMindlinConfig(HertzConfig):
    """The Hertzian solid with frictional contacts: a tangential (Mindlin) stiffness
    ``K_t = r_t K_n`` beside the normal Hertz law, optional Coulomb sliding, and particle
    rotations held or solved (docs/model.md, "Frictional solid (kind hertz-mindlin)").

    Give the tangential stiffness either as ``shear_stiffness_ratio`` (``r_t = K_t / K_n``)
    or as the grains' ``poisson_ratio`` (Mindlin: ``r_t = 2 (1 - nu) / (2 - nu)``), not both.
    With ``r_t = 0`` the solid is the ``hertz`` solid exactly.
    """

    kind: Literal["hertz-mindlin"] = "hertz-mindlin"  # type: ignore[assignment]
    shear_stiffness_ratio: float | None = Field(
        None,
        ge=0,
        le=2,
        description="Tangential over normal contact stiffness K_t / K_n (-), the same at every "
        "compression (both grow like sqrt(R* h)). Mindlin's value for elastic spheres is "
        "2 (1 - nu) / (2 - nu): 1 at nu = 0, 0.857 at 0.25, 0.667 at 0.5; smaller values "
        "stand for rough or partially slipping contacts. 0 is the frictionless 'hertz' solid.",
    )
    poisson_ratio: float | None = Field(
        None,
        gt=-1,
        le=0.5,
        description="Poisson's ratio nu of the grains (-), from which Mindlin's "
        "K_t / K_n = 2 (1 - nu) / (2 - nu) is taken (instead of shear_stiffness_ratio).",
    )
    friction: float | None = Field(
        None,
        ge=0,
        description="Coulomb friction coefficient mu_f of the contacts (-): a contact slides "
        "when its tangential force would exceed mu_f times its normal force, and keeps its "
        "slip. Omitted: contacts never slide (infinite friction).",
    )
    rotation: Literal["held", "free"] = Field(
        "held",
        description="Particle rotations: 'held' (not a degree of freedom: the limit of strong "
        "rolling resistance; x and y then split into two scalar problems, solved by "
        "multigrid) or 'free' (solved, with torque balance on every particle; "
        "sparse-direct solver only). What the choice changes: docs/model.md.",
    )
    solver: Literal["auto", "multigrid", "sparse-direct"] = Field(  # type: ignore[assignment]
        "auto",
        description="Linear solver of each update: 'multigrid' (conjugate gradients "
        "preconditioned by a robust geometric multigrid; square lattice, rotation 'held'), "
        "'sparse-direct' (scipy SuperLU, any lattice, exact) or 'auto' (multigrid where it "
        "applies).",
    )
    solver_tolerance: float = Field(
        1e-2,
        ge=0,
        description="Multigrid: stop when the correction one more iteration would "
        "change no contact's compression or tangential displacement by more than this, in "
        "units of the pore size a (-); the force left out of balance is carried to the next "
        "update, never lost. 0 solves to round-off.",
    )
    max_solver_iterations: int = Field(
        200, ge=1, description="Most multigrid iterations per solve (-); more is reported."
    )
    slip_tolerance: float = Field(
        1e-2,
        ge=0,
        description="With friction: a contact whose change between sticking and sliding "
        "decides a slip of at most this (units of the pore size a, -), i.e. moves its "
        "tangential force by at most K_t times it, changes mode without another solve of the "
        "update; the force this leaves out of balance is carried to the next update. 0 solves "
        'again after every change (docs/model.md, "Frictional solid", Solver).',
    )

    @model_validator(mode="after")
    def _one_shear_stiffness(self) -> HertzMindlinConfig:
        if (self.shear_stiffness_ratio is None) == (self.poisson_ratio is None):
            raise ValueError(
                "give exactly one of 'shear_stiffness_ratio' (K_t / K_n) and 'poisson_ratio' "
                "(nu, Mindlin's ratio 2 (1 - nu) / (2 - nu))"
                + (" (both were given)" if self.poisson_ratio is not None else "")
            )
        if self.rotation == "free" and self.solver == "multigrid":
            raise ValueError(
                "solver = 'multigrid' needs rotation = 'held' (free rotations couple x and y); "
                "use 'sparse-direct' or 'auto'"
            )
        return self

    @property
    def stiffness_ratio(self) -> float:
        """``K_t / K_n`` (-), given or from ``poisson_ratio``."""
        if self.shear_stiffness_ratio is not None:
            return float(self.shear_stiffness_ratio)
        assert self.poisson_ratio is not None
        return mindlin_ratio(self.poisson_ratio)

    def effects(self) -> dict[str, bool]:
        sheared = self.stiffness_ratio > 0
        return {
            "deformation": True,
            "contact_loss": True,
            "shear_stiffness": sheared,
            "sliding": sheared and self.friction is not None,
            "particle_rotation": sheared and self.rotation == "free",
        }

    @classmethod
    def example_scene(cls) -> dict[str, Any]:
        """A small scene of invasion percolation in this solid (the contract suite runs it)."""
        from porenet.kinds.scenes import INVASION, tiny_scene

        return tiny_scene(
            INVASION,
            solid={"kind": "hertz-mindlin", "fracturing_number": 1.0, "shear_stiffness_ratio": 0.5},
        )
