"""The frictional contact kernels: balance, the elastic response of a point load, sliding."""

from __future__ import annotations

import math

import numpy as np
import pytest

from porenet.kinds.hertz.kernels import springs as mk
from porenet.kinds.mindlin.grid_solver import GridSolver
from porenet.kinds.mindlin.kernels import frictional as fr
from porenet.kinds.mindlin.kernels import frictional_sparse as fs
from porenet.kinds.mindlin.kernels.grid import find_grid
from porenet.kinds.square.model import SquareLattice, SquareLatticeConfig

MODULUS = 4.47  # E* a / gamma at N_f = 10, lambda = 0.1, eps_0 = 0.05
H0 = 0.1


class FrictionalNetwork:
    """The square lattice's prestressed solid with frictional contacts, updated by hand."""

    def __init__(self, n: int, ratio: float, rotation: bool = False, friction: float = math.inf,
                 angle: float = 0.0, slip_tolerance: float = 0.0) -> None:  # fmt: skip
        lat = SquareLattice(SquareLatticeConfig(n=n, disorder=0.1), np.random.default_rng(0))
        c, s = np.cos(angle), np.sin(angle)
        self.n = n
        self.xy = lat.particle_coords @ np.array([[c, -s], [s, c]]).T
        self.springs = lat.spring_particles
        self.fixed = lat.fixed_particles
        self.axis = mk.spring_axes(self.springs, self.xy)
        m = len(self.springs)
        self.k0 = float(mk.hertz_stiffness(H0, MODULUS))
        h = np.full(m, H0)
        self.state = mk.SpringState(h, mk.hertz_force(h, MODULUS), np.zeros(m, np.int8))
        self.shear = fr.ShearState(np.zeros(m), np.zeros(m), np.zeros(m, np.int8), np.ones(m))
        self.law = fr.FrictionLaw(MODULUS, 1e-6 * self.k0, self.k0, 0.0, True, ratio, friction,
                                  rotation, 50, slip_tolerance)  # fmt: skip
        self.displacement = np.zeros_like(self.xy)
        self.rotation = np.zeros(len(self.xy))
        self.grid = find_grid(self.xy, self.springs, self.fixed)
        self.pattern = fs.pattern(self.springs, self.axis, self.fixed, rotation)
        self.apertures = mk.ApertureMap(np.ones(m), np.ones(m), 1e-9, 1e9, np.zeros(m, bool),
                                        np.zeros(m, bool))  # fmt: skip

    def centre(self) -> int:
        return (self.n // 2) * (self.n + 1) + self.n // 2

    def imbalance(self, load: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        force, torque = np.zeros_like(self.xy), np.zeros(len(self.xy))
        fr.out_of_balance(load, self.displacement, self.springs, self.axis, self.state.force,
                          self.shear.force, 0.0, force, torque)  # fmt: skip
        force[self.fixed] = 0.0
        torque[self.fixed] = 0.0
        return force, torque

    def update(self, load: np.ndarray, solver: str = "sparse") -> int:
        """One update under ``load`` with the contact iteration; returns the iterations."""
        work = fr.increments(len(self.springs))
        fr.start_update(self.state, self.shear, self.law, work)
        du, dtheta = np.zeros_like(self.xy), np.zeros(len(self.xy))
        force, torque = np.zeros_like(self.xy), np.zeros(len(self.xy))
        mg = GridSolver(self.grid, 0.0, 1e-15, 500) if solver == "multigrid" else None
        for iteration in range(1, 51):
            fr.trial_laws(self.state, self.shear, self.law, work)
            fr.out_of_balance(load, self.displacement, self.springs, self.axis, work.normal_base,
                              work.shear_base, 0.0, force, torque)  # fmt: skip
            if mg is None:
                fs.solve(self.pattern, work.normal_stiffness, work.shear_stiffness, 0.0, force,
                         torque, du, dtheta)  # fmt: skip
            else:
                mg.solve(work.normal_stiffness, work.shear_stiffness, 0.0, force, du)
            fr.solved_increments(self.springs, self.axis, du, dtheta, work)
            if fr.next_modes(self.state, self.shear, self.law, work, iteration < 50) == 0:
                break
        changed = np.zeros(len(self.springs), np.int64)
        *_, finite = fr.apply_increments(self.state, self.shear, self.law, work, du, dtheta,
                                         self.displacement, self.rotation, self.apertures,
                                         changed, 0.0)  # fmt: skip
        assert finite
        return iteration

    def energy(self) -> float:
        return sum(fr.stored_energy(self.state, self.shear, self.law))


def point_load(net: FrictionalNetwork, size: float) -> np.ndarray:
    load = np.zeros_like(net.xy)
    load[net.centre(), 0] = size
    return load


def axis_profiles(net: FrictionalNetwork) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """u_x along the +x and +y axes from the centre particle, at distances r (spacings)."""
    n = net.n
    ux = net.displacement[:, 0].reshape(n + 1, n + 1)
    c = n // 2
    r = np.arange(1, n // 2)
    return r, ux[c, c + r], ux[c + r, c]


def log_slope(r: np.ndarray, u: np.ndarray) -> float:
    """``-du / d ln r`` fitted over 4-12 spacings (far from the load's discreteness and from
    the fixed ring 50 spacings away)."""
    sel = (r >= 4) & (r <= 12)
    return float(-np.polyfit(np.log(r[sel]), u[sel], 1)[0])


@pytest.mark.parametrize(
    "ratio, rotation, solver, tolerance",
    [
        (1.0, False, "multigrid", 0.02),
        (1.0, False, "sparse", 0.02),
        (0.3, False, "multigrid", 0.05),
        (1.0, True, "sparse", 0.02),
    ],
)
def test_a_point_load_spreads_as_in_a_2d_elastic_medium(ratio, rotation, solver, tolerance):
    """A point force F in the bulk displaces the medium like ln(1/r), with the coefficient of
    the effective moduli the contact stiffnesses give (docs/model.md, "Frictional solid"):
    rotations held, an anisotropic medium whose u_x obeys K_n d2u/dx2 + K_t d2u/dy2 = -f, so
    -du/dln r = F / (2 pi sqrt(K_n K_t)) along both axes; rotations free at K_t = K_n, the
    isotropic 2-D medium of Lame constants lambda = 0, mu = K_n / 2, whose Kelvin solution has
    -du_x/dln r = 3 F / (8 pi mu) = 3 F / (4 pi K_n). (The tolerance covers the lattice's
    discreteness and the fixed ring, measured at 0.5-3 % on n = 100.)"""
    net = FrictionalNetwork(100, ratio, rotation)
    force = 1e-3 * net.k0
    net.update(point_load(net, force), solver)
    r, along_x, along_y = axis_profiles(net)
    k_n, k_t = net.k0, ratio * net.k0
    expected = 3 / (4 * math.pi * k_n) if rotation else 1 / (2 * math.pi * math.sqrt(k_n * k_t))
    assert log_slope(r, along_x) / force == pytest.approx(expected, rel=tolerance)
    assert log_slope(r, along_y) / force == pytest.approx(expected, rel=tolerance)


def test_without_shear_stiffness_a_point_load_moves_only_its_line():
    """The frictionless chain: u_x falls linearly to the fixed ring along the load's line
    (it does not decay like an elastic medium's) and nothing moves off it."""
    net = FrictionalNetwork(40, 0.0)
    force = 1e-3 * net.k0
    net.update(point_load(net, force))
    r, along_x, along_y = axis_profiles(net)
    # a chain of 20 + 20 springs of stiffness K_0 between fixed ends: u(r) = F (20 - r) / (2 K_0)
    np.testing.assert_allclose(along_x, force * (20 - r) / (2 * net.k0), rtol=1e-6)
    assert np.abs(along_y).max() <= 1e-9 * along_x.max()


@pytest.mark.parametrize("rotation", [False, True])
def test_forces_and_torques_balance_to_round_off(rotation):
    """Random pore-like loads big enough to open and re-close contacts: every free particle's
    net force (and torque, where particles rotate) is round-off after the update."""
    net = FrictionalNetwork(16, 0.5, rotation, friction=0.3)
    rng = np.random.default_rng(4)
    load = rng.normal(scale=2.0 * net.state.force[0], size=net.xy.shape)
    assert net.update(load) < 50  # settled
    assert np.count_nonzero(net.state.mode == mk.OPEN) > 0
    force, torque = net.imbalance(load)
    # round-off of a solve whose stiffnesses span 1e6 (open contacts keep k_c = 1e-6 K_0)
    scale = net.state.force.max()
    assert np.abs(force).max() <= 1e-10 * scale
    if rotation:
        assert np.abs(torque).max() <= 1e-10 * scale
    else:
        assert np.all(net.rotation == 0.0)


def test_multigrid_and_sparse_direct_agree():
    a, b = FrictionalNetwork(20, 0.4), FrictionalNetwork(20, 0.4)
    load = np.random.default_rng(2).normal(scale=0.3 * a.state.force[0], size=a.xy.shape)
    a.update(load, "sparse")
    b.update(load, "multigrid")
    scale = np.abs(a.displacement).max()
    np.testing.assert_allclose(b.displacement, a.displacement, atol=1e-10 * scale)
    np.testing.assert_array_equal(b.state.mode, a.state.mode)


def test_multigrid_and_sparse_direct_agree_with_sliding():
    """With contacts sliding (their tangential edges zero in the operator, the multigrid's
    hierarchy built with them stuck) the two solvers give the same update, mode for mode."""
    a, b = (FrictionalNetwork(16, 0.8, friction=0.01) for _ in range(2))
    load = point_load(a, 0.2 * a.state.force[0])
    a.update(load, "sparse")
    b.update(load, "multigrid")
    assert np.count_nonzero(a.shear.mode) > 0
    np.testing.assert_array_equal(b.shear.mode, a.shear.mode)
    scale = np.abs(a.displacement).max()
    np.testing.assert_allclose(b.displacement, a.displacement, atol=1e-9 * scale)


def test_sparse_solver_is_rotation_invariant():
    """The same network turned by 30 degrees (no grid: the sparse solver's general
    assembly) gives the same contact forces."""
    load = np.random.default_rng(1).normal(scale=0.1 * H0, size=((17 * 17), 2))
    straight, turned = FrictionalNetwork(16, 0.6, True), FrictionalNetwork(16, 0.6, True, angle=0.5)
    assert straight.grid is not None and turned.grid is None
    c, s = np.cos(0.5), np.sin(0.5)
    straight.update(load)
    turned.update(load @ np.array([[c, -s], [s, c]]).T)
    np.testing.assert_allclose(turned.state.force, straight.state.force, atol=1e-12)
    np.testing.assert_allclose(turned.shear.force, straight.shear.force, atol=1e-12)


def test_sliding_caps_the_tangential_force_and_dissipates():
    """With a small friction coefficient, contacts around a loaded particle slide: their
    tangential force sits at mu F (F at the update's start), the sticking ones below it, each
    slip goes against the force (the energy it dissipates, -S slip, is positive), and forces
    balance."""
    mu = 0.01
    net = FrictionalNetwork(16, 0.8, friction=mu)
    load = point_load(net, 0.2 * net.state.force[0])
    cap = mu * net.state.force.copy()
    net.update(load)
    slides = net.shear.mode == fr.SLIDE
    assert slides.sum() >= 2
    np.testing.assert_allclose(np.abs(net.shear.force[slides]), cap[slides], rtol=1e-12)
    assert np.all(np.abs(net.shear.force[~slides]) <= cap[~slides] * (1 + 1e-12))
    assert np.all(net.shear.force * net.shear.slip <= 0.0)
    assert np.count_nonzero(net.shear.slip) == slides.sum()
    force, _ = net.imbalance(load)
    assert np.abs(force).max() <= 1e-12 * net.state.force.max()


def test_sliding_never_increases_stored_energy():
    """Over a load cycle (up in five steps, down in five): at every update each sliding
    contact stores less tangential energy than its sticking trial would (S^2 / 2 K_t below
    S_trial^2 / 2 K_t), no contact stores more than Coulomb's cap allows ((mu F)^2 / 2 K_t),
    and the energy dissipated never decreases; unloaded, the slip stays (history kept)."""
    mu = 0.01
    net = FrictionalNetwork(12, 0.8, friction=mu)
    peak = 0.3 * net.state.force[0]
    dissipated = 0.0
    for size in np.concatenate([np.linspace(0, peak, 6)[1:], np.linspace(peak, 0, 6)[1:]]):
        cap = mu * net.state.force.copy()
        slip_before = net.shear.slip.copy()
        net.update(point_load(net, size))
        k_t = net.law.stiffness_ratio * mk.hertz_stiffness(net.state.compression, MODULUS)
        step = net.shear.slip - slip_before
        shear = net.shear.force
        trial = shear - k_t * step  # slip = (S - S_trial) / K_t
        slid = step != 0.0
        assert np.all(shear[slid] ** 2 < trial[slid] ** 2)
        assert np.all(np.abs(shear) <= cap * (1 + 1e-12))
        increment = float(np.sum(-shear * step))
        assert increment >= 0.0
        dissipated += increment
    assert dissipated > 0.0
    assert np.count_nonzero(net.shear.slip) > 0


def test_a_particle_without_contacts_is_held_by_cohesion():
    """Pull the four neighbours of a particle away from it, so that all four of its contacts
    open: the update stays finite, the particle (which carries no load) stays in balance on
    its cohesive springs (both stiffnesses lost: no tangential force left), and every other
    particle balances too."""
    net = FrictionalNetwork(10, 0.5, rotation=True)
    c = net.centre()
    springs = np.flatnonzero((net.springs == c).any(axis=1))
    load = np.zeros_like(net.xy)
    for s in springs:
        other = net.springs[s, 1] if net.springs[s, 0] == c else net.springs[s, 0]
        away = net.xy[other] - net.xy[c]
        load[other] = 10.0 * net.state.force[0] * away / np.linalg.norm(away)
    assert net.update(load) < 50  # settled
    assert np.all(net.state.mode[springs] == mk.OPEN)
    assert np.all(np.isfinite(net.displacement)) and np.all(np.isfinite(net.rotation))
    force, torque = net.imbalance(load)
    assert np.abs(force).max() <= 1e-10 * net.state.force.max()
    assert np.abs(torque).max() <= 1e-10 * net.state.force.max()
    assert np.abs(net.shear.force[springs]).max() <= 1e-3 * net.state.force.max()


@pytest.mark.parametrize("recontact", [True, False])
def test_a_contact_left_apart_starts_the_next_update_re_forming(recontact):
    """A contact left in contact at h <= 0 (a contact frozen at its kink ends an update at
    h slightly below 0) has no Hertz tangent: it starts the next update re-forming (K_0 h,
    sticking) where re-contact is allowed, so a load cannot push its particles through each
    other on the cohesive stiffness alone; with re-contact off it keeps its mode."""
    net = FrictionalNetwork(6, 0.5, friction=0.3)
    law = net.law._replace(recontact=recontact)
    apart = [3, 7]
    net.state.compression[apart] = [-1e-3, 0.0]
    net.shear.mode[apart] = fr.SLIDE
    work = fr.increments(len(net.springs))
    reforming = fr.start_update(net.state, net.shear, law, work)
    assert reforming == (2 if recontact else 0)
    expected = mk.RECONTACT if recontact else mk.IN_CONTACT
    np.testing.assert_array_equal(work.normal_mode[apart], expected)
    others = np.setdiff1d(np.arange(len(net.springs)), apart)
    assert (work.normal_mode[others] == mk.IN_CONTACT).all()
    assert (work.shear_mode[apart] == (fr.STICK if recontact else fr.SLIDE)).all()


@pytest.mark.parametrize("rotation", [False, True])
def test_a_small_change_of_sliding_mode_takes_effect_without_another_solve(rotation):
    """With a slip tolerance delta, a contact whose change between sticking and sliding moves
    its tangential force by at most K_t delta changes mode without another solve: Coulomb's
    law still holds at every contact (sliding ones at mu F, sticking ones below it), each slip
    still goes against the force, and the force this leaves out of balance on a particle is at
    most its contacts' K_t delta. A delta far above any slip settles in one solve; with delta
    = 0 the same load needs more solves and balances to round-off."""
    mu = 0.01
    exact = FrictionalNetwork(16, 0.8, rotation=rotation, friction=mu)
    load = point_load(exact, 0.2 * exact.state.force[0])
    solves_exact = exact.update(load)
    force, _ = exact.imbalance(load)
    assert np.abs(force).max() <= 1e-10 * exact.state.force.max()
    for delta in (1e-4, 1e-2, 1e3):
        net = FrictionalNetwork(16, 0.8, rotation=rotation, friction=mu, slip_tolerance=delta)
        cap = mu * net.state.force.copy()
        k_t = net.law.stiffness_ratio * mk.hertz_stiffness(net.state.compression, MODULUS)
        solves = net.update(load)
        slides = net.shear.mode == fr.SLIDE
        assert slides.sum() >= 2
        # with rotations a sliding contact keeps the cohesive k_c dd_t (1e-6 K_0 times the slip)
        rtol = 1e-4 if rotation else 1e-12
        np.testing.assert_allclose(np.abs(net.shear.force[slides]), cap[slides], rtol=rtol)
        assert np.all(np.abs(net.shear.force[~slides]) <= cap[~slides] * (1 + rtol))
        assert np.all(net.shear.force * net.shear.slip <= 0.0)
        force, _ = net.imbalance(load)
        bound = 4 * k_t.max() * delta  # four contacts a particle
        assert np.abs(force).max() <= bound + 1e-10 * net.state.force.max()
        assert solves <= solves_exact
        if delta == 1e3:
            assert solves == 1
    assert solves_exact > 1
