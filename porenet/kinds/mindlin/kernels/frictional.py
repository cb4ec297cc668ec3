"""Frictional contacts: the Hertz normal law with a tangential (Mindlin) stiffness and Coulomb
sliding (docs/model.md, "Frictional solid (kind hertz-mindlin)").

Pure functions on arrays in the scaled units of :mod:`porenet.kinds.hertz.kernels.springs`
(lengths by ``a``, forces by ``gamma a``, stiffnesses by ``gamma``).

A contact between particles ``m`` and ``n`` (unit vector ``e`` from ``m`` to ``n``, tangent
``t = z x e``) carries the normal force ``F`` of the Hertzian solid (compression ``h``, the same
modes and laws as :mod:`porenet.kinds.hertz.kernels.springs`) and a tangential force ``S``, the
force on ``n`` along ``t`` (``-S t`` on ``m``). The relative tangential displacement of the
contact point is

    ``d_t = (u_n - u_m) . t - l (theta_m + theta_n)``,

``l = 1`` (the contact point halfway between the centres, one pore size ``a`` from each) and
``theta`` the particles' rotations (0 where rotations are held). In an update, each contact
follows a linear law in the increments of ``h`` and ``d_t``:

====================  ==========================  =================================
contact               normal ``F_new``            tangential ``S_new``
====================  ==========================  =================================
in contact, sticking  ``F + K dh``                ``S - K_t dd_t``, ``K_t = r_t K``
in contact, sliding   ``F + K dh``                ``s mu F (- k_c dd_t)``
open                  ``k_c h + k_c dh``          ``S_o - k_c dd_t``
re-forming            ``K_0 h + K_0 dh``          ``- r_t K_0 dd_t``
====================  ==========================  =================================

``K = 2 E* sqrt(R* h)`` is the Hertz tangent and ``F`` the normal force at the start of the
update, ``r_t = K_t / K_n`` the stiffness ratio, ``k_c`` the cohesive stiffness (on a sliding
contact only where particles rotate: a rotation needs it to stay solvable) and ``s`` the
sliding direction. A contact that opens loses both
stiffnesses and its tangential force (``S_o`` is ``S`` for a contact already open at the
start of the update, else 0): the cohesive springs keep a particle without contacts solvable.

Coulomb's law (``friction`` ``mu`` finite): after each solve a contact in contact sticks if
the sticking law's trial force ``|S - K_t dd_t| <= mu F``, else it slides in the trial force's
direction with ``|S_new| = mu F`` (the return mapping of elastoplasticity); the slip
``(S_trial - S_new) / K_t`` accumulates. The cap ``mu F`` is taken at the normal force of the
start of the update (Tresca's law within an update: every solve stays symmetric and the
problem convex); a contact whose normal force then fell below ``|S| / mu`` slides at the next
update, the force it sheds carried as an imbalance like any other. The update is solved again
until no contact changes mode (:func:`next_modes`): a sliding contact whose trial force is no
longer beyond the cap on its side sticks (it never jumps to sliding the other way). A change
between sticking and sliding that moves the contact's tangential force by at most ``K_t delta``
(``delta`` the law's ``slip_tolerance``, in a) takes effect without another solve: the
contact's force follows its new law when the update is applied (at the cap if it slides, its
trial force if it sticks), so Coulomb's law holds at every contact and the force left out of
balance, at most ``K_t delta`` a contact, is carried to the next update; near the cap the
solves' own error (``solver_tolerance``) would otherwise flip such contacts back and forth. A
contact that changed mode :data:`MAX_FLIPS` times in one update keeps its mode for the rest of
it: shear couples the contacts, and the paper's incremental law (whose force is discontinuous
where a contact opens) can make the iteration cycle between two sets of open contacts. One that
kept opening and closing sits at ``h = 0`` and keeps the re-forming law (force ``K_0 h``, zero
there, stiff both ways; open if re-contact is off): frozen open, a contact under a load many
times the prestress let its particles pass through each other by 1e4 a in one update
(docs/stability.md, "Frictional contacts"), and a contact left in contact at ``h <= 0`` starts
the next update re-forming (:func:`start_update`). The force the frozen contacts leave out
of balance is carried to the next update and the update counted as unsettled only if the
iteration still had not settled after ``max_iterations``. With ``mu`` infinite no contact
slides.

Forces on the particles (:func:`out_of_balance`): ``F e + S t`` on ``n`` and its opposite on
``m``; with rotations, the torque ``-l S`` on both (the contact point sits at ``-l e`` from
``n``'s centre and ``+l e`` from ``m``'s).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from porenet.jit.jit import njit
from porenet.kinds.hertz.kernels.springs import (
    IN_CONTACT,
    OPEN,
    RECONTACT,
    REDUCED_RADIUS,
    ApertureMap,
    SpringState,
    apply_spring_lagged,
    next_mode,
)

#: Lever arm of a contact force about a particle's centre (units of a).
LEVER = 1.0

#: Tangential modes of a contact in contact.
STICK, SLIDE = 0, 1

#: Changes of mode after which a contact keeps its mode for the rest of an update (one that
#: kept opening and closing keeps the re-forming law).
MAX_FLIPS = 4


class ShearState(NamedTuple):
    """The tangential side of the contacts (scaled units).

    Attributes
    ----------
    force : ndarray of float64, shape (M,)
        ``S``: the tangential force on each spring's second particle, along ``t = z x e``
        (gamma a).
    slip : ndarray of float64, shape (M,)
        Sliding of the second particle against the first along ``t`` accumulated (a),
        signed; friction opposes it, so each increment has the sign of ``-S`` (the energy
        dissipated, ``-S d(slip)``, is never negative).
    mode : ndarray of int8, shape (M,)
        :data:`STICK` or :data:`SLIDE` (as left by the last update).
    direction : ndarray of float64, shape (M,)
        ``+1`` or ``-1``: the direction of ``S`` while sliding.
    """

    force: np.ndarray
    slip: np.ndarray
    mode: np.ndarray
    direction: np.ndarray


class FrictionLaw(NamedTuple):
    """The contact laws of an update (module docstring).

    Attributes
    ----------
    modulus : float
        ``E*`` (gamma / a).
    cohesion_stiffness, contact_stiffness, foundation_stiffness : float
        ``k_c``, ``K_0`` and ``k_f`` (gamma).
    recontact : bool
        Whether an open contact may close again.
    stiffness_ratio : float
        ``K_t / K_n`` (-).
    friction : float
        Coulomb's ``mu`` (-); ``inf``: no sliding.
    rotation : bool
        Whether the particles rotate (else their rotations are held at 0).
    max_iterations : int
        Most solves per update while contacts change mode.
    slip_tolerance : float
        ``delta`` (a): a contact whose change between sticking and sliding moves its
        tangential force by at most ``K_t delta`` changes mode without another solve (module
        docstring); 0: every change is solved again.
    """

    modulus: float
    cohesion_stiffness: float
    contact_stiffness: float
    foundation_stiffness: float
    recontact: bool
    stiffness_ratio: float
    friction: float
    rotation: bool
    max_iterations: int
    slip_tolerance: float


class Increments(NamedTuple):
    """An update's trial laws and solution, per spring (module docstring's table).

    Attributes
    ----------
    normal_stiffness, normal_base : ndarray of float64, shape (M,)
        ``F_new = normal_base + normal_stiffness * dh``.
    shear_stiffness, shear_base : ndarray of float64, shape (M,)
        ``S_new = shear_base - shear_stiffness * dd_t``.
    normal_mode : ndarray of int8, shape (M,)
        The normal mode within the update (``RECONTACT`` allowed).
    shear_mode : ndarray of int8, shape (M,)
    flips : ndarray of int8, shape (M,)
        Changes of mode (normal or tangential) within the update.
    compression, tangential : ndarray of float64, shape (M,)
        The solved ``dh`` and ``dd_t``.
    """

    normal_stiffness: np.ndarray
    normal_base: np.ndarray
    shear_stiffness: np.ndarray
    shear_base: np.ndarray
    normal_mode: np.ndarray
    shear_mode: np.ndarray
    flips: np.ndarray
    compression: np.ndarray
    tangential: np.ndarray


def increments(m: int) -> Increments:
    """Empty :class:`Increments` for ``m`` springs."""
    z = np.zeros
    return Increments(
        z(m), z(m), z(m), z(m), z(m, np.int8), z(m, np.int8), z(m, np.int8), z(m), z(m)
    )


@njit(helper=True)
def _hertz_tangent(h: float, modulus: float) -> float:
    return 2.0 * modulus * math.sqrt(REDUCED_RADIUS * h) if h > 0.0 else 0.0


@njit
def start_update(
    springs: SpringState, shear: ShearState, law: FrictionLaw, work: Increments
) -> int:
    """Begin an update: the modes of every contact as the last update left them, except that
    a contact left in contact at ``h <= 0`` (by a contact frozen at its kink, or an unsettled
    update) re-forms, where re-contact is allowed: it has no Hertz tangent, and with the
    cohesive stiffness alone a load could push its particles through each other. Returns how
    many contacts start re-forming so."""
    reforming = 0
    for s in range(springs.mode.shape[0]):
        work.normal_mode[s] = springs.mode[s]
        work.shear_mode[s] = shear.mode[s]
        if springs.mode[s] == IN_CONTACT and springs.compression[s] <= 0.0 and law.recontact:
            work.normal_mode[s] = RECONTACT
            work.shear_mode[s] = STICK
            reforming += 1
        work.flips[s] = 0
        work.compression[s] = 0.0
        work.tangential[s] = 0.0
    return reforming


@njit
def trial_laws(springs: SpringState, shear: ShearState, law: FrictionLaw, work: Increments) -> None:
    """Every contact's linear laws in its current modes (module docstring's table)."""
    h, force, start_mode = springs.compression, springs.force, springs.mode
    k_c, k_0, ratio = law.cohesion_stiffness, law.contact_stiffness, law.stiffness_ratio
    for s in range(h.shape[0]):
        mode = work.normal_mode[s]
        if mode == IN_CONTACT:
            # at least k_c: a contact left at h <= 0 by an unsettled update has no Hertz tangent
            tangent = max(_hertz_tangent(h[s], law.modulus), k_c)
            work.normal_stiffness[s] = tangent
            work.normal_base[s] = force[s]
            # the laws of _slide_law and _stick_law, written out: called from this loop over
            # every contact they were not optimised into it (3.4x slower on 320 000 contacts;
            # docs/performance.md, "Where the time goes and what was done", on helpers)
            if work.shear_mode[s] == SLIDE:
                # held rotations: each particle keeps its normal springs, no regularisation
                work.shear_stiffness[s] = k_c if law.rotation else 0.0
                work.shear_base[s] = shear.direction[s] * law.friction * max(force[s], 0.0)
            else:
                work.shear_stiffness[s] = ratio * tangent
                work.shear_base[s] = shear.force[s]
        elif mode == OPEN:
            work.normal_stiffness[s] = k_c
            work.normal_base[s] = k_c * h[s]
            work.shear_stiffness[s] = k_c
            work.shear_base[s] = shear.force[s] if start_mode[s] == OPEN else 0.0
        else:  # re-forming at h = 0
            work.normal_stiffness[s] = k_0
            work.normal_base[s] = k_0 * h[s]
            work.shear_stiffness[s] = ratio * k_0
            work.shear_base[s] = 0.0


@njit
def out_of_balance(
    load: np.ndarray,
    displacement: np.ndarray,
    spring_particles: np.ndarray,
    axis: np.ndarray,
    normal_force: np.ndarray,
    shear_force: np.ndarray,
    foundation_stiffness: float,
    force_out: np.ndarray,
    torque_out: np.ndarray,
) -> None:
    """The net force (``force_out``, (n_particles, 2)) and torque (``torque_out``,
    (n_particles,)) on every particle: fluid ``load``, the foundation's ``-k_f u`` and the
    contacts' ``normal_force`` ``F`` and ``shear_force`` ``S`` (module docstring)."""
    for q in range(force_out.shape[0]):
        force_out[q, 0] = load[q, 0] - foundation_stiffness * displacement[q, 0]
        force_out[q, 1] = load[q, 1] - foundation_stiffness * displacement[q, 1]
        torque_out[q] = 0.0
    for s in range(spring_particles.shape[0]):
        m, n = spring_particles[s, 0], spring_particles[s, 1]
        ex, ey = axis[s, 0], axis[s, 1]
        fx = normal_force[s] * ex - shear_force[s] * ey  # t = (-e_y, e_x)
        fy = normal_force[s] * ey + shear_force[s] * ex
        force_out[n, 0] += fx
        force_out[n, 1] += fy
        force_out[m, 0] -= fx
        force_out[m, 1] -= fy
        torque = -LEVER * shear_force[s]
        torque_out[n] += torque
        torque_out[m] += torque


@njit
def solved_increments(
    spring_particles: np.ndarray,
    axis: np.ndarray,
    du: np.ndarray,
    rotation: np.ndarray,
    work: Increments,
) -> None:
    """``dh = -(du_n - du_m) . e`` and ``dd_t = (du_n - du_m) . t - l (dtheta_m + dtheta_n)``
    of every spring, from the particles' increments ``du`` ((n_particles, 2)) and
    ``rotation`` ((n_particles,), zeros where rotations are held)."""
    for s in range(spring_particles.shape[0]):
        m, n = spring_particles[s, 0], spring_particles[s, 1]
        dx = du[n, 0] - du[m, 0]
        dy = du[n, 1] - du[m, 1]
        work.compression[s] = -(dx * axis[s, 0] + dy * axis[s, 1])
        work.tangential[s] = (-dx * axis[s, 1] + dy * axis[s, 0]
                              - LEVER * (rotation[m] + rotation[n]))  # fmt: skip


@njit
def next_modes(
    springs: SpringState, shear: ShearState, law: FrictionLaw, work: Increments, commit: bool
) -> int:
    """After a solve: every contact's next modes (module docstring), written into ``work``
    (and the sliding directions into ``shear``) if ``commit``. Returns how many contacts
    change mode (0: the update is settled). Without ``commit`` nothing is written: the last
    solve's modes stay those the update is applied with."""
    h, force = springs.compression, springs.force
    changed = 0
    slides = math.isfinite(law.friction)
    for s in range(h.shape[0]):
        if work.flips[s] >= MAX_FLIPS:
            continue  # frozen for the rest of the update
        mode = work.normal_mode[s]
        new = next_mode(mode, h[s] + work.compression[s], law.recontact)
        if new != mode:
            if commit:
                work.flips[s] += 1
                if work.flips[s] >= MAX_FLIPS and law.recontact:
                    # it keeps opening and closing: it sits at h = 0, and keeps the re-forming
                    # law (zero force there, stiff both ways) for the rest of the update
                    new = RECONTACT
                work.normal_mode[s] = new
                work.shear_mode[s] = STICK
            changed += 1
            continue
        if mode != IN_CONTACT or not slides:
            continue
        cap = law.friction * max(force[s], 0.0)
        tangent = max(_hertz_tangent(h[s], law.modulus), law.cohesion_stiffness)
        stick = law.stiffness_ratio * tangent
        trial = shear.force[s] - stick * work.tangential[s]
        # a change that moves the contact's force by at most K_t delta (the slip it decides
        # is at most delta) takes effect without another solve: its force follows the new
        # mode's law in apply_increments, the difference carried as an imbalance
        band = stick * law.slip_tolerance
        if work.shear_mode[s] == SLIDE:
            # slides on while the trial force stays beyond the cap on its side (the slip goes
            # against the force); otherwise it sticks (never straight to the other side)
            along = shear.direction[s] * trial
            if along <= cap:
                if commit:
                    work.shear_mode[s] = STICK
                    work.flips[s] += 1
                    if along > cap - band:
                        _stick_law(s, shear, stick, work)
                        continue
                changed += 1
        elif abs(trial) > cap:
            if commit:
                work.shear_mode[s] = SLIDE
                shear.direction[s] = 1.0 if trial > 0.0 else -1.0
                work.flips[s] += 1
                if abs(trial) <= cap + band:
                    _slide_law(s, shear, law, cap, work)
                    continue
            changed += 1
    return changed


@njit(helper=True)
def _stick_law(s: int, shear: ShearState, stick: float, work: Increments) -> None:
    """Contact ``s``'s sticking law (:func:`trial_laws`), set without another solve."""
    work.shear_stiffness[s] = stick
    work.shear_base[s] = shear.force[s]


@njit(helper=True)
def _slide_law(s: int, shear: ShearState, law: FrictionLaw, cap: float, work: Increments) -> None:
    """Contact ``s``'s sliding law (:func:`trial_laws`), set without another solve."""
    work.shear_stiffness[s] = law.cohesion_stiffness if law.rotation else 0.0
    work.shear_base[s] = shear.direction[s] * cap


@njit
def apply_increments(
    springs: SpringState,
    shear: ShearState,
    law: FrictionLaw,
    work: Increments,
    du: np.ndarray,
    rotation_increment: np.ndarray,
    displacement: np.ndarray,
    rotation: np.ndarray,
    aperture: ApertureMap,
    changed: np.ndarray,
    aperture_lag: float,
) -> tuple[int, float, int, int, bool]:
    """Apply a settled update in place: the springs' compressions, normal forces and
    apertures (:func:`porenet.kinds.hertz.kernels.springs.apply_spring_lagged`: the fluid's
    aperture follows once it is ``aperture_lag`` behind), the tangential forces, modes and
    slip, and the particles' displacements and rotations.

    Returns
    -------
    n_changed : int
        Throats whose aperture changed, listed first in ``changed``.
    largest_change : float
        Largest aperture change (a).
    opened : int
        Contacts open after the update minus before.
    sliding : int
        Contacts sliding after the update.
    finite : bool
        False if a non-finite value appeared (nothing is applied then).
    """
    m = springs.compression.shape[0]
    for s in range(m):
        if not (math.isfinite(work.compression[s]) and math.isfinite(work.tangential[s])):
            return 0, 0.0, 0, 0, False
    for q in range(du.shape[0]):
        if not (math.isfinite(du[q, 0]) and math.isfinite(du[q, 1])
                and math.isfinite(rotation_increment[q])):  # fmt: skip
            return 0, 0.0, 0, 0, False
    n_changed, largest, opened, sliding = 0, 0.0, 0, 0
    for s in range(m):
        dh, dt = work.compression[s], work.tangential[s]
        mode = work.normal_mode[s]
        f_new = work.normal_base[s] + work.normal_stiffness[s] * dh
        if mode == OPEN:
            s_new = work.shear_base[s] - work.shear_stiffness[s] * dt
            if springs.mode[s] != OPEN:
                opened += 1
        else:
            if springs.mode[s] == OPEN:
                opened -= 1
            s_new = work.shear_base[s] - work.shear_stiffness[s] * dt
            if work.shear_mode[s] == SLIDE:  # s_new: s mu F, and the cohesive k_c dd_t
                stick = law.stiffness_ratio * work.normal_stiffness[s]
                trial = shear.force[s] - stick * dt
                if stick > 0.0:
                    shear.slip[s] += (s_new - trial) / stick
                sliding += 1
        shear.force[s] = s_new
        shear.mode[s] = work.shear_mode[s] if mode == IN_CONTACT else STICK
        if dh != 0.0 or f_new != springs.force[s]:
            change = apply_spring_lagged(s, dh, f_new, springs, aperture, aperture_lag)
            if change > 0.0:
                changed[n_changed] = s
                n_changed += 1
                largest = max(largest, change)
        springs.mode[s] = OPEN if mode == OPEN else IN_CONTACT
    for q in range(du.shape[0]):
        displacement[q, 0] += du[q, 0]
        displacement[q, 1] += du[q, 1]
        rotation[q] += rotation_increment[q]
    return n_changed, largest, opened, sliding, True


@njit
def largest_imbalance(
    force: np.ndarray, torque: np.ndarray, fixed: np.ndarray, rotation: bool
) -> float:
    """Largest net force (or torque per lever arm, where particles rotate) on a free
    particle, from :func:`out_of_balance` (gamma a)."""
    largest = 0.0
    for q in range(fixed.shape[0]):
        if fixed[q]:
            continue
        largest = max(largest, abs(force[q, 0]), abs(force[q, 1]))
        if rotation:
            largest = max(largest, abs(torque[q]) / LEVER)
    return largest


@njit
def stored_energy(springs: SpringState, shear: ShearState, law: FrictionLaw) -> tuple[float, float]:
    """Elastic energy stored in the contacts (gamma a^2): the Hertz normal energy
    ``(2/5) F h`` and the tangential ``S^2 / (2 K_t)`` of the contacts in contact."""
    normal, tangential = 0.0, 0.0
    for s in range(springs.compression.shape[0]):
        if springs.mode[s] == OPEN:
            continue
        h = springs.compression[s]
        normal += 0.4 * springs.force[s] * max(h, 0.0)
        k_t = law.stiffness_ratio * _hertz_tangent(h, law.modulus)
        if k_t > 0.0:
            tangential += shear.force[s] ** 2 / (2.0 * k_t)
    return normal, tangential
