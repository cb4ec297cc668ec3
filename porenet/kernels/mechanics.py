"""Block-and-spring mechanics with Hertzian contacts (MODEL.md section 5).

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

Chains
------
When every spring lies along x or y (the square lattice), x and y decouple and every line of
springs between two fixed particles is an independent tridiagonal system (a *chain*, found by
:func:`find_chains`), solved by the Thomas algorithm in O(N) with the contact iteration done
per chain. Otherwise :func:`solve_sparse` assembles the 2-D stiffness matrix (scipy.sparse) and
solves it with a sparse direct solver.
"""

from __future__ import annotations

import math

import numpy as np

from porenet.kernels._jit import njit

#: R* / a for two equal spheres of radius a.
REDUCED_RADIUS = 0.5

IN_CONTACT, OPEN, RECONTACT = 0, 1, 2


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


def spring_axes(spring_particles: np.ndarray, particle_coords: np.ndarray) -> np.ndarray:
    """(M, 2) unit vectors from each spring's first particle to its second."""
    d = particle_coords[spring_particles[:, 1]] - particle_coords[spring_particles[:, 0]]
    length = np.hypot(d[:, 0], d[:, 1])
    if np.any(length <= 0):
        bad = int(np.flatnonzero(length <= 0)[0])
        raise ValueError(f"spring {bad} joins two particles at the same position")
    return d / length[:, None]


def pore_particle_directions(
    pair_pore: np.ndarray,
    pair_particle: np.ndarray,
    pore_coords: np.ndarray,
    particle_coords: np.ndarray,
) -> np.ndarray:
    """(P, 2) unit vectors from each pore centre towards each particle it touches."""
    d = particle_coords[pair_particle] - pore_coords[pair_pore]
    length = np.hypot(d[:, 0], d[:, 1])
    if np.any(length <= 0):
        bad = int(np.flatnonzero(length <= 0)[0])
        raise ValueError(f"pore {int(pair_pore[bad])} sits on particle {int(pair_particle[bad])}")
    return d / length[:, None]


# -- chains ---------------------------------------------------------------------------------


def find_chains(
    spring_particles: np.ndarray,
    axis: np.ndarray,
    fixed: np.ndarray,
    tolerance: float = 1e-9,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray] | None:
    """Split an axis-aligned spring network into chains between fixed particles.

    Returns None unless every spring lies along x or y, every free particle has at most two
    springs along each axis, and every line of springs starts and ends at a fixed particle (the
    structure that makes each line an independent tridiagonal system).

    Returns
    -------
    particle_ptr : (C+1,) int64
        Chain c has particles ``chain_particles[particle_ptr[c]:particle_ptr[c+1]]``, in order
        along the line, the first and last fixed.
    chain_particles : (P,) int64
    chain_springs : (P - C,) int64
        Chain c has springs ``chain_springs[particle_ptr[c]-c : particle_ptr[c+1]-c-1]``;
        spring i joins particles i and i+1 of the chain.
    chain_axis : (C,) int8
        0 for a chain along x, 1 along y.
    """
    spring_particles = np.asarray(spring_particles, dtype=np.int64)
    along_x = np.abs(axis[:, 1]) <= tolerance * np.abs(axis[:, 0])
    along_y = np.abs(axis[:, 0]) <= tolerance * np.abs(axis[:, 1])
    if not np.all(along_x | along_y):
        return None
    n_particles = len(fixed)
    out = _chains(spring_particles, along_y.astype(np.int8), np.asarray(fixed, bool), n_particles)
    if out[0][0] < 0:
        return None
    return out


@njit
def _chains(
    spring_particles: np.ndarray, spring_axis: np.ndarray, fixed: np.ndarray, n_particles: int
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """:func:`find_chains` on validated arrays; ``particle_ptr[0] = -1`` when not chains."""
    m = spring_particles.shape[0]
    # per particle and axis: up to two springs (slots), -1 empty
    slots = np.full((n_particles, 2, 2), -1, dtype=np.int64)
    bad = np.full(1, -1, dtype=np.int64)
    for s in range(m):
        ax = spring_axis[s]
        for end in range(2):
            q = spring_particles[s, end]
            if slots[q, ax, 0] < 0:
                slots[q, ax, 0] = s
            elif slots[q, ax, 1] < 0:
                slots[q, ax, 1] = s
            elif not fixed[q]:
                return bad, bad, bad, spring_axis[:0]
    used = np.zeros(m, dtype=np.bool_)
    particle_ptr = np.zeros(m + 1, dtype=np.int64)
    chain_particles = np.empty(2 * m, dtype=np.int64)
    chain_springs = np.empty(m, dtype=np.int64)
    chain_axis = np.empty(m, dtype=np.int8)
    n_chains = 0
    n_p = 0
    n_s = 0
    for start in range(m):
        if used[start]:
            continue
        # walk back from spring `start` to a fixed end, then forward to the other one
        s = start
        q = spring_particles[s, 0]
        ax = spring_axis[s]
        steps = 0
        while not fixed[q]:
            nxt = slots[q, ax, 0] if slots[q, ax, 0] != s else slots[q, ax, 1]
            if nxt < 0 or steps > m:
                return bad, bad, bad, spring_axis[:0]  # a free end, or a ring of free particles
            s = nxt
            q = spring_particles[s, 0] if spring_particles[s, 1] == q else spring_particles[s, 1]
            steps += 1
        # q is fixed and s its spring on this line: walk forward to the next fixed particle
        chain_particles[n_p] = q
        n_p += 1
        while True:
            used[s] = True
            chain_springs[n_s] = s
            n_s += 1
            q = spring_particles[s, 0] if spring_particles[s, 1] == q else spring_particles[s, 1]
            chain_particles[n_p] = q
            n_p += 1
            if fixed[q]:
                break
            nxt = slots[q, ax, 0] if slots[q, ax, 0] != s else slots[q, ax, 1]
            if nxt < 0:
                return bad, bad, bad, spring_axis[:0]
            s = nxt
        chain_axis[n_chains] = ax
        n_chains += 1
        particle_ptr[n_chains] = n_p
    return (
        particle_ptr[: n_chains + 1].copy(),
        chain_particles[:n_p].copy(),
        chain_springs[:n_s].copy(),
        chain_axis[:n_chains].copy(),
    )


@njit
def solve_chains(
    particle_ptr: np.ndarray,
    chain_particles: np.ndarray,
    chain_springs: np.ndarray,
    chain_axis: np.ndarray,
    particle_coords: np.ndarray,
    load: np.ndarray,
    h: np.ndarray,
    force: np.ndarray,
    mode: np.ndarray,
    modulus: float,
    cohesion_stiffness: float,
    contact_stiffness: float,
    recontact: bool,
    max_iterations: int,
    displacement: np.ndarray,
    dh: np.ndarray,
    force_new: np.ndarray,
) -> tuple[int, int]:
    """One mechanical update on chains (see the module docstring), contacts iterated per chain.

    Parameters
    ----------
    particle_ptr, chain_particles, chain_springs, chain_axis
        From :func:`find_chains`.
    particle_coords : (n_particles, 2) float
        Used only to orient each spring along its chain.
    load : (n_particles, 2) float
        Fluid forces on the particles (:func:`pressure_loads`), gamma a.
    h, force : (M,) float
        Compression (a) and force (gamma a) of each spring at the start of the update.
    mode : (M,) int8, in/out
        ``IN_CONTACT`` or ``OPEN`` at the start; the final modes on return (``RECONTACT``
        springs are returned as ``IN_CONTACT``).
    modulus, cohesion_stiffness, contact_stiffness : float
        ``E*`` (gamma/a), ``k_c`` and ``K_0`` (gamma).
    recontact : bool
        Whether an open spring may close again.
    max_iterations : int
        Most contact iterations per chain.
    displacement : (n_particles, 2) float, out
        Displacement increments (a); component along each chain's axis written.
    dh, force_new : (M,) float, out
        Compression change and new force of every spring of a chain.

    Returns
    -------
    iterations : int
        Largest number of solves any chain needed.
    unsettled : int
        Number of chains whose contacts still changed after ``max_iterations`` solves.
    """
    n_chains = chain_axis.shape[0]
    longest = 0
    for c in range(n_chains):
        longest = max(longest, particle_ptr[c + 1] - particle_ptr[c])
    k = np.empty(longest)
    b = np.empty(longest)
    local = np.empty(longest, dtype=np.int8)
    rhs = np.empty(longest)
    cprime = np.empty(longest)
    v = np.zeros(longest)
    worst = 0
    unsettled = 0
    for c in range(n_chains):
        p0 = particle_ptr[c]
        n_part = particle_ptr[c + 1] - p0
        n_spr = n_part - 1
        n_int = n_part - 2
        s0 = p0 - c
        ax = chain_axis[c]
        # v: displacement along the chain's direction d, from its first particle to its last.
        # Spring i joins chain particles i and i+1 and compresses by dh_i = v_i - v_{i+1}
        # whichever way it is oriented; its force pushes particle i+1 along +d.
        q_first = chain_particles[p0]
        q_second = chain_particles[p0 + 1]
        d_sign = 1.0 if particle_coords[q_second, ax] > particle_coords[q_first, ax] else -1.0
        for i in range(n_spr):
            local[i] = mode[chain_springs[s0 + i]]
        iterations = 0
        while True:
            iterations += 1
            for i in range(n_spr):
                s = chain_springs[s0 + i]
                if local[i] == IN_CONTACT:
                    k[i] = 2.0 * modulus * math.sqrt(REDUCED_RADIUS * max(h[s], 0.0))
                    b[i] = force[s]
                elif local[i] == OPEN:
                    k[i] = cohesion_stiffness
                    b[i] = cohesion_stiffness * h[s]
                else:
                    k[i] = contact_stiffness
                    b[i] = contact_stiffness * h[s]
            # Balance at interior particle j+1 (unknown j):
            # (k_j + k_{j+1}) v_j - k_j v_{j-1} - k_{j+1} v_{j+1} = f_j + b_j - b_{j+1}
            for j in range(n_int):
                q = chain_particles[p0 + j + 1]
                rhs[j] = load[q, ax] * d_sign + b[j] - b[j + 1]
            if n_int > 0:  # Thomas algorithm (symmetric positive definite: k > 0)
                diag = k[0] + k[1]
                cprime[0] = -k[1] / diag
                rhs[0] = rhs[0] / diag
                for j in range(1, n_int):
                    diag = k[j] + k[j + 1] + k[j] * cprime[j - 1]
                    cprime[j] = -k[j + 1] / diag
                    rhs[j] = (rhs[j] + k[j] * rhs[j - 1]) / diag
                v[n_int - 1] = rhs[n_int - 1]
                for j in range(n_int - 2, -1, -1):
                    v[j] = rhs[j] - cprime[j] * v[j + 1]
            changed = False
            for i in range(n_spr):
                s = chain_springs[s0 + i]
                left = 0.0 if i == 0 else v[i - 1]
                right = 0.0 if i == n_spr - 1 else v[i]
                h_new = h[s] + left - right
                if local[i] != OPEN and h_new <= 0.0:
                    local[i] = OPEN
                    changed = True
                elif local[i] == OPEN and recontact and h_new > 0.0:
                    local[i] = RECONTACT
                    changed = True
            if not changed:
                break
            if iterations >= max_iterations:
                unsettled += 1
                break
        worst = max(worst, iterations)
        for i in range(n_spr):
            s = chain_springs[s0 + i]
            left = 0.0 if i == 0 else v[i - 1]
            right = 0.0 if i == n_spr - 1 else v[i]
            dh[s] = left - right
            force_new[s] = b[i] + k[i] * dh[s]
            mode[s] = OPEN if local[i] == OPEN else IN_CONTACT
        for j in range(n_int):
            displacement[chain_particles[p0 + j + 1], ax] = v[j] * d_sign
    return worst, unsettled


# -- any lattice: sparse direct solve -------------------------------------------------------


def _mode_laws(
    h: np.ndarray,
    force: np.ndarray,
    mode: np.ndarray,
    modulus: float,
    cohesion_stiffness: float,
    contact_stiffness: float,
) -> tuple[np.ndarray, np.ndarray]:
    """Stiffness ``k`` and force at ``dh = 0`` ``b`` of each spring's linear law (module doc)."""
    k = np.where(mode == IN_CONTACT, hertz_stiffness(h, modulus), cohesion_stiffness)
    b = np.where(mode == IN_CONTACT, force, cohesion_stiffness * h)
    recontact = mode == RECONTACT
    k[recontact] = contact_stiffness
    b[recontact] = contact_stiffness * h[recontact]
    return k, b


def solve_sparse(
    spring_particles: np.ndarray,
    axis: np.ndarray,
    fixed: np.ndarray,
    load: np.ndarray,
    h: np.ndarray,
    force: np.ndarray,
    mode: np.ndarray,
    modulus: float,
    cohesion_stiffness: float,
    contact_stiffness: float,
    recontact: bool,
    max_iterations: int,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, int, int]:
    """One mechanical update on any spring network: the same laws and contact iteration as
    :func:`solve_chains`, with the 2-D stiffness matrix of the free particles assembled in
    scipy.sparse and factorised by SuperLU at each contact iteration.

    Parameters are those of :func:`solve_chains` plus ``axis`` ((M, 2) unit vectors,
    :func:`spring_axes`) and ``fixed`` ((n_particles,) bool). ``mode`` is updated in place.

    Returns
    -------
    displacement : (n_particles, 2) float
    dh, force_new : (M,) float
    iterations, unsettled : int
        Solves done, and 1 if the contacts still changed after ``max_iterations`` solves.
    """
    from scipy.sparse import coo_matrix
    from scipy.sparse.linalg import splu

    n_particles = fixed.shape[0]
    dof = np.full((n_particles, 2), -1, dtype=np.int64)
    free = np.flatnonzero(~fixed)
    dof[free] = np.arange(2 * free.size).reshape(-1, 2)
    m_idx, n_idx = spring_particles[:, 0], spring_particles[:, 1]
    local = mode.copy()
    du = np.zeros((n_particles, 2))
    iterations, unsettled = 0, 0
    while True:
        iterations += 1
        k, b = _mode_laws(h, force, local, modulus, cohesion_stiffness, contact_stiffness)
        rhs_full = load.copy()
        add_spring_loads(b, spring_particles, axis, rhs_full)
        rows, cols, vals = [], [], []
        for a in range(2):
            for c in range(2):
                kee = k * axis[:, a] * axis[:, c]
                for p, q, sgn in ((m_idx, m_idx, 1.0), (n_idx, n_idx, 1.0),
                                  (m_idx, n_idx, -1.0), (n_idx, m_idx, -1.0)):  # fmt: skip
                    rows.append(dof[p, a])
                    cols.append(dof[q, c])
                    vals.append(sgn * kee)
        r, c_, v = np.concatenate(rows), np.concatenate(cols), np.concatenate(vals)
        keep = (r >= 0) & (c_ >= 0)
        size = 2 * free.size
        matrix = coo_matrix((v[keep], (r[keep], c_[keep])), shape=(size, size)).tocsc()
        x = splu(matrix).solve(rhs_full[free].ravel())
        du[:] = 0.0
        du[free] = x.reshape(-1, 2)
        dh = -np.einsum("ij,ij->i", du[n_idx] - du[m_idx], axis)
        h_new = h + dh
        opening = (local != OPEN) & (h_new <= 0.0)
        closing = (local == OPEN) & (h_new > 0.0) if recontact else np.zeros_like(opening)
        if not (opening.any() or closing.any()):
            break
        if iterations >= max_iterations:
            unsettled = 1
            break
        local[opening] = OPEN
        local[closing] = RECONTACT
    mode[:] = np.where(local == OPEN, OPEN, IN_CONTACT)
    return du, dh, b + k * dh, iterations, unsettled


def balance_residual(
    load: np.ndarray,
    force: np.ndarray,
    spring_particles: np.ndarray,
    axis: np.ndarray,
    fixed: np.ndarray,
) -> float:
    """Largest net force on a free particle (gamma a): fluid ``load`` plus contact forces."""
    total = load.copy()
    add_spring_loads(force, spring_particles, axis, total)
    free = ~fixed
    return float(np.max(np.abs(total[free]))) if free.any() else 0.0
