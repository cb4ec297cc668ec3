"""Tiny scenes the built-in kinds' compile warm-ups and contract examples share.

Each kind's ``warmups.py`` and config name the scenes that call its kernels; this module only
spells the common frame (the paper's square lattice, 12 pores a side, one seed), so that every
built-in kind's examples read the same way.
"""

from __future__ import annotations

from typing import Any

#: The lattice of the tiny scenes: the paper's square lattice, 12 pores a side.
TINY_LATTICE: dict[str, Any] = {"kind": "square", "n": 12, "disorder": 0.3, "pore_size": 1e-7}
#: The paper's two fluids and its solid, as the tiny scenes' sections.
INVASION: dict[str, Any] = {"kind": "invasion-percolation"}
VISCOUS: dict[str, Any] = {"kind": "viscous", "capillary_number": 1e-3}
HERTZ: dict[str, Any] = {"kind": "hertz", "fracturing_number": 1.0}


def tiny_scene(fluid: dict[str, Any], n: int = 12, **sections: Any) -> dict[str, Any]:
    """A scene on the ``n x n`` square lattice with ``fluid`` and further ``sections``."""
    scene: dict[str, Any] = {"seed": 1, "lattice": TINY_LATTICE | {"n": n}, "fluid": fluid}
    scene.update(sections)
    return scene
