"""One-way coupling: the invasion is the rigid medium's to the bit, on every schedule and for
both fluid models; the solid feels the fluid (its recorded forces balance the fluid's
pressures, recomputed here from the lattice's particles); the two-way coupler's run differs
once the solid is soft, and only through the feedback."""

from __future__ import annotations

import numpy as np
import pytest
from porenet_oneway.config import KIND
from porenet_oneway.model import pore_pressures

from porenet.testing.contract import FORCE_ROUND_OFF
from porenet.testing.runs import simulate

#: What the fluid's run consists of: compared to the bit with the rigid medium's.
FLUID_FIELDS = ("order", "throat", "invasion_pressure", "invasion_time", "pressure", "drained",
                "trapped")  # fmt: skip
INVASION = {"kind": "invasion-percolation"}
VISCOUS = {"kind": "viscous", "capillary_number": 1e-2}


def scene(fluid: dict, n: int = 16, **solid) -> dict:
    """The rigid scene, or with ``solid`` fields a scene of porenet's Hertzian solid."""
    data = {"seed": 3, "lattice": {"n": n, "disorder": 0.3, "pore_size": 1e-4},
            "fluid": fluid, "classifier": {"kind": "none"}}  # fmt: skip
    if solid:
        data["solid"] = {"kind": "hertz", "fracturing_number": 1.0, "coupler": KIND, **solid}
    return data


def test_pore_pressures_are_the_invaders_in_drained_pores_the_defenders_elsewhere():
    drained = np.array([True, False, True, False])
    np.testing.assert_array_equal(pore_pressures(drained, 2.5, None), [2.5, 0, 2.5, 0])
    defender = np.array([9.0, 1.5, 9.0, -0.5])
    np.testing.assert_array_equal(pore_pressures(drained, 2.5, defender), [2.5, 1.5, 2.5, -0.5])


@pytest.mark.parametrize(
    ("fluid", "schedule"),
    [
        (INVASION, {"coupling": "every-step"}),
        (INVASION, {"coupling": "adaptive", "coupling_tolerance": 0.05}),
        (VISCOUS, {"coupling": "interval", "coupling_interval": 50}),
        (VISCOUS, {"coupling": "adaptive", "coupling_tolerance": 0.01}),
    ],
    ids=["ip-every-step", "ip-adaptive", "viscous-interval", "viscous-adaptive"],
)
def test_the_invasion_is_the_rigid_mediums_to_the_bit(reg, fluid, schedule):
    """A soft solid (N_f = 1) coupled one way: the drainage order, throats, pressures, times,
    pressure field, trapped pores and time series are the rigid run's, bit for bit, and the
    apertures the fluid ends with are the initial ones; the solid was updated and would have
    moved them."""
    rigid = simulate(scene(fluid), registry=reg)[1].data
    _, result = simulate(scene(fluid, **schedule), registry=reg)
    data = result.data
    for name in FLUID_FIELDS:
        assert np.array_equal(getattr(data, name), getattr(rigid, name)), name
    for name, series in rigid.timeseries.items():
        assert np.array_equal(data.timeseries[name], series), name
    np.testing.assert_array_equal(data.final_apertures, rigid.apertures)
    assert result.summary["mechanical_updates"] > 0
    assert data.mechanics_series["max_aperture_change"].max() > 0.01 * data.pore_size


def test_the_solid_feels_the_fluid(reg):
    """Coupled after every drained pore, the solid is updated once per pore drained past the
    inlet; its recorded forces moved from the uniform prestress and balance, at every free
    particle,
    the pressures of the fluid's final state, recomputed from the lattice's particles: each
    pore pushes each particle it touches with p A_p away from its centre, each spring pushes
    its two particles apart with its force."""
    sim, result = simulate(scene(INVASION, coupling="every-step"), registry=reg)
    data, lat, sc = result.data, sim.lattice, sim.scales
    assert result.summary["mechanical_updates"] == data.drained.sum() - 1
    force = data.mechanics_final["spring_force"] / (sc.pressure * sc.area)  # gamma a
    # the prestress is the same in every spring; the fluid's load made them differ
    assert np.ptp(force) > 0.1 * np.abs(force).max()
    pressure = pore_pressures(sim.state.drained, sim.state.invading_pressure, None)
    xy, springs = lat.particle_coords, lat.spring_particles
    axis = xy[springs[:, 1]] - xy[springs[:, 0]]
    axis /= np.linalg.norm(axis, axis=1)[:, None]
    net = np.zeros_like(xy)
    np.add.at(net, springs[:, 1], force[:, None] * axis)
    np.add.at(net, springs[:, 0], -force[:, None] * axis)
    pores, particles = lat.pore_particle_pairs
    push = xy[particles] - lat.pore_coords[pores]
    push /= np.linalg.norm(push, axis=1)[:, None]
    np.add.at(net, particles, pressure[pores, None] * push)
    free = ~lat.fixed_particles
    assert np.abs(net[free]).max() < FORCE_ROUND_OFF
    assert np.abs(net[~free]).max() > 0.1  # the fixed ring holds the load
    residual = data.mechanics_series["balance_residual"] / (sc.pressure * sc.area)
    assert residual.max() < FORCE_ROUND_OFF


def test_two_way_coupling_differs_once_the_solid_is_soft(reg):
    """The same scene with porenet's two-way coupler: the first update sees the same
    pressures on the same solid (the same largest aperture change); from then on the
    apertures it feeds back change the invasion. In a stiff solid (N_f = 1e-9) the feedback
    vanishes and the two-way run drains in the rigid order too."""
    runs = {
        (coupler, nf): simulate(
            scene(INVASION, coupling="every-step", coupler=coupler, fracturing_number=nf),
            registry=reg,
        )[1].data
        for coupler in (KIND, "pressure-aperture")
        for nf in (1.0, 1e-9)
    }
    one, two = runs[KIND, 1.0], runs["pressure-aperture", 1.0]
    first = [r.mechanics_series["max_aperture_change"][0] for r in (one, two)]
    assert first[0] == first[1] > 0
    assert not np.array_equal(one.order, two.order)
    assert np.array_equal(runs["pressure-aperture", 1e-9].order, runs[KIND, 1e-9].order)
    assert np.array_equal(runs[KIND, 1e-9].order, one.order)


def test_the_schedules_space_the_updates(reg):
    """Every step: one update per drained pore; an interval of k fluid steps: updates at
    least k steps apart, so at most steps / k of them; adaptive: fewer than every step."""
    counts = {}
    for name, schedule in {"every-step": {}, "interval": {"coupling_interval": 200},
                           "adaptive": {"coupling_tolerance": 0.05}}.items():  # fmt: skip
        _, result = simulate(scene(VISCOUS, n=10, coupling=name, **schedule), registry=reg)
        counts[name] = result.summary["mechanical_updates"]
        steps = result.summary["time_steps"]
    assert counts["every-step"] == steps
    assert 0 < counts["interval"] <= steps // 200
    assert 0 < counts["adaptive"] < counts["every-step"]
