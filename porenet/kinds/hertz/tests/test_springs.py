"""The block-and-spring kernels: Hertz laws, force balance, symmetry, solvers, contact loss."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from porenet.kinds.hertz.kernels import chains as ck
from porenet.kinds.hertz.kernels import springs as mk
from porenet.kinds.square.model import SquareLattice, SquareLatticeConfig

MODULUS = 4.47  # E* a / gamma at N_f = 10, lambda = 0.1, eps_0 = 0.05
H0 = 0.1


class Network:
    """The square lattice's solid network, optionally rotated (then no chains exist)."""

    def __init__(self, n: int, angle: float = 0.0) -> None:
        lat = SquareLattice(SquareLatticeConfig(n=n, disorder=0.1), np.random.default_rng(0))
        c, s = np.cos(angle), np.sin(angle)
        rot = np.array([[c, -s], [s, c]])
        self.n = n
        self.xy = lat.particle_coords @ rot.T
        self.pore_xy = lat.pore_coords @ rot.T
        self.springs = lat.spring_particles
        self.fixed = lat.fixed_particles  # the ring, from the unrotated lattice
        self.axis = mk.spring_axes(self.springs, self.xy)
        self.pair_pore, self.pair_particle = lat.pore_particle_pairs
        self.dirs = mk.pore_particle_directions(
            self.pair_pore, self.pair_particle, self.pore_xy, self.xy
        )
        self.chains = ck.find_chains(self.springs, self.axis, self.fixed)
        m = len(self.springs)
        self.h = np.full(m, H0)
        self.force = mk.hertz_force(self.h, MODULUS)
        self.k0 = float(mk.hertz_stiffness(H0, MODULUS))

    def load(self, pressure: np.ndarray) -> np.ndarray:
        out = np.zeros_like(self.xy)
        mk.pressure_loads(pressure, self.pair_pore, self.pair_particle, self.dirs, 1.0, out)
        return out

    def solve(
        self, pressure, solver="chains", cohesion=1e-6, recontact=True, mode=None, h=None,
        foundation=0.0, du0=None,
    ):  # fmt: skip
        """One update from the prestressed state (or the given ``mode``, ``h`` and
        displacements ``du0``), with a foundation of ``foundation`` K_0."""
        mode = np.zeros(len(self.springs), np.int8) if mode is None else mode.copy()
        h = (self.h if h is None else h).copy()
        force = np.where(mode == mk.OPEN, cohesion * self.k0 * h, mk.hertz_force(h, MODULUS))
        load = self.load(pressure)
        k_c, k_f = cohesion * self.k0, foundation * self.k0
        u0 = np.zeros_like(self.xy) if du0 is None else du0
        if solver == "chains":
            h0, du = h.copy(), u0.copy()
            m = len(self.springs)
            stats = np.zeros(len(mk.Stat))
            law = mk.ContactLaw(MODULUS, k_c, self.k0, k_f, recontact, 50)
            apertures = mk.ApertureMap(np.ones(m), np.ones(m), 1e-9, 1e9, np.zeros(m, bool),
                                       np.zeros(m, bool))  # fmt: skip
            ck.solve_chains(
                self.chains, self.xy, load, np.ones(len(self.chains.chain_axis), bool),
                mk.SpringState(h, force, mode), law, du, apertures, np.zeros(m, np.int64), stats,
            )  # fmt: skip
            dh, f_new, unsettled = h - h0, force, stats[mk.Stat.UNSETTLED]
            # the kernel's own residual (per chain) is the global one
            global_residual = mk.balance_residual(
                load, f_new, self.springs, self.axis, self.fixed, du, k_f
            )
            du = du - u0
            assert stats[mk.Stat.RESIDUAL] == pytest.approx(global_residual, abs=1e-15)
        else:
            law = mk.ContactLaw(MODULUS, k_c, self.k0, k_f, recontact, 50)
            du, dh, f_new, _, unsettled = mk.solve_sparse(
                self.springs, self.axis, self.fixed, load, mk.SpringState(h, force, mode), law, u0
            )
        residual = mk.balance_residual(
            load, f_new, self.springs, self.axis, self.fixed, u0 + du, k_f
        )
        return SimpleNamespace(
            du=du, dh=dh, force=f_new, mode=mode, residual=residual, unsettled=unsettled
        )


def test_hertz_stiffness_is_the_derivative_of_the_force():
    h = np.linspace(0.01, 0.3, 7)
    eps = 1e-7
    numeric = (mk.hertz_force(h + eps, 2.0) - mk.hertz_force(h - eps, 2.0)) / (2 * eps)
    np.testing.assert_allclose(mk.hertz_stiffness(h, 2.0), numeric, rtol=1e-6)
    assert mk.hertz_force(-0.1, 2.0) == 0.0 and mk.hertz_stiffness(-0.1, 2.0) == 0.0


def test_aperture_change_formula():
    # eps = h / 2a = 0.05: dr = -dh 0.95 / (2 sqrt(1 + 0.95^2))
    dr = mk.aperture_change(np.array([0.01]), np.array([0.1]))
    assert dr[0] == pytest.approx(-0.01 * 0.95 / (2 * np.sqrt(1 + 0.95**2)), rel=1e-14)


def test_square_lattice_decomposes_into_chains():
    net = Network(6)
    ptr, particles, springs, axis = net.chains
    assert len(axis) == 2 * (6 - 1)  # one chain per interior row and column
    assert sorted(springs.tolist()) == list(range(len(net.springs)))
    assert np.all(net.fixed[particles[ptr[:-1]]]) and np.all(net.fixed[particles[ptr[1:] - 1]])
    assert Network(6, angle=0.3).chains is None


def test_uniform_pressure_moves_nothing():
    net = Network(9)
    out = net.solve(np.full(81, 1.7))
    assert np.max(np.abs(out.du)) < 1e-14
    assert np.max(np.abs(out.dh)) < 1e-14
    assert out.residual < 1e-13


def test_single_pressurised_pore_pushes_its_four_particles_symmetrically():
    n = 9
    net = Network(n)
    p = np.zeros(n * n)
    centre = (n // 2) * n + n // 2
    p[centre] = 0.5
    du = net.solve(p).du
    corners = net.pair_particle[net.pair_pore == centre]
    outward = net.xy[corners] - net.pore_xy[centre]
    # each corner moves away from the pore centre, along the diagonal, by the same amount
    assert np.all(np.einsum("ij,ij->i", du[corners], outward) > 0)
    magnitudes = np.abs(du[corners])
    np.testing.assert_allclose(magnitudes, magnitudes[0, 0], rtol=1e-12)
    # the whole field is mirror-symmetric about the pore's centre lines
    grid = du.reshape(n + 1, n + 1, 2)
    np.testing.assert_allclose(grid[:, ::-1, 0], -grid[:, :, 0], atol=1e-15)
    np.testing.assert_allclose(grid[::-1, :, 1], -grid[:, :, 1], atol=1e-15)


@settings(max_examples=25, deadline=None)
@given(seed=st.integers(0, 2**31), scale=st.floats(0.01, 5.0))
def test_chains_and_sparse_agree_and_balance_forces(seed, scale):
    net = Network(7)
    p = np.random.default_rng(seed).uniform(0, scale, 49)
    a = net.solve(p, "chains")
    b = net.solve(p, "sparse")
    force_scale = max(1.0, float(np.abs(a.force).max()))
    assert a.residual < 1e-12 * force_scale and b.residual < 1e-12 * force_scale  # balance
    np.testing.assert_array_equal(a.mode, b.mode)  # same contacts lost
    np.testing.assert_allclose(a.du, b.du, atol=1e-9 * (1 + np.abs(a.du).max()))


@settings(max_examples=25, deadline=None)
@given(seed=st.integers(0, 2**31), foundation=st.floats(1e-3, 10.0))
def test_chains_and_sparse_agree_with_a_foundation(seed, foundation):
    """The foundation's force ``-k_f u`` uses the particles' total displacement, so the two
    solvers must also agree from a displaced state, and both balance it to round-off."""
    net = Network(7)
    rng = np.random.default_rng(seed)
    p = rng.uniform(0, 1.0, 49)
    u0 = np.where(net.fixed[:, None], 0.0, rng.normal(0, 1e-3, net.xy.shape))
    a = net.solve(p, "chains", foundation=foundation, du0=u0)
    b = net.solve(p, "sparse", foundation=foundation, du0=u0)
    force_scale = max(1.0, float(np.abs(a.force).max()))
    assert a.residual < 1e-12 * force_scale and b.residual < 1e-12 * force_scale
    np.testing.assert_array_equal(a.mode, b.mode)
    np.testing.assert_allclose(a.du, b.du, atol=1e-9 * (1 + np.abs(a.du).max()))


@pytest.mark.parametrize("foundation", [0.1, 1.0, 4.0])
def test_a_foundation_makes_a_point_load_decay_along_its_line(foundation):
    """A force on one particle of a line of springs of stiffness K on a foundation k_f moves
    the particles at distance d by u_0 r^d with r + 1/r = 2 + k_f / K (the discrete
    Green's function); without the foundation the displacement falls linearly to the ring."""
    n = 41
    net = Network(n)
    p = np.zeros(n * n)
    centre = (n // 2) * n + n // 2
    p[centre] = 1e-3  # small: the tangent stays K_0 to ~1e-6
    kappa = foundation
    r = 1.0 + kappa / 2.0 - np.sqrt(kappa + kappa**2 / 4.0)
    grid = net.solve(p, foundation=foundation).du.reshape(n + 1, n + 1, 2)
    row = grid[n // 2 + 1, n // 2 + 1 :, 0]  # the line through the pore's upper-right corner
    ratios = row[1:8] / row[:7]
    np.testing.assert_allclose(ratios, r, rtol=2e-3)
    flat = net.solve(p).du.reshape(n + 1, n + 1, 2)[n // 2 + 1, n // 2 + 1 :, 0]
    np.testing.assert_allclose(np.diff(flat), np.diff(flat)[0], rtol=1e-6)  # linear


def test_sparse_solver_is_rotation_invariant():
    p = np.random.default_rng(3).uniform(0, 0.5, 36)
    straight = Network(6)
    turned = Network(6, angle=0.4)
    a = straight.solve(p, "chains")
    b = turned.solve(p, "sparse")
    c, s = np.cos(0.4), np.sin(0.4)
    np.testing.assert_allclose(b.du, a.du @ np.array([[c, -s], [s, c]]).T, atol=1e-12)
    np.testing.assert_allclose(b.dh, a.dh, atol=1e-12)


def test_tension_removes_springs_and_balance_still_holds():
    n = 9
    net = Network(n)
    p = np.zeros(n * n)
    p[(n // 2) * n + n // 2] = 3.0  # far above the prestress force: the pore's springs open
    out = net.solve(p)
    opened = out.mode == mk.OPEN
    assert opened.any() and out.unsettled == 0
    assert np.all(net.h[opened] + out.dh[opened] <= 0)  # removed springs are in tension
    assert np.all(net.h[~opened] + out.dh[~opened] > 0)  # the others still in contact
    assert out.residual < 1e-12


def floating_particle(net: Network, cohesion: float) -> np.ndarray:
    """Open every spring of an interior particle (gaps of 0.05 a) and push it along x."""
    n = net.n
    q = (n // 2) * (n + 1) + n // 2
    mine = np.flatnonzero((net.springs == q).any(axis=1))
    mode = np.zeros(len(net.springs), np.int8)
    mode[mine] = mk.OPEN
    h = net.h.copy()
    h[mine] = -0.05
    # pressure in the two pores left of the particle only: a net push along +x
    p = np.zeros(n * n)
    row, col = n // 2, n // 2
    p[[(row - 1) * n + col - 1, row * n + col - 1]] = 0.2
    out = net.solve(p, cohesion=cohesion, mode=mode, h=h)
    assert out.unsettled == 0 and out.residual < 1e-12
    return out.du


def test_floating_particle_stops_at_its_neighbour_whatever_the_cohesion():
    net = Network(9)
    results = [floating_particle(net, c) for c in (1e-9, 1e-7, 1e-5)]
    q = (9 // 2) * 10 + 9 // 2
    # it crosses its 0.05 a gap and pushes on: bounded, not F / k_c
    assert 0.05 < results[0][q, 0] < 1.0
    for other in results[1:]:
        np.testing.assert_allclose(other, results[0], atol=1e-4)


def test_without_recontact_a_floating_particle_is_held_only_by_cohesion():
    net = Network(9)
    n = 9
    q = (n // 2) * (n + 1) + n // 2
    mine = np.flatnonzero((net.springs == q).any(axis=1))
    mode = np.zeros(len(net.springs), np.int8)
    mode[mine] = mk.OPEN
    h = net.h.copy()
    h[mine] = -0.05
    p = np.zeros(n * n)
    p[[(n // 2 - 1) * n + n // 2 - 1, (n // 2) * n + n // 2 - 1]] = 0.2
    du = net.solve(p, recontact=False, mode=mode, h=h, cohesion=1e-6).du
    assert du[q, 0] > 100.0  # the regularisation alone: why 'restore' is the default


def test_lazy_loads_solve_only_the_lines_through_changed_pores():
    n = 9
    net = Network(n)
    axis = net.chains.chain_axis
    particle_chain = ck.particle_chains(net.chains, len(net.xy))
    order = np.argsort(net.pair_pore, kind="stable")
    pair_ptr = np.searchsorted(net.pair_pore[order], np.arange(n * n + 1))
    p = np.zeros(n * n)
    centre = (n // 2) * n + n // 2
    p[centre] = 0.5
    p[0] = 1e-4  # a small change in a corner pore
    seen, load = np.zeros(n * n), np.zeros_like(net.xy)
    dirty = np.zeros(len(axis), bool)
    contacts = ck.PoreContacts(pair_ptr, net.pair_particle[order], net.dirs[order], 1.0)
    args = (contacts, load, particle_chain, dirty)
    assert ck.refresh_loads(p, seen, 1e-3, *args) == 1  # the corner pore lags
    assert dirty.sum() == 4  # the two lines along x and the two along y through the centre
    np.testing.assert_allclose(load, net.load(np.where(np.arange(n * n) == centre, 0.5, 0)))
    assert seen[0] == 0 and seen[centre] == 0.5
    dirty[:] = False
    assert ck.refresh_loads(p, seen, 0.0, *args) == 1  # exact: the corner too
    np.testing.assert_allclose(load, net.load(p), atol=1e-15)
