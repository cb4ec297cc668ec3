"""Scaled units (docs/model.md section 8).

Inside porenet lengths are measured in units of the pore size ``a``, pressures in units of
``gamma / a`` and times in units of ``mu * a / gamma``, so that a = 0.1 um and a = 1 mm give the
same well-scaled numbers. Configs and outputs are SI; :class:`Scales` converts between the two.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Scales:
    """Characteristic scales of a scene, in SI.

    Attributes
    ----------
    length : float
        Pore size ``a`` (m).
    pressure : float
        Capillary pressure scale ``gamma / a`` (Pa).
    time : float or None
        Viscous time ``mu * a / gamma`` (s); ``None`` when the defending fluid is inviscid.
    """

    length: float
    pressure: float
    time: float | None = None

    @classmethod
    def from_physics(
        cls, pore_size: float, interfacial_tension: float, viscosity: float | None = None
    ) -> Scales:
        """Scales from ``a`` (m), ``gamma`` (N/m) and optionally ``mu`` (Pa s)."""
        time = None if viscosity is None else viscosity * pore_size / interfacial_tension
        return cls(length=pore_size, pressure=interfacial_tension / pore_size, time=time)

    @property
    def area(self) -> float:
        """Area scale ``a**2`` (m^2)."""
        return self.length**2

    @property
    def volume(self) -> float:
        """Volume scale ``a**3`` (m^3)."""
        return self.length**3

    def solid_fields(self, fields: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
        """A solid's fields or per-update series (:meth:`porenet.core.interfaces.SolidModel.
        outputs`, ``snapshot``) from scaled units to SI, by name; boolean masks and names it
        does not know are unchanged."""
        force = self.pressure * self.area
        units = {"spring_compression": self.length, "spring_force": force,
                 "apertures": self.length, "displacement": self.length,
                 "time": self.time or 1.0, "max_aperture_change": self.length,
                 "balance_residual": force, "shear_force": force,
                 "slip": self.length}  # fmt: skip
        return {
            k: v if np.asarray(v).dtype == bool else np.asarray(v) * units.get(k, 1.0)
            for k, v in fields.items()
        }
