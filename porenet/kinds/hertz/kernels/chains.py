"""Chains: the mechanics of an axis-aligned spring network, one line of springs at a time.

When every spring lies along x or y (the square lattice), the x and y components of the force
balance decouple (contacts are frictionless, so a spring resists only along its axis), and
every line of springs between two fixed particles is an independent tridiagonal system: a
*chain*. :func:`find_chains` finds them for any such lattice; :func:`solve_chains` solves the
lines whose loads changed by the Thomas algorithm, with the contact iteration of
:mod:`porenet.kinds.hertz.kernels.springs` per line, and applies the result.

Loads are kept up to date lazily (:func:`refresh_loads`): a pore's pressure is passed on to its
particles only when it moved by more than a threshold since it was last passed on, and only
the lines through those particles are solved. With threshold 0 this is exact (every line with
a changed load is solved; the others are in balance and would not move); a positive threshold
is the adaptive coupling's tolerance: each pore's pressure as the solid sees it lags by at most
the threshold.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from porenet.jit.jit import njit
from porenet.kinds.hertz.kernels.springs import (
    IN_CONTACT,
    OPEN,
    REDUCED_RADIUS,
    ApertureMap,
    ContactLaw,
    SpringState,
    Stat,
    apply_spring,
    contact_law,
    next_mode,
)


class Chains(NamedTuple):
    """The lines of springs of an axis-aligned network (:func:`find_chains`).

    Attributes
    ----------
    particle_ptr : ndarray of int64, shape (C+1,)
        Chain c has particles ``chain_particles[particle_ptr[c]:particle_ptr[c+1]]``, in order
        along the line, the first and last fixed.
    chain_particles : ndarray of int64, shape (P,)
    chain_springs : ndarray of int64, shape (P - C,)
        Chain c has springs ``chain_springs[particle_ptr[c]-c : particle_ptr[c+1]-c-1]``;
        spring i joins particles i and i+1 of the chain.
    chain_axis : ndarray of int8, shape (C,)
        0 for a chain along x, 1 along y.
    """

    particle_ptr: np.ndarray
    chain_particles: np.ndarray
    chain_springs: np.ndarray
    chain_axis: np.ndarray


class PoreContacts(NamedTuple):
    """Which particles each pore pushes, and how.

    Attributes
    ----------
    pair_ptr : ndarray of int, shape (N+1,)
        Pore i's particle contacts are ``pair_ptr[i]:pair_ptr[i+1]`` of the two arrays below.
    pair_particle : ndarray of int, shape (P,)
    pair_direction : ndarray of float64, shape (P, 2)
        Unit vector from the pore centre towards the particle.
    area : float
        ``A_p / a**2``.
    """

    pair_ptr: np.ndarray
    pair_particle: np.ndarray
    pair_direction: np.ndarray
    area: float


def find_chains(
    spring_particles: np.ndarray,
    axis: np.ndarray,
    fixed: np.ndarray,
    tolerance: float = 1e-9,
) -> Chains | None:
    """Split an axis-aligned spring network into chains between fixed particles.

    Returns None unless every spring lies along x or y, every free particle has at most two
    springs along each axis, and every line of springs starts and ends at a fixed particle (the
    structure that makes each line an independent tridiagonal system).

    Returns
    -------
    Chains or None
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
    return Chains(*out)


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


def particle_chains(chains: Chains, n_particles: int) -> np.ndarray:
    """(n_particles, 2) int64: the chain through each particle along x (column 0) and y
    (column 1), -1 where none (fixed particles are the ends of several chains: -1 too)."""
    particle_ptr, chain_particles, _, chain_axis = chains
    out = np.full((n_particles, 2), -1, dtype=np.int64)
    for c in range(len(chain_axis)):
        interior = chain_particles[particle_ptr[c] + 1 : particle_ptr[c + 1] - 1]
        out[interior, int(chain_axis[c])] = c
    return out


@njit
def refresh_loads(
    pore_pressure: np.ndarray,
    seen: np.ndarray,
    threshold: float,
    contacts: PoreContacts,
    load: np.ndarray,
    particle_chain: np.ndarray,
    dirty: np.ndarray,
) -> int:
    """Pass on to the particles the pressure of every pore that moved by more than
    ``threshold`` since it was last passed on, and mark the chains through them dirty.

    Parameters
    ----------
    pore_pressure : (N,) float
        Pressure in every pore now (gamma/a).
    seen : (N,) float, in/out
        Pressure each pore's loads were computed with.
    threshold : float
        Largest pressure lag left in place (gamma/a); a negative value refreshes every pore.
    contacts : PoreContacts
    load : (n_particles, 2) float, in/out
        Fluid forces (gamma a), kept equal to those of ``seen``.
    particle_chain : (n_particles, 2) int
        From :func:`particle_chains`.
    dirty : (C,) bool, in/out
        Chains to solve.

    Returns
    -------
    int
        Pores refreshed.
    """
    pair_ptr, pair_particle, pair_direction, area = contacts
    count = 0
    for i in range(seen.shape[0]):
        delta = pore_pressure[i] - seen[i]
        if abs(delta) <= threshold or delta == 0.0:
            continue
        count += 1
        f = delta * area
        for k in range(pair_ptr[i], pair_ptr[i + 1]):
            q = pair_particle[k]
            load[q, 0] += f * pair_direction[k, 0]
            load[q, 1] += f * pair_direction[k, 1]
            for ax in range(2):
                c = particle_chain[q, ax]
                if c >= 0:
                    dirty[c] = True
        seen[i] = pore_pressure[i]
    return count


@njit
def solve_chains(
    chains: Chains,
    particle_coords: np.ndarray,
    load: np.ndarray,
    dirty: np.ndarray,
    springs: SpringState,
    law: ContactLaw,
    displacement: np.ndarray,
    aperture: ApertureMap,
    changed: np.ndarray,
    stats: np.ndarray,
) -> None:
    """Solve the dirty chains (module docstring) and apply the result in place.

    Parameters
    ----------
    chains : Chains
        From :func:`find_chains`.
    particle_coords : (n_particles, 2) float
        Used only to orient each chain.
    load : (n_particles, 2) float
        Fluid forces on the particles (gamma a).
    dirty : (C,) bool, in/out
        Chains to solve; cleared on return.
    springs : SpringState, in/out
        Compressions, forces and modes (``RECONTACT`` is used within an update only).
    law : ContactLaw
        ``k_f`` ties every free particle to its initial position along the chain
        (:mod:`porenet.kinds.hertz.kernels.springs`, "Foundation"); ``max_iterations`` counts
        per chain.
    displacement : (n_particles, 2) float, in/out
        Particle displacements (a).
    aperture : ApertureMap
        As for :func:`porenet.kinds.hertz.kernels.springs.apply_spring`.
    changed : (M,) int64, out
        The throats whose aperture changed, in ``changed[:stats[Stat.CHANGED]]``.
    stats : (len(Stat),) float, out
        By :class:`porenet.kinds.hertz.kernels.springs.Stat`.
    """
    particle_ptr, chain_particles, chain_springs, chain_axis = chains
    h, force, mode = springs
    modulus, cohesion_stiffness, contact_stiffness, k_f, recontact, max_iterations = law
    n_chains = chain_axis.shape[0]
    longest = 0
    for c in range(n_chains):
        longest = max(longest, particle_ptr[c + 1] - particle_ptr[c])
    # the chain's springs gathered once into contiguous scratch (a line along y is strided)
    sl = np.empty(longest, dtype=np.int64)  # spring index
    hl = np.empty(longest)  # compression at the start of the update
    fl = np.empty(longest)  # force at the start of the update
    kh = np.empty(longest)  # Hertz tangent at hl
    k = np.empty(longest)
    b = np.empty(longest)
    local = np.empty(longest, dtype=np.int8)
    fp = np.empty(longest)
    rhs = np.empty(longest)
    cprime = np.empty(longest)
    v = np.zeros(longest)
    worst = 0
    unsettled = 0
    residual = 0.0
    solved = 0
    opened = 0
    n_changed = 0
    largest = 0.0
    finite = True
    for c in range(n_chains):
        if not dirty[c]:
            continue
        dirty[c] = False
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
            s = chain_springs[s0 + i]
            sl[i] = s
            hl[i] = h[s]
            fl[i] = force[s]
            local[i] = mode[s]
        imbalance = 0.0
        for j in range(n_int):
            q = chain_particles[p0 + j + 1]
            fp[j] = (load[q, ax] - k_f * displacement[q, ax]) * d_sign  # fluid + foundation
            imbalance = max(imbalance, abs(fp[j] + fl[j] - fl[j + 1]))
        if imbalance == 0.0:  # in balance: its solution would be 0
            continue
        solved += 1
        for i in range(n_spr):
            kh[i] = 2.0 * modulus * math.sqrt(REDUCED_RADIUS * max(hl[i], 0.0))
        iterations = 0
        while True:
            iterations += 1
            for i in range(n_spr):
                k[i], b[i] = contact_law(
                    local[i], hl[i], fl[i], kh[i], cohesion_stiffness, contact_stiffness
                )
            # Balance at interior particle j+1 (unknown j):
            # (k_j + k_{j+1} + k_f) v_j - k_j v_{j-1} - k_{j+1} v_{j+1} = f_j + b_j - b_{j+1}
            for j in range(n_int):
                rhs[j] = fp[j] + b[j] - b[j + 1]
            if n_int > 0:  # Thomas algorithm (symmetric positive definite: k > 0)
                inv = 1.0 / (k[0] + k[1] + k_f)
                cprime[0] = -k[1] * inv
                rhs[0] = rhs[0] * inv
                for j in range(1, n_int):
                    inv = 1.0 / (k[j] + k[j + 1] + k_f + k[j] * cprime[j - 1])
                    cprime[j] = -k[j + 1] * inv
                    rhs[j] = (rhs[j] + k[j] * rhs[j - 1]) * inv
                v[n_int - 1] = rhs[n_int - 1]
                for j in range(n_int - 2, -1, -1):
                    v[j] = rhs[j] - cprime[j] * v[j + 1]
            change = False
            for i in range(n_spr):
                left = 0.0 if i == 0 else v[i - 1]
                right = 0.0 if i == n_spr - 1 else v[i]
                new_mode = next_mode(local[i], hl[i] + left - right, recontact)
                if new_mode != local[i]:
                    local[i] = new_mode
                    change = True
            if not change:
                break
            if iterations >= max_iterations:
                unsettled += 1
                break
        worst = max(worst, iterations)
        ok = True
        for j in range(n_int):
            ok = ok and math.isfinite(v[j])
        if not ok:
            finite = False
            continue
        # apply: springs (apertures, compressions, forces, modes), then particles
        for i in range(n_spr):
            s = sl[i]
            left = 0.0 if i == 0 else v[i - 1]
            right = 0.0 if i == n_spr - 1 else v[i]
            dh = left - right
            b[i] = b[i] + k[i] * dh  # the new force
            delta = apply_spring(s, dh, b[i], springs, aperture)
            if delta > 0.0:
                changed[n_changed] = s
                n_changed += 1
                largest = max(largest, delta)
            new_mode = OPEN if local[i] == OPEN else IN_CONTACT
            if new_mode != mode[s]:
                opened += 1 if new_mode == OPEN else -1
                mode[s] = new_mode
        for j in range(n_int):
            displacement[chain_particles[p0 + j + 1], ax] += v[j] * d_sign
            residual = max(residual, abs(fp[j] - k_f * v[j] + b[j] - b[j + 1]))
    stats[Stat.ITERATIONS] = worst
    stats[Stat.UNSETTLED] = unsettled
    stats[Stat.RESIDUAL] = residual
    stats[Stat.SOLVED] = solved
    stats[Stat.OPENED] = opened
    stats[Stat.CHANGED] = n_changed
    stats[Stat.LARGEST_CHANGE] = largest
    stats[Stat.FINITE] = 1.0 if finite else 0.0
