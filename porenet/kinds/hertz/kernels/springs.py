"""Block-and-spring mechanics with Hertzian contacts (docs/model.md section 5).

Pure functions on arrays, in scaled units: lengths by the pore size ``a``, pressures by
``gamma / a``, forces by ``gamma a``, stiffnesses (force per length) by ``gamma`` and the
modulus ``E*`` by ``gamma / a``.

The model (Holtzman & Juanes 2010, p. 3):

* a spring (contact) between particles ``m`` and ``n`` is compressed by ``h`` (overlap); the
  Hertz contact of equal spheres of radius ``a`` has ``R* = a/2``, normal force
  ``F = (4/3) E* sqrt(R*) h**1.5`` and tangent stiffness ``K = 2 E* sqrt(R* h)``;
* each pore pushes each particle it touches with ``p A_p`` along the unit vector from the pore
  centre to the particle (45 degrees on the square lattice);
* an update imposes force balance on every free particle, linearised about the current state:
  ``F_new = F + K dh`` with ``dh = -(du_n - du_m) . e_mn``, ``e_mn`` the unit vector from
  ``m`` to ``n``;
* the throat crossing a spring changes aperture by
  ``dr = -dh (1 - eps) / (2 sqrt(1 + (1 - eps)**2))``, ``eps = h / 2a`` (:func:`aperture_change`);
* contacts carry no tension: a spring whose ``h <= 0`` is removed.

Contacts within an update
-------------------------
Every spring is in one of three modes during an update, each a linear law
``F_new = b + k dh`` about the state at the start of the update:

==============  ===========================  =============================================
mode            k                            b
==============  ===========================  =============================================
``IN_CONTACT``  ``K(h)`` (Hertz tangent)     ``F`` (the paper's incremental law)
``OPEN``        ``k_c`` (cohesion)           ``k_c h``: a weak spring through ``h = 0``
``RECONTACT``   ``K_0 = K(h_0)``             ``K_0 h``: a contact re-forming at ``h = 0``
==============  ===========================  =============================================

After each solve, a spring in contact whose new ``h <= 0`` opens, and (if re-contact is
allowed) an open spring whose new ``h > 0`` closes again (``RECONTACT``, also for a spring
that was in contact at the start of the update and opened during it); the update is solved
again until no spring changes mode. ``OPEN`` and ``RECONTACT`` both carry zero force at
``h = 0``, so together they form one monotone law and the iteration cannot cycle between
them; going back to the incremental ``IN_CONTACT`` law, whose force vanishes at
``h = h_old / 3`` rather than at 0, could.

The cohesive stiffness ``k_c`` (orders of magnitude below ``K_0``) is the regularisation that
keeps a particle solvable when it has lost all its contacts along an axis. With re-contact, a
particle that loses its contacts moves only until it touches another one, so the result does
not depend on ``k_c`` (tests/verification/test_mechanics_physics.py). A re-forming contact
starts at ``h = 0``, where the Hertz tangent is zero, so it is given the
prestress stiffness ``K_0`` for the update in which it forms, and the Hertz tangent afterwards.

Foundation
----------
An option beyond the paper (``foundation`` of the solid's config, 0 by default): every free
particle is also held to its initial position by a linear spring of stiffness ``k_f`` in x and
in y (a Winkler foundation), force ``-k_f u`` with ``u`` its total displacement. In the
paper's frictionless square lattice the springs resist only along their axis, so a force on a
particle is carried by its line of springs to the fixed ring and its displacement grows with
the distance to it (~ ``L f / 4K``); with ``k_f > 0`` it decays along the line over
~ ``sqrt(K / k_f)`` springs, a local response as the fracturing number's scaling assumes
(``dh ~ df / K`` of one spring). The foundation changes neither the prestressed state (it
carries no force at ``u = 0``) nor the linearity of an update: it adds ``k_f`` to the
stiffness matrix's diagonal and ``-k_f u`` to the loads.

Solvers
-------
When every spring lies along x or y (the square lattice), x and y decouple and every line of
springs between two fixed particles is an independent tridiagonal system (a *chain*), solved
by the Thomas algorithm in O(N) with the contact iteration done per chain
(:mod:`porenet.kinds.hertz.kernels.chains`). Otherwise :func:`solve_sparse` assembles the 2-D
stiffness matrix (scipy.sparse) and solves it with a sparse direct solver.

Length (over the ~500 lines of docs/architecture.md's rule): the contact laws, the loads and the
sparse solve they feed use the same named tuples (SpringState, ContactLaw, ApertureMap); the
line-by-line solve of axis-aligned networks is apart (chains.py). About a third of the module is
documentation of the model and its units.
"""

from __future__ import annotations

import math
from enum import IntEnum
from typing import NamedTuple

import numpy as np

from porenet.jit.jit import njit

#: R* / a for two equal spheres of radius a.
REDUCED_RADIUS = 0.5

#: Modes of a spring within an update (module docstring, "Contacts within an update").
IN_CONTACT, OPEN, RECONTACT = 0, 1, 2


class SpringState(NamedTuple):
    """The springs (contacts) of the solid, one per throat (scaled units).

    Attributes
    ----------
    compression : ndarray of float64, shape (M,)
        Overlap ``h`` of each contact (a).
    force : ndarray of float64, shape (M,)
        Normal force (gamma a).
    mode : ndarray of int8, shape (M,)
        :data:`IN_CONTACT` or :data:`OPEN` between updates.
    """

    compression: np.ndarray
    force: np.ndarray
    mode: np.ndarray


class ContactLaw(NamedTuple):
    """The contact laws of an update (module docstring).

    Attributes
    ----------
    modulus : float
        ``E*`` (gamma / a).
    cohesion_stiffness, contact_stiffness, foundation_stiffness : float
        ``k_c``, ``K_0`` and ``k_f`` (gamma).
    recontact : bool
        Whether an open spring may close again.
    max_iterations : int
        Most contact iterations (solves) per update.
    """

    modulus: float
    cohesion_stiffness: float
    contact_stiffness: float
    foundation_stiffness: float
    recontact: bool
    max_iterations: int


class ApertureMap(NamedTuple):
    """From the springs' compressions to the throats' apertures (:func:`apply_spring`).

    Attributes
    ----------
    geometric : ndarray of float64, shape (M,)
        The aperture the packing's geometry gives (a), unbounded.
    apertures : ndarray of float64, shape (M,)
        The aperture the fluid sees: the geometric one bounded to ``[floor, cap]``.
    floor, cap : float
        The bounds (a).
    at_floor, at_cap : ndarray of bool, shape (M,)
        Throats that reached a bound.
    """

    geometric: np.ndarray
    apertures: np.ndarray
    floor: float
    cap: float
    at_floor: np.ndarray
    at_cap: np.ndarray


class Stat(IntEnum):
    """Slots of the statistics of an update (:func:`porenet.kinds.hertz.kernels.chains.
    solve_chains`)."""

    ITERATIONS = 0  #: largest number of solves of one line (or of the system)
    UNSETTLED = 1  #: lines whose contacts still changed after the last iteration
    RESIDUAL = 2  #: largest out-of-balance force left on a free particle (round-off)
    SOLVED = 3  #: lines solved
    OPENED = 4  #: springs that opened minus springs that closed
    CHANGED = 5  #: throats whose aperture changed (listed)
    LARGEST_CHANGE = 6  #: largest aperture change (a)
    FINITE = 7  #: 0 if a non-finite value appeared


def hertz_force(h: np.ndarray | float, modulus: float) -> np.ndarray:
    """Hertz normal force ``(4/3) E* sqrt(R*) h**1.5`` (0 for ``h <= 0``), scaled by gamma a.

    ``h`` in units of a, ``modulus`` (E*) in units of gamma / a.
    """
    hp = np.maximum(np.asarray(h, dtype=np.float64), 0.0)
    return (4.0 / 3.0) * modulus * math.sqrt(REDUCED_RADIUS) * hp**1.5


def hertz_stiffness(h: np.ndarray | float, modulus: float) -> np.ndarray:
    """Hertz tangent stiffness ``2 E* sqrt(R* h)`` (0 for ``h <= 0``), scaled by gamma."""
    hp = np.maximum(np.asarray(h, dtype=np.float64), 0.0)
    return 2.0 * modulus * np.sqrt(REDUCED_RADIUS * hp)


def aperture_change(dh: np.ndarray, h: np.ndarray) -> np.ndarray:
    """Aperture change of the throat crossing each spring, ``-dh (1-eps)/(2 sqrt(1+(1-eps)^2))``.

    Parameters
    ----------
    dh : ndarray, shape (M,)
        Change of the spring compression over the update (units of a).
    h : ndarray, shape (M,)
        Compression at the start of the update (units of a); ``eps = h / 2``.

    Returns
    -------
    ndarray, shape (M,)
        ``dr / a`` (cubic packing of Hertzian spheres, Holtzman & Juanes 2010).
    """
    one_minus = 1.0 - 0.5 * h
    return -dh * one_minus / (2.0 * np.sqrt(1.0 + one_minus**2))


@njit
def pressure_loads(
    pore_pressure: np.ndarray,
    pair_pore: np.ndarray,
    pair_particle: np.ndarray,
    pair_direction: np.ndarray,
    area: float,
    out: np.ndarray,
) -> None:
    """Fluid forces on the particles: ``out[q] = sum p_i A_p d_iq`` over the pores i touching q.

    Parameters
    ----------
    pore_pressure : (N,) float
        Pressure in each pore (gamma / a).
    pair_pore, pair_particle : (P,) int
        The pore-particle contacts.
    pair_direction : (P, 2) float
        Unit vector from the pore centre towards the particle.
    area : float
        ``A_p / a**2``.
    out : (n_particles, 2) float
        Overwritten with the forces (gamma a).
    """
    out[:] = 0.0
    for k in range(pair_pore.shape[0]):
        f = pore_pressure[pair_pore[k]] * area
        q = pair_particle[k]
        out[q, 0] += f * pair_direction[k, 0]
        out[q, 1] += f * pair_direction[k, 1]


@njit
def add_spring_loads(
    force: np.ndarray, spring_particles: np.ndarray, axis: np.ndarray, out: np.ndarray
) -> None:
    """Add the contact forces to ``out``: a compressive ``F > 0`` pushes the spring's second
    particle along ``axis`` (unit vector from its first particle to its second) and the first
    one back."""
    for s in range(force.shape[0]):
        m = spring_particles[s, 0]
        n = spring_particles[s, 1]
        fx = force[s] * axis[s, 0]
        fy = force[s] * axis[s, 1]
        out[n, 0] += fx
        out[n, 1] += fy
        out[m, 0] -= fx
        out[m, 1] -= fy


def _unit_vectors(d: np.ndarray) -> tuple[np.ndarray, int]:
    """Rows of ``d`` divided by their lengths, and the first row of zero length (-1 if none)."""
    length = np.hypot(d[:, 0], d[:, 1])
    zero = np.flatnonzero(length <= 0)
    if zero.size:
        return d, int(zero[0])
    return d / length[:, None], -1


def spring_axes(spring_particles: np.ndarray, particle_coords: np.ndarray) -> np.ndarray:
    """(M, 2) unit vectors from each spring's first particle to its second."""
    d = particle_coords[spring_particles[:, 1]] - particle_coords[spring_particles[:, 0]]
    axes, bad = _unit_vectors(d)
    if bad >= 0:
        raise ValueError(f"spring {bad} joins two particles at the same position")
    return axes


def pore_particle_directions(
    pair_pore: np.ndarray,
    pair_particle: np.ndarray,
    pore_coords: np.ndarray,
    particle_coords: np.ndarray,
) -> np.ndarray:
    """(P, 2) unit vectors from each pore centre towards each particle it touches."""
    directions, bad = _unit_vectors(particle_coords[pair_particle] - pore_coords[pair_pore])
    if bad >= 0:
        raise ValueError(f"pore {int(pair_pore[bad])} sits on particle {int(pair_particle[bad])}")
    return directions


# -- any lattice: sparse direct solve -------------------------------------------------------


@njit(helper=True)
def contact_law(
    mode: int, h: float, force: float, tangent: float, cohesion: float, recontact: float
) -> tuple[float, float]:
    """One spring's linear law ``F_new = b + k dh`` in its ``mode`` (module docstring): returns
    ``(k, b)``. ``tangent`` is the Hertz stiffness at ``h``, ``cohesion`` and ``recontact`` the
    stiffnesses ``k_c`` and ``K_0``."""
    if mode == IN_CONTACT:
        return tangent, force
    if mode == OPEN:
        return cohesion, cohesion * h
    return recontact, recontact * h


@njit(helper=True)
def next_mode(mode: int, h_new: float, recontact: bool) -> int:
    """The mode after a solve that gave compression ``h_new``: a spring in contact opens at
    ``h_new <= 0``; an open one closes again at ``h_new > 0`` if re-contact is allowed."""
    if mode != OPEN and h_new <= 0.0:
        return OPEN
    if mode == OPEN and recontact and h_new > 0.0:
        return RECONTACT
    return mode


@njit
def _contact_laws(
    mode: np.ndarray,
    h: np.ndarray,
    force: np.ndarray,
    tangent: np.ndarray,
    cohesion: float,
    recontact: float,
    k: np.ndarray,
    b: np.ndarray,
) -> None:
    """:func:`contact_law` of every spring, into ``k`` and ``b``."""
    for s in range(mode.shape[0]):
        k[s], b[s] = contact_law(mode[s], h[s], force[s], tangent[s], cohesion, recontact)


@njit
def _next_modes(mode: np.ndarray, h_new: np.ndarray, recontact: bool) -> bool:
    """:func:`next_mode` of every spring, in place; True if any changed."""
    changed = False
    for s in range(mode.shape[0]):
        new = next_mode(mode[s], h_new[s], recontact)
        if new != mode[s]:
            mode[s] = new
            changed = True
    return changed


def solve_sparse(
    spring_particles: np.ndarray,
    axis: np.ndarray,
    fixed: np.ndarray,
    load: np.ndarray,
    springs: SpringState,
    law: ContactLaw,
    displacement: np.ndarray | None = None,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, int, int]:
    """One mechanical update on any spring network: the same laws and contact iteration as
    :func:`solve_chains`, with the 2-D stiffness matrix of the free particles assembled in
    scipy.sparse and factorised by SuperLU at each contact iteration.

    ``spring_particles`` (M, 2) the particles of each spring, ``axis`` ((M, 2) unit vectors,
    :func:`spring_axes`), ``fixed`` ((n_particles,) bool), ``load`` the fluid forces
    ((n_particles, 2)). ``springs.mode`` is updated in place. With a foundation
    (``law.foundation_stiffness`` ``k_f > 0``, module docstring, "Foundation") the particles'
    current total ``displacement`` ((n_particles, 2)) is needed.

    Returns
    -------
    displacement : (n_particles, 2) float
    dh, force_new : (M,) float
    iterations, unsettled : int
        Solves done, and 1 if the contacts still changed after ``max_iterations`` solves.
    """
    from scipy.sparse import coo_matrix
    from scipy.sparse.linalg import splu

    h, force, mode = springs
    modulus, cohesion_stiffness, contact_stiffness, foundation_stiffness, recontact, max_iter = law
    n_particles = fixed.shape[0]
    dof = np.full((n_particles, 2), -1, dtype=np.int64)
    free = np.flatnonzero(~fixed)
    dof[free] = np.arange(2 * free.size).reshape(-1, 2)
    m_idx, n_idx = spring_particles[:, 0], spring_particles[:, 1]
    # The matrix's pattern is fixed: entry e is k[spring[e]] * coef[e] at (row[e], col[e]).
    rows, cols, coefs, springs = [], [], [], []
    every = np.arange(len(m_idx))
    for a in range(2):
        for c in range(2):
            for p, q, sgn in ((m_idx, m_idx, 1.0), (n_idx, n_idx, 1.0),
                              (m_idx, n_idx, -1.0), (n_idx, m_idx, -1.0)):  # fmt: skip
                rows.append(dof[p, a])
                cols.append(dof[q, c])
                coefs.append(sgn * axis[:, a] * axis[:, c])
                springs.append(every)
    row, col = np.concatenate(rows), np.concatenate(cols)
    keep = (row >= 0) & (col >= 0)
    row, col = row[keep], col[keep]
    coef, spring = np.concatenate(coefs)[keep], np.concatenate(springs)[keep]
    size = 2 * free.size
    foundation_load, diagonal = None, np.zeros(0)
    if foundation_stiffness > 0.0:
        if displacement is None:
            raise ValueError("solve_sparse: a foundation needs the current displacement")
        row = np.concatenate([row, np.arange(size)])
        col = np.concatenate([col, np.arange(size)])  # k_f on the diagonal, after the springs
        diagonal = np.full(size, foundation_stiffness)
        foundation_load = foundation_stiffness * displacement  # fixed within the update
    tangent = hertz_stiffness(h, modulus)
    k, b = np.empty_like(h), np.empty_like(h)
    local = mode.copy()
    du = np.zeros((n_particles, 2))
    iterations, unsettled = 0, 0
    while True:
        iterations += 1
        _contact_laws(local, h, force, tangent, cohesion_stiffness, contact_stiffness, k, b)
        rhs_full = load.copy() if foundation_load is None else load - foundation_load
        add_spring_loads(b, spring_particles, axis, rhs_full)
        values = np.concatenate([k[spring] * coef, diagonal])
        matrix = coo_matrix((values, (row, col)), shape=(size, size)).tocsc()
        x = splu(matrix).solve(rhs_full[free].ravel())
        du[:] = 0.0
        du[free] = x.reshape(-1, 2)
        dh = -np.einsum("ij,ij->i", du[n_idx] - du[m_idx], axis)
        new = local.copy()
        if not _next_modes(new, h + dh, recontact):
            break
        if iterations >= max_iter:
            unsettled = 1
            break
        local = new
    mode[:] = np.where(local == OPEN, OPEN, IN_CONTACT)
    return du, dh, b + k * dh, iterations, unsettled


@njit
def balance_residual(
    load: np.ndarray,
    force: np.ndarray,
    spring_particles: np.ndarray,
    axis: np.ndarray,
    fixed: np.ndarray,
    displacement: np.ndarray,
    foundation_stiffness: float,
) -> float:
    """Largest net force on a free particle (gamma a): fluid ``load`` plus contact forces plus
    the foundation's ``-k_f u`` (module docstring)."""
    total = load - foundation_stiffness * displacement
    add_spring_loads(force, spring_particles, axis, total)
    largest = 0.0
    for q in range(fixed.shape[0]):
        if not fixed[q]:
            largest = max(largest, abs(total[q, 0]), abs(total[q, 1]))
    return largest


@njit(helper=True)
def apply_spring(
    s: int, dh: float, force_new: float, springs: SpringState, aperture: ApertureMap
) -> float:
    """Apply spring ``s``'s solved change: its throat's geometric aperture changes by
    :func:`aperture_change` (with the compression before the update), the aperture the fluid
    sees becomes it bounded to ``[floor, cap]`` (``at_floor`` / ``at_cap`` mark the bounds
    reached), then the compression grows by ``dh`` and the force becomes ``force_new``.
    Returns ``|change|`` of the seen aperture."""
    return apply_spring_lagged(s, dh, force_new, springs, aperture, 0.0)


@njit(helper=True)
def apply_spring_lagged(
    s: int, dh: float, force_new: float, springs: SpringState, aperture: ApertureMap, lag: float
) -> float:
    """:func:`apply_spring`, except that the aperture the fluid sees keeps its value while the
    bounded geometric aperture differs from it by at most ``lag`` (a; returns 0 then): a
    global solve moves every contact a little, and the fluid need not refresh a throat for a
    change far below the coupling's tolerance. The geometric aperture always follows, so the
    lag never accumulates beyond ``lag``."""
    h, force = springs.compression, springs.force
    geometric, apertures = aperture.geometric, aperture.apertures
    one_minus = 1.0 - 0.5 * h[s]
    geometric[s] += -dh * one_minus / (2.0 * math.sqrt(1.0 + one_minus * one_minus))
    r = geometric[s]
    if r < aperture.floor:
        r = aperture.floor
        aperture.at_floor[s] = True
    elif r > aperture.cap:
        r = aperture.cap
        aperture.at_cap[s] = True
    change = abs(r - apertures[s])
    h[s] += dh
    force[s] = force_new
    if lag > 0.0 and change <= lag:
        return 0.0
    apertures[s] = r
    return change


@njit
def apply_update(
    dh: np.ndarray,
    force_new: np.ndarray,
    du: np.ndarray,
    springs: SpringState,
    displacement: np.ndarray,
    aperture: ApertureMap,
) -> tuple[float, bool]:
    """Apply a solved update of every spring (:func:`apply_spring`) and particle
    (``displacement += du``), in place.

    Returns
    -------
    largest_change : float
        Largest ``|change|`` of the apertures (a).
    finite : bool
        False if any displacement increment or force is not finite (nothing is applied then).
    """
    for s in range(dh.shape[0]):
        if not (math.isfinite(dh[s]) and math.isfinite(force_new[s])):
            return 0.0, False
    for q in range(du.shape[0]):
        if not (math.isfinite(du[q, 0]) and math.isfinite(du[q, 1])):
            return 0.0, False
    largest = 0.0
    for s in range(dh.shape[0]):
        change = apply_spring(s, dh[s], force_new[s], springs, aperture)
        largest = max(largest, change)
    for q in range(du.shape[0]):
        displacement[q, 0] += du[q, 0]
        displacement[q, 1] += du[q, 1]
    return largest, True


@njit
def largest_pressure_change(
    pressure: np.ndarray, drained: np.ndarray, invading_pressure: float, last: np.ndarray
) -> float:
    """``max |p - last|`` over the pores, ``p`` being ``invading_pressure`` in drained pores and
    ``pressure`` elsewhere (what :func:`pressure_loads` would be given), without a temporary."""
    largest = 0.0
    for i in range(last.shape[0]):
        p = invading_pressure if drained[i] else pressure[i]
        largest = max(largest, abs(p - last[i]))
    return largest


@njit
def fill_pore_pressures(
    out: np.ndarray, pressure: np.ndarray, drained: np.ndarray, invading_pressure: float
) -> None:
    """``out[i] = invading_pressure`` in drained pores, ``pressure[i]`` elsewhere (``pressure``
    may be empty: the defender is then at 0)."""
    have = pressure.shape[0] > 0
    for i in range(out.shape[0]):
        if drained[i]:
            out[i] = invading_pressure
        else:
            out[i] = pressure[i] if have else 0.0
