"""Linear contact springs between particles: the mechanics as pure functions of arrays.

Units are porenet's scaled ones (docs/model.md section 8): lengths in the pore size ``a``,
pressures in ``gamma / a``, forces in ``gamma a`` and stiffnesses (force per length) in
``gamma``.

The model is the block-and-spring network of docs/model.md section 5 with the Hertz contact
replaced by a linear one. Spring ``s`` joins particles ``m`` and ``n``, with ``e_s`` the unit
vector from ``m`` to ``n``. With ``u`` the particles' displacements from the prestressed
state, its overlap is

    h_s = h_0 - (u_n - u_m) . e_s                      (h_0 = 2 a eps_0, the prestrain)

and its normal force

    F_s = k h_s       for h_s > 0  (a contact)
    F_s = k_c h_s     for h_s <= 0 (open: k_c = cohesion x k, the weak spring that keeps a
                                    particle that lost its contacts solvable)

A compressive ``F_s > 0`` pushes ``n`` along ``+e_s`` and ``m`` along ``-e_s``; each pore ``i``
pushes each particle it touches with ``p_i A_p`` along the unit vector from the pore centre
to the particle. With ``B`` the (M, 2P) matrix that maps displacements to
``(u_n - u_m) . e_s``, the forces on the particles are ``f + B^T F``, and force balance on the
free particles (the fixed ones do not move) is the linear system

    (B^T K B) u = f + B^T K h_0,          K = diag(k_s),  k_s = k or k_c,

solved again, with the open contacts' ``k_s = k_c``, until no contact opens or closes (an
active-set iteration; the law is one function of ``h``, so a contact whose particles touch
again simply carries ``k h`` again). Unlike the Hertz solid's update, which is linearised
about the current state, this solve is exact: the response is linear while the contacts do
not change.

The throat crossing spring ``s`` has the aperture

    r_s = r_s(0) + sqrt(1 + (1 - h_s / 2)^2) - sqrt(1 + (1 - h_0 / 2)^2),

the integral of the incremental rule ``dr = -dh (1 - eps) / [2 sqrt(1 + (1 - eps)^2)]``,
``eps = h / 2a``, of docs/model.md section 5 (cubic packing of spheres of radius a): the same
geometry as the Hertz solid, in closed form.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from scipy import sparse
from scipy.sparse.linalg import spsolve

from porenet.core.interfaces import Lattice

__all__ = [
    "Network",
    "Solution",
    "aperture",
    "compressions",
    "contact_force",
    "fracturing_number",
    "net_forces",
    "network",
    "pressure_loads",
    "solve",
    "stiffness_for",
]


def stiffness_for(fracturing_number: float, disorder: float) -> float:
    """The contact stiffness ``k = 2 / (lambda N_f)`` (units of gamma) of a fracturing number."""
    return 2.0 / (disorder * fracturing_number)


def fracturing_number(stiffness: float, disorder: float) -> float:
    """``N_f = 2 / (lambda k)`` (``k`` in units of gamma): inverse of :func:`stiffness_for`."""
    return 2.0 / (disorder * stiffness)


def contact_force(h: np.ndarray, stiffness: float, cohesion: float) -> np.ndarray:
    """Normal force (gamma a) of overlaps ``h`` (a): ``k h`` where ``h > 0``, else
    ``cohesion x k x h`` (open contacts)."""
    h = np.asarray(h, dtype=np.float64)
    return np.where(h > 0, stiffness, cohesion * stiffness) * h


def aperture(h: np.ndarray, h0: float, initial: np.ndarray) -> np.ndarray:
    """Aperture (a) of the throat crossing each spring at overlap ``h`` (a), from its aperture
    ``initial`` (a) at the prestrain overlap ``h0`` (module docstring)."""
    h = np.asarray(h, dtype=np.float64)
    change = np.sqrt(1.0 + (1.0 - 0.5 * h) ** 2) - np.sqrt(1.0 + (1.0 - 0.5 * h0) ** 2)
    return initial + change  # the change first: exactly ``initial`` at ``h = h0``


class Network(NamedTuple):
    """The springs and particles of a lattice, as the solver takes them (units of a)."""

    #: (M, 2) int64: the two particles of each spring (one spring per throat).
    springs: np.ndarray
    #: (M, 2P) sparse: ``(B u)_s = (u_n - u_m) . e_s``, u flattened as (x_0, y_0, x_1, ...).
    b: sparse.csr_matrix
    #: (2P,) bool: displacement components that may move (those of the free particles).
    free: np.ndarray
    #: (Q,) int64 and (Q,) int64: each pore-particle contact.
    pair_pore: np.ndarray
    pair_particle: np.ndarray
    #: (Q, 2): unit vector from the pore centre towards the particle.
    pair_direction: np.ndarray


def network(lattice: Lattice) -> Network:
    """The :class:`Network` of ``lattice``, from its public particle description
    (``particle_coords``, ``spring_particles``, ``fixed_particles``, ``pore_particle_pairs``).

    Raises
    ------
    ValueError
        If a spring joins two particles at one position, or a pore sits on a particle.
    """
    xy = np.asarray(lattice.particle_coords, dtype=np.float64)
    springs = np.asarray(lattice.spring_particles, dtype=np.int64)
    m, n = springs[:, 0], springs[:, 1]
    axis = unit(xy[n] - xy[m], "spring")
    rows = np.repeat(np.arange(len(springs)), 4)
    cols = np.stack([2 * n, 2 * n + 1, 2 * m, 2 * m + 1], axis=1).ravel()
    values = np.concatenate([axis, -axis], axis=1).ravel()
    b = sparse.csr_matrix((values, (rows, cols)), shape=(len(springs), 2 * len(xy)))
    fixed = np.asarray(lattice.fixed_particles, dtype=bool)
    pores, particles = (np.asarray(v, dtype=np.int64) for v in lattice.pore_particle_pairs)
    direction = unit(xy[particles] - np.asarray(lattice.pore_coords)[pores], "pore-particle")
    return Network(springs, b, np.repeat(~fixed, 2), pores, particles, direction)


def unit(d: np.ndarray, what: str) -> np.ndarray:
    """Rows of ``d`` divided by their lengths; a row of length 0 is an error."""
    length = np.hypot(d[:, 0], d[:, 1])
    if np.any(length <= 0):
        raise ValueError(f"{what} {int(np.argmin(length))} has zero length")
    return d / length[:, None]


def pressure_loads(net: Network, pore_pressure: np.ndarray, area: float) -> np.ndarray:
    """(2P,) forces (gamma a) of the pore pressures (gamma / a) on the particles: each pore
    pushes each particle it touches with ``p A_p`` (``area`` = A_p / a^2) away from its
    centre."""
    n_particles = net.b.shape[1] // 2
    force = np.zeros((n_particles, 2))
    push = (np.asarray(pore_pressure)[net.pair_pore] * area)[:, None] * net.pair_direction
    np.add.at(force, net.pair_particle, push)
    return force.ravel()


def compressions(net: Network, u: np.ndarray, h0: float) -> np.ndarray:
    """(M,) overlaps ``h = h0 - B u`` (a) of displacements ``u`` ((2P,), a)."""
    return h0 - net.b @ u


class Solution(NamedTuple):
    """A solved state of the springs (:func:`solve`)."""

    #: (2P,) displacements from the prestressed state (a), flattened (x_0, y_0, x_1, ...).
    displacement: np.ndarray
    #: (M,) overlaps (a) and normal forces (gamma a).
    compression: np.ndarray
    force: np.ndarray
    #: (M,) bool: springs in contact (h > 0).
    closed: np.ndarray
    #: Solves done, and whether the contacts stopped changing within ``max_iterations``.
    iterations: int
    settled: bool


def solve(
    net: Network,
    load: np.ndarray,
    h0: float,
    stiffness: float,
    cohesion: float,
    closed: np.ndarray,
    max_iterations: int = 50,
) -> Solution:
    """Force balance on the free particles under ``load`` ((2P,), gamma a), starting from the
    contacts ``closed`` ((M,) bool): solve ``(B^T K B) u = f + B^T K h0`` on the free
    components with scipy's sparse direct solver, update the contacts from the new overlaps,
    repeat until they do not change (module docstring). ``stiffness`` k in gamma,
    ``cohesion`` k_c / k."""
    b_free = net.b[:, net.free]
    closed = np.asarray(closed, dtype=bool).copy()
    u = np.zeros(net.b.shape[1])
    iterations, settled = 0, False
    while iterations < max_iterations:
        iterations += 1
        k = np.where(closed, stiffness, cohesion * stiffness)
        matrix = (b_free.T @ sparse.diags(k) @ b_free).tocsc()
        u[net.free] = spsolve(matrix, load[net.free] + b_free.T @ (k * h0))
        h = compressions(net, u, h0)
        now = h > 0
        if np.array_equal(now, closed):
            settled = True
            break
        closed = now
    h = compressions(net, u, h0)
    return Solution(u, h, contact_force(h, stiffness, cohesion), closed, iterations, settled)


def net_forces(net: Network, load: np.ndarray, force: np.ndarray) -> np.ndarray:
    """(2P,) net force (gamma a) on every particle: ``load`` plus the springs' ``B^T F``."""
    return load + net.b.T @ force
