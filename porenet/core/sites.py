"""Names of injection sites and outlets, shared by the configs, the plan and the lattices
(pure Python: importable anywhere, imports nothing).

A site is ``"centre"``, a face of the lattice's bounding box (:data:`FACES`), a label of the
lattice (an imported network's ``pore.inlet``) or a list of pore indices
(:meth:`porenet.core.interfaces.Lattice.sites`, docs/lattices.md).
"""

from __future__ import annotations

#: Faces of a lattice's bounding box: name -> (axis, side), side -1 at the smallest coordinate.
FACES: dict[str, tuple[int, int]] = {
    "x-": (0, -1), "x+": (0, 1), "y-": (1, -1), "y+": (1, 1), "z-": (2, -1), "z+": (2, 1),
}  # fmt: skip
#: The face opposite each face (the outlet of an injection at a face).
OPPOSITE_FACE: dict[str, str] = {
    "x-": "x+", "x+": "x-", "y-": "y+", "y+": "y-", "z-": "z+", "z+": "z-",
}  # fmt: skip
#: Older names of faces, still accepted: the paper's linear geometry injects at the left edge.
FACE_ALIASES: dict[str, str] = {"left-edge": "x-"}


def face_of(site: object) -> str | None:
    """The face a site names (aliases resolved), or None if it names no face."""
    if not isinstance(site, str):
        return None
    face = FACE_ALIASES.get(site, site)
    return face if face in FACES else None


def site_geometry(site: object) -> str:
    """``"centre"``, ``"face"`` (linear geometry: injection at one face, outlet at the opposite
    one, the other faces closed) or ``"other"`` (a label or a list of pores)."""
    if site == "centre":
        return "centre"
    return "face" if face_of(site) is not None else "other"
