"""The paper's dimensionless groups (docs/model.md section 6), in one place.

Plain arithmetic on floats, in any consistent units (SI, or porenet's scaled units with
``gamma = a = 1``).
"""

from __future__ import annotations

import math


def disorder_factor(disorder: float) -> float:
    """``lambda / (1 - lambda^2)``, the disorder's weight in the modified capillary number."""
    return disorder / (1.0 - disorder**2)


def modified_capillary_number(capillary_number: float, n: int, disorder: float) -> float:
    """``Ca* = Ca (L/a) / [lambda/(1-lambda^2)]`` with ``L = n a``; the CF/VF crossover is at
    Ca* ~ 1 (Fig. 2)."""
    return capillary_number * n / disorder_factor(disorder)


def capillary_number_at(modified: float, n: int, disorder: float) -> float:
    """The ``Ca`` that gives the modified capillary number ``Ca* = modified`` (inverse of
    :func:`modified_capillary_number`)."""
    return modified * disorder_factor(disorder) / n


def fracturing_number(
    interfacial_tension: float, disorder: float, pore_size: float, modulus: float, prestrain: float
) -> float:
    """Eq. 2: ``N_f = gamma / (lambda a E* eps_0^(1/2))``; fracturing dominates for N_f >~ 1."""
    return interfacial_tension / (disorder * pore_size * modulus * math.sqrt(prestrain))


def modulus_for(
    fracturing: float, interfacial_tension: float, disorder: float, pore_size: float,
    prestrain: float,
) -> float:  # fmt: skip
    """The ``E*`` that gives the fracturing number ``fracturing`` (inverse of Eq. 2)."""
    return interfacial_tension / (fracturing * disorder * pore_size * math.sqrt(prestrain))
