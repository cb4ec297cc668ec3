"""Physics on an imported, irregular network (docs/lattices.md, "Imported networks (kind
`network`)"): the example network of examples/networks/ (400 pores of a jittered grid joined
by 965 Delaunay edges, throats of three shapes, lengths and volumes from the file).

1. Invasion percolation, with and without trapping, drains the pores in the order of a slow,
   obvious reference written here (a heap of frontier throats; with trapping, a breadth-first
   search after every step for the defender that still reaches the outlet).
2. The viscous model closes its volume balances to round-off with every integrator, its pump
   delivers Ca A_b t, and the volume its menisci displaced is the throat volume they swept.
3. Ca -> 0 is invasion percolation with trapping.
"""

from __future__ import annotations

import heapq
from collections import deque
from pathlib import Path

import numpy as np
import pytest

from porenet.simulation import Simulation

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "networks" / "delaunay-2d.npz"
#: The example scene's length unit a (m): the mean throat radius of the file.
A = 8.07739e-06


def scene(fluid: dict, at="pore.left", stop="breakthrough", a=A, **lattice) -> dict:
    return {
        "lattice": {"kind": "network", "file": str(EXAMPLE), "pore_size": a, **lattice},
        "injection": {"at": at},
        "fluid": fluid,
        "stop": {"at": stop},
        "classifier": {"kind": "none"},  # the classifier needs a grid (docs/lattices.md)
    }


def raw() -> dict[str, np.ndarray]:
    with np.load(EXAMPLE) as data:
        return {key: data[key] for key in data.files}


# -- 1. invasion percolation against a slow reference -------------------------------------------


def reference_invasion(
    n: int,
    throats: np.ndarray,
    entry: np.ndarray,
    inlets: np.ndarray,
    outlet: np.ndarray,
    trapping: bool,
    stop_at_outlet: bool,
) -> tuple[list[int], list[int]]:
    """Invasion percolation the obvious way: drain the inlets; then, step by step, enter the
    frontier throat of least entry pressure (ties: the lower throat index) whose undrained
    pore is not trapped, where a pore is trapped when no path of undrained pores joins it to
    an undrained outlet pore (found afresh by a breadth-first search after every step).
    Returns the drained pores in order and the throat of each step (-1 for inlets)."""
    neighbours: list[list[tuple[int, int]]] = [[] for _ in range(n)]
    for t, (a, b) in enumerate(throats):
        neighbours[a].append((b, t))
        neighbours[b].append((a, t))
    drained = np.zeros(n, dtype=bool)
    order, via, heap = [], [], []

    def drain(pore: int, throat: int) -> None:
        drained[pore] = True
        order.append(pore)
        via.append(throat)
        for other, t in neighbours[pore]:
            if not drained[other]:
                heapq.heappush(heap, (entry[t], t, other))

    def reaches_outlet() -> np.ndarray:
        seen = outlet & ~drained
        queue = deque(np.flatnonzero(seen))
        while queue:
            pore = queue.popleft()
            for other, _ in neighbours[pore]:
                if not drained[other] and not seen[other]:
                    seen[other] = True
                    queue.append(other)
        return seen

    for pore in sorted(int(p) for p in inlets):
        drain(pore, -1)
    if stop_at_outlet and outlet[inlets].any():
        return order, via
    while heap:
        alive = reaches_outlet() if trapping else ~drained
        while heap and (drained[heap[0][2]] or not alive[heap[0][2]]):
            heapq.heappop(heap)  # a trapped pore stays trapped: drop it for good
        if not heap:
            break
        _, t, pore = heapq.heappop(heap)
        drain(pore, t)
        if stop_at_outlet and outlet[pore]:
            break
    return order, via


IP_CASES = {
    "left-to-right-trapping": ({"at": "pore.left", "outlet": "pore.right"}, True, "complete"),
    "left-to-right": ({"at": "pore.left", "outlet": "pore.right"}, False, "complete"),
    "breakthrough": ({"at": "pore.left", "outlet": "pore.right"}, True, "breakthrough"),
    "centre-trapping": ({"at": "centre"}, True, "complete"),
    "face-shape-factor": ({"at": "y-", "entry_pressure": "shape-factor"}, True, "complete"),
}


@pytest.mark.parametrize(("case", "trapping", "stop"), IP_CASES.values(), ids=IP_CASES.keys())
def test_invasion_order_is_the_reference_order(case, trapping, stop):
    case = dict(case)
    at = case.pop("at")
    fluid = {"kind": "invasion-percolation", "trapping": trapping}
    sim = Simulation.from_scene(scene(fluid, at=at, stop=stop, **case))
    data = sim.run().data
    lat = sim.lattice
    # the entry pressures from the file's arrays, independently of the lattice
    arrays = raw()
    r = arrays["throat.inscribed_diameter"] / 2 / A
    if case.get("entry_pressure") == "shape-factor":
        entry = (1 + 2 * np.sqrt(np.pi * arrays["throat.shape_factor"])) / r
    else:
        entry = 2 / r
    order, via = reference_invasion(
        lat.n_pores,
        arrays["throat.conns"],
        entry,
        lat.inlet_pores(at),
        lat.outlet_mask(at),
        trapping,
        stop == "breakthrough",
    )
    assert len(order) > 50
    np.testing.assert_array_equal(data.order, order)
    np.testing.assert_array_equal(data.throat, via)


# -- 2. the viscous model's volume balances -------------------------------------------------------


@pytest.mark.parametrize("integrator", ["explicit", "rkc", "implicit"])
def test_viscous_volume_balances_on_the_network(integrator):
    ca = 1e-3
    fluid = {"kind": "viscous", "capillary_number": ca, "integrator": integrator}
    sim = Simulation.from_scene(scene(fluid, outlet="pore.right"))
    result = sim.run()
    s, lat = result.summary, sim.lattice
    assert s["integrator"] == integrator and s["stop_reason"] == "breakthrough"
    if integrator == "rkc":
        assert s["rkc_steps"] > 0
    # measured (this machine): explicit 1.1e-12 over 5.4e4 steps, rkc 3e-14, implicit 4e-15
    assert s["volume_balance_error"] < 1e-10
    v = sim.fluid.volumes()
    # the pump delivers Q = Ca A_b, A_b = one a^2 per outlet pore (20 on pore.right)
    outlets = int(lat.outlet_mask("pore.left").sum())
    assert sim.fluid.cross_section == outlets == 20
    np.testing.assert_allclose(v["injected"], ca * outlets * v["time"], rtol=1e-10)
    # the pores drained hold the volume the file gives them (inlets included)
    drained = result.data.drained
    np.testing.assert_allclose(
        v["drained_pore_volume"], raw()["pore.volume"][drained].sum() / A**3, rtol=1e-12
    )
    # the defender the menisci displaced is the throat volume A l they swept: (1 - ell/2a) of
    # each throat they entered (lengths mapped onto 2a, docs/lattices.md "Throat lengths")
    c_area, _ = lat.throat_factors
    ell = sim.state.meniscus_length
    assert np.all((ell >= 0) & (ell <= 2))
    volume = c_area * lat.initial_apertures**2 * lat.throat_lengths
    swept = float(np.sum(volume * (1 - ell / 2)))
    np.testing.assert_allclose(swept, v["drained"], rtol=1e-10)


# -- 3. Ca -> 0 is invasion percolation with trapping ---------------------------------------------


def _patterns(a: float, ca: float) -> tuple:
    ip = Simulation.from_scene(
        scene({"kind": "invasion-percolation", "trapping": True}, a=a, outlet="pore.right")
    )
    fluid = {"kind": "viscous", "capillary_number": ca, "integrator": "implicit"}
    viscous = Simulation.from_scene(scene(fluid, a=a, outlet="pore.right"))
    return ip.run().data, viscous.run().data


def _jaccard(x: np.ndarray, y: np.ndarray) -> float:
    return float((x & y).sum() / (x | y).sum())


def test_small_ca_is_invasion_percolation_with_trapping():
    """With a = 1 µm the drained set at breakthrough is trapping IP's, pore for pore, from
    Ca = 1e-4 down (measured: Jaccard overlap 1 at Ca = 1e-4 and 1e-7, implicit integrator;
    RKC agrees at 1e-4 but takes ~5e6 stage sweeps there)."""
    ip, viscous = _patterns(1e-6, 1e-6)
    np.testing.assert_array_equal(viscous.drained, ip.drained)
    assert viscous.drained.sum() > 150


def test_compressible_defender_drains_trapped_pores_when_a_is_large():
    """The defender's compressibility c_t = a/gamma (docs/model.md section 4) lets an advancing
    meniscus push defender into a trapped pore until its pressure stops it: c_t V dp of
    volume. With a = the mean throat radius (the example scene, 8 µm) the pores are ~30 a^3
    and absorb a whole throat's volume, so at Ca -> 0 a few pores that IP traps still drain;
    they do so at any Ca (the same five at Ca = 1e-5, 1e-6 and 1e-7; one at a = 2 and 4 µm,
    none at 1 µm). The drained set is IP's plus IP-trapped pores only: Jaccard overlap 0.974
    (measured), asserted >= 0.95."""
    ip, viscous = _patterns(A, 1e-6)
    extra = viscous.drained & ~ip.drained
    assert not (ip.drained & ~viscous.drained).any()  # every pore IP drains
    assert np.all(ip.trapped[extra])  # the rest were trapped in IP
    assert 0 < extra.sum() <= 10 and _jaccard(viscous.drained, ip.drained) >= 0.95
