"""The mechanics of ``linear.springs`` against hand-computed limits, an independent force
balance, linearity, symmetry and a dense numpy solve written out in this file.

Square lattice of ``n x n`` pores (docs/model.md section 1): particles at the ``(n+1)^2``
nodes ``(2J, 2I)`` (units of a), the outer ring fixed, pore ``(i, j)`` at ``(2j+1, 2i+1)``
pushing its four corner particles at 45 degrees.
"""

from __future__ import annotations

import numpy as np
import pytest
from porenet_linear import springs as sp
from porenet_linear.config import KIND

from porenet.analysis.numbers import modulus_for
from porenet.core.state import State
from porenet.kinds.hertz.kernels.springs import aperture_change, hertz_stiffness
from porenet.simulation import Simulation

NF, DISORDER, PRESTRAIN = 0.5, 0.3, 0.05


def solid(reg, n: int, **fields):
    """The solid of an n x n scene, set up in its prestressed state."""
    scene = {
        "seed": 2,
        "lattice": {"kind": "square", "n": n, "disorder": DISORDER},
        "fluid": {"kind": "invasion-percolation"},
        "solid": {"kind": KIND, "fracturing_number": NF, **fields},
        "classifier": {"kind": "none"},
    }
    sim = Simulation.from_scene(scene, registry=reg)
    state = State.initial(sim.lattice.n_pores, sim.lattice.initial_apertures)
    sim.solid.setup(state)
    return sim.solid, state


def test_stiffness_from_the_fracturing_number_is_the_hertz_prestress_stiffness():
    """N_f = 2 gamma / (lambda k): the linear contact at N_f is as stiff as the Hertz contact
    of the same N_f (Eq. 2) in its prestressed state, K_0 = 2 E* sqrt(R* h_0)."""
    modulus = modulus_for(NF, 1.0, DISORDER, 1.0, PRESTRAIN)  # scaled: gamma = a = 1
    k0 = float(hertz_stiffness(2 * PRESTRAIN, modulus))
    assert sp.stiffness_for(NF, DISORDER) == pytest.approx(k0, rel=1e-14)
    assert sp.fracturing_number(k0, DISORDER) == pytest.approx(NF, rel=1e-14)


def test_no_pressure_no_displacement(reg):
    s, state = solid(reg, 6)
    before = state.apertures.copy()
    changed = s.update(state, np.zeros(state.n_pores))
    assert changed.size == 0
    assert np.all(state.displacement == 0)
    assert np.all(state.spring_compression == 2 * PRESTRAIN)
    np.testing.assert_array_equal(state.spring_force, s.stiffness * 2 * PRESTRAIN)
    np.testing.assert_array_equal(state.apertures, before)


def test_two_free_particles_on_a_line_move_by_the_hand_computed_amounts(reg):
    """n = 3: the free particles are the 2 x 2 inner nodes. A pressure p in pore (0, 0)
    pushes node (1, 1) with f = p A_p (1, 1)/sqrt(2). Along x, row 1 is the chain
    fixed -k- (1,1) -k- (1,2) -k- fixed: [[2k, -k], [-k, 2k]] u = (f_x, 0) gives
    u = (2, 1) f_x / 3k; column 1 likewise along y. Nothing else moves."""
    s, state = solid(reg, 3, pressure_area_factor=0.7)
    p = 0.3
    pressure = np.zeros(9)
    pressure[0] = p
    s.update(state, pressure)
    f = p * 0.7 / np.sqrt(2)
    expected = np.zeros((16, 2))
    expected[5] = 2 * f / (3 * s.stiffness)  # node (1, 1): x and y
    expected[6, 0] = f / (3 * s.stiffness)  # node (1, 2), along its row
    expected[9, 1] = f / (3 * s.stiffness)  # node (2, 1), along its column
    np.testing.assert_allclose(state.displacement, expected, rtol=1e-13, atol=1e-18)


def independent_residual(lattice, pressure, area, force) -> np.ndarray:
    """Net force on each free particle, summed spring by spring and pore by pore."""
    xy = np.asarray(lattice.particle_coords)
    total = np.zeros_like(xy)
    for (m, n), f in zip(lattice.spring_particles, force, strict=True):
        e = (xy[n] - xy[m]) / np.linalg.norm(xy[n] - xy[m])
        total[n] += f * e
        total[m] -= f * e
    pores, particles = lattice.pore_particle_pairs
    centres = np.asarray(lattice.pore_coords)
    for i, q in zip(pores, particles, strict=True):
        d = xy[q] - centres[i]
        total[q] += pressure[i] * area * d / np.linalg.norm(d)
    return total[~np.asarray(lattice.fixed_particles)]


@pytest.mark.parametrize("scale", [0.05, 30.0])  # contacts stay closed / many open
def test_forces_balance_at_every_free_particle_to_round_off(reg, scale):
    s, state = solid(reg, 7, pressure_area_factor=1.3)
    pressure = scale * np.random.default_rng(4).random(state.n_pores)
    s.update(state, pressure)
    opened = np.count_nonzero(state.spring_compression <= 0)
    assert (opened == 0) if scale < 1 else (opened > 5)
    residual = independent_residual(s.lattice, pressure, 1.3, state.spring_force)
    assert np.abs(residual).max() < 1e-12 * s.stiffness * 2 * PRESTRAIN * 10
    assert s.largest_residual < 1e-12 * s.stiffness * 2 * PRESTRAIN * 10
    # the contact law at the solution: contacts where h > 0, only cohesive tension elsewhere
    h, f = state.spring_compression, state.spring_force
    np.testing.assert_allclose(f[h > 0], s.stiffness * h[h > 0], rtol=1e-14)
    np.testing.assert_allclose(f[h <= 0], 1e-6 * s.stiffness * h[h <= 0], rtol=1e-14)


def test_doubling_the_pressure_doubles_the_displacement_while_contacts_hold(reg):
    s, state = solid(reg, 7)
    pressure = 0.05 * np.random.default_rng(5).random(state.n_pores)
    s.update(state, pressure)
    once = state.displacement.copy()
    assert np.all(state.spring_compression > 0) and np.abs(once).max() > 0
    s.update(state, 2 * pressure)
    np.testing.assert_allclose(state.displacement, 2 * once, rtol=1e-10, atol=1e-15)
    # beyond contact loss the response is no longer linear
    s.update(state, 400 * pressure)
    big = state.displacement.copy()
    assert np.any(state.spring_compression <= 0)
    s.update(state, 800 * pressure)
    assert not np.allclose(state.displacement, 2 * big, rtol=1e-3)


@pytest.mark.parametrize("p", [0.1, 20.0])
def test_a_symmetric_load_gives_a_symmetric_displacement(reg, p):
    """Pressure in the centre pore of a 5 x 5 lattice only: the field is mirror symmetric
    about both axes through the centre and about the diagonal."""
    n = 5
    s, state = solid(reg, n)
    pressure = np.zeros(n * n)
    pressure[(n // 2) * n + n // 2] = p
    s.update(state, pressure)
    u = state.displacement.reshape(n + 1, n + 1, 2)  # [I, J, (x, y)]
    assert np.abs(u).max() > 0
    np.testing.assert_allclose(u[:, ::-1, 0], -u[:, :, 0], atol=1e-15)  # mirror x
    np.testing.assert_allclose(u[:, ::-1, 1], u[:, :, 1], atol=1e-15)
    np.testing.assert_allclose(u[::-1, :, 1], -u[:, :, 1], atol=1e-15)  # mirror y
    np.testing.assert_allclose(u.transpose(1, 0, 2)[:, :, ::-1], u, atol=1e-15)  # diagonal
    # the pore pushes its corners outwards: the throats around it open
    corner = u[n // 2 + 1, n // 2 + 1]
    assert corner[0] > 0 and corner[1] > 0


def dense_reference(lattice, pressure, area, k_spring, h0) -> np.ndarray:
    """Force balance assembled densely, spring by spring, and solved with numpy."""
    xy = np.asarray(lattice.particle_coords)
    size = 2 * len(xy)
    matrix, rhs = np.zeros((size, size)), np.zeros(size)
    for (m, n), k in zip(lattice.spring_particles, k_spring, strict=True):
        e = (xy[n] - xy[m]) / np.linalg.norm(xy[n] - xy[m])
        block = k * np.outer(e, e)
        for a, sa in ((m, -1), (n, 1)):
            rhs[2 * a : 2 * a + 2] += sa * k * h0 * e  # the prestress pushes n along e
            for b, sb in ((m, -1), (n, 1)):
                matrix[2 * a : 2 * a + 2, 2 * b : 2 * b + 2] += sa * sb * block
    pores, particles = lattice.pore_particle_pairs
    centres = np.asarray(lattice.pore_coords)
    for i, q in zip(pores, particles, strict=True):
        d = xy[q] - centres[i]
        rhs[2 * q : 2 * q + 2] += pressure[i] * area * d / np.linalg.norm(d)
    free = np.repeat(~np.asarray(lattice.fixed_particles), 2)
    u = np.zeros(size)
    u[free] = np.linalg.solve(matrix[np.ix_(free, free)], rhs[free])
    return u.reshape(-1, 2)


@pytest.mark.parametrize("scale", [0.1, 15.0])
def test_agrees_with_a_dense_solve(reg, scale):
    """With the contacts the solver settled on, the dense solve gives the same displacements,
    and those contacts are the ones with h > 0 (a consistent active set)."""
    s, state = solid(reg, 4)
    pressure = scale * np.random.default_rng(6).random(state.n_pores)
    s.update(state, pressure)
    closed = state.spring_compression > 0
    k = np.where(closed, s.stiffness, 1e-6 * s.stiffness)
    u = dense_reference(s.lattice, pressure, 1.0, k, 2 * PRESTRAIN)
    np.testing.assert_allclose(state.displacement, u, rtol=1e-9, atol=1e-12 * np.abs(u).max())
    assert (scale < 1) == bool(closed.all())


def test_closed_form_aperture_is_the_integral_of_porenets_incremental_rule():
    h = np.linspace(-0.2, 0.3, 11)
    dh = 1e-6
    step = sp.aperture(h + dh, 0.1, np.zeros_like(h)) - sp.aperture(h, 0.1, np.zeros_like(h))
    np.testing.assert_allclose(step, aperture_change(np.full_like(h, dh), h), rtol=1e-5)
    assert sp.aperture(0.1, 0.1, 0.8) == 0.8  # the initial aperture at the prestrain


def test_apertures_are_bounded_and_reported(reg):
    s, state = solid(reg, 5, aperture_cap=1.05)
    pressure = np.full(state.n_pores, 40.0)
    changed = s.update(state, pressure)
    cap = 1.05 * s.lattice.mean_aperture
    assert changed.size > 0 and state.apertures.max() == pytest.approx(cap, rel=1e-15)
    assert s.summary(state)["apertures_at_cap"] == np.count_nonzero(state.apertures >= cap)
