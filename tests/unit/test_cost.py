"""The cost model (porenet.core.cost, docs/cost.md): estimates from the scene alone."""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace

import pytest

from porenet.config.loading import load_scene
from porenet.core.cost import CostEstimate, estimate_cost, format_bytes, format_seconds
from porenet.core.plan import estimated_cost as plan_cost
from porenet.core.plan import make_plan
from porenet.hooks import get_registry
from porenet.kinds.hertz.cost import adaptive_ramp
from porenet.kinds.invasion.cost import ip_drained_fraction
from porenet.kinds.viscous.cost import explicit_step, fracture_weight
from porenet.simulation import Simulation

SCENES = Path(__file__).resolve().parents[2] / "examples" / "scenes"


def within(pred: float, measured: float, factor: float) -> bool:
    return measured / factor <= pred <= measured * factor


def test_ip_drained_fractions():
    # Ensemble means measured for docs/cost.md: 0.112 at n = 100, 0.084 at n = 400 and 800
    assert within(ip_drained_fraction(100, at="breakthrough", trapping=True), 0.112, 1.1)
    assert within(ip_drained_fraction(400, at="breakthrough", trapping=True), 0.084, 1.15)
    assert ip_drained_fraction(100, at="complete", trapping=False) == 1.0
    assert within(ip_drained_fraction(400, at="complete", trapping=True), 0.514, 1.05)
    edge = ip_drained_fraction(100, at="breakthrough", trapping=True, injection="left-edge")
    assert within(edge, 0.34, 1.15)
    assert ip_drained_fraction(3, at="breakthrough", trapping=False) <= 1.0


def test_invasion_percolation_one_step_per_pore_and_no_updates(scene_dict):
    est = estimate_cost(load_scene(scene_dict))
    assert est.steps == est.drained and est.mechanical_updates == 0
    assert est.memory_bytes == pytest.approx(240 * 31**2, rel=0.01)
    assert est.wall_seconds is not None and est.wall_seconds < 0.1


def test_max_drained_caps_the_estimate(scene_dict):
    est = estimate_cost(load_scene(scene_dict | {"stop": {"max_drained": 7}}))
    assert est.drained == 7


def test_fig1b_within_a_factor_of_the_documented_run():
    # docs/performance.md: 12 435 drained pores, 147 455 steps, 58 s
    est = estimate_cost(load_scene(SCENES / "fig1b.toml"))
    assert within(est.drained, 12_435, 2) and within(est.steps, 147_455, 2)
    assert within(est.wall_seconds, 58, 3) and est.mechanical_updates == 0


def test_fig5_fractures_and_updates_the_solid():
    # docs/fig5-table.md, N_f = 10: 790 drained, 30 793 steps, 19 148 updates, 221 s
    est = estimate_cost(load_scene(SCENES / "fig5.toml"))
    assert within(est.drained, 790, 1.5) and within(est.steps, 30_793, 2)
    assert within(est.mechanical_updates, 19_148, 2) and within(est.wall_seconds, 221, 3)
    assert any("fracturing" in note for note in est.notes)


def test_stiff_solid_and_coupling_schedules():
    assert adaptive_ramp(0.001) == 0.0 and adaptive_ramp(1.0) == 1.0
    assert 0 < adaptive_ramp(0.03) < 1.0
    assert fracture_weight(None) == 0 and fracture_weight(0.1) == 0 and fracture_weight(10) == 1
    base = SCENES / "fig5.toml"
    every = estimate_cost(load_scene(base, ["lattice.n=50", "solid.coupling=every-step"]))
    assert every.mechanical_updates == every.steps
    interval = ["lattice.n=50", "solid.coupling=interval", "solid.coupling_interval=4"]
    est = estimate_cost(load_scene(base, interval))
    assert est.mechanical_updates == pytest.approx(est.steps / 4, abs=1)


@pytest.mark.parametrize(
    ("ca", "integrator"), [(1e-2, "explicit"), (1e-4, "rkc"), (1e-6, "implicit")]
)
def test_step_and_integrator_agree_with_the_model(ca, integrator):
    scene = load_scene(
        {"seed": 3, "lattice": {"n": 20, "disorder": 0.3},
         "fluid": {"kind": "viscous", "capillary_number": ca}}
    )  # fmt: skip
    reg = get_registry()
    sim = Simulation(make_plan(scene, reg), reg)
    sim.fluid.setup(sim.state)
    assert sim.fluid.integrator == integrator
    # the estimate assumes the widest throats around one pore: a lower bound, close for large n
    assert 0.75 * sim.fluid.dt_stable <= explicit_step(scene, 0.3) <= sim.fluid.dt_stable
    notes = " ".join(estimate_cost(scene).notes)
    assert ("implicit" in notes) == (integrator == "implicit")
    assert ("rkc" in notes) == (integrator == "rkc")


def test_unknown_kinds_give_unknown_not_an_error():
    scene = SimpleNamespace(
        lattice=SimpleNamespace(kind="square", n=10, disorder=0.3),
        fluid=SimpleNamespace(kind="somebody.else"),
        solid=SimpleNamespace(kind="rigid"),
        stop=SimpleNamespace(at="breakthrough", max_drained=None),
        injection=SimpleNamespace(at="centre"),
    )
    est = estimate_cost(scene)
    assert est.steps is None and est.wall_seconds is None and est.drained is None
    assert "unknown" in "\n".join(est.lines())
    scene.lattice = SimpleNamespace(kind="graph")  # no size at all
    est = estimate_cost(scene)
    assert est.drained is None and est.memory_bytes is None and est.notes
    # a config the model cannot read at all: the plan still gets an (unknown) estimate
    broken = SimpleNamespace(lattice=SimpleNamespace(kind="square", n=10))
    est = plan_cost(broken)
    assert isinstance(est, CostEstimate) and est.wall_seconds is None
    assert est.notes[0].startswith("no estimate")


def test_pressure_control_has_no_step_estimate():
    scene = load_scene(
        {"lattice": {"n": 20, "disorder": 0.3},
         "fluid": {"kind": "viscous", "control": "pressure", "injection_pressure": 1e6}}
    )  # fmt: skip
    est = estimate_cost(scene)
    assert est.drained is not None and est.steps is None and est.wall_seconds is None


def test_formats():
    assert format_bytes(None) == "unknown" and format_bytes(174e6) == "~170 MB"
    assert format_bytes(9.6e6) == "~9.6 MB"
    assert format_seconds(0.01) == "< 0.1 s" and format_seconds(58) == "~58 s"
    assert format_seconds(221) == "~3.7 min" and format_seconds(7200) == "~2 h"


def test_local_steps_cut_the_rkc_estimate_on_large_lattices_only():
    # Measured: 773 s single-rate, 256 s with local steps (one thread), n = 400, Ca = 1e-5
    def wall(*overrides):
        scene = load_scene(SCENES / "fig1b.toml", ["fluid.capillary_number=1e-5", *overrides])
        return estimate_cost(scene).wall_seconds

    off, auto = wall("fluid.local_steps=off"), wall()
    assert within(off, 773.0, 2.0) and within(auto, 256.0, 2.0)
    assert 0.3 < auto / off < 0.4
    small = ("lattice.n=100",)
    assert wall(*small) == wall(*small, "fluid.local_steps=off")  # below the box auto needs


def test_frictional_solid_is_costed_like_hertz_with_its_own_update():
    # tests/benchmarks/bench_frictional.py run (2026-12-06): 791 drained, 31 396 steps,
    # 17 086 updates, 577 s on the project's machine with nothing else running
    est = estimate_cost(load_scene(SCENES / "fig5-mindlin.toml"))
    assert within(est.drained, 791, 1.5) and within(est.steps, 31_396, 2)
    assert within(est.mechanical_updates, 17_071, 2) and within(est.wall_seconds, 577, 3)
    assert not any("no cost model" in note for note in est.notes)
    sliding = estimate_cost(load_scene(SCENES / "fig5-mindlin.toml", ["solid.friction=0.3"]))
    assert any("sliding" in note for note in sliding.notes)


@pytest.mark.parametrize(
    ("ratio", "nf", "measured"),
    [
        # CPU time with sliding over the same run's without, both made with one code (adae027)
        # on one machine, one thread each (docs/fracture-shear-n400.md, "What sliding costs":
        # `python examples/scripts/fracture_shear.py --n 400 --records
        # docs/data/fracture-shear-n400/*.jsonl --sliding-cost T`): K_t/K_n = 0.5 at N_f = 1
        # (458 / 194 s); 0.8 at N_f = 1, 3 and 10 (492 / 219, 947 / 451, 1 794 / 798); 0.1 at
        # N_f = 3 and 10 (625 / 427, 1 083 / 855). Below the crossover nothing slides
        # much: 0.1 and 0.8 at N_f = 0.1, 1.05x and 1.09x (890 / 846, 843 / 771 s, the sixth
        # session's runs, docs/fracture-shear-n400.md).
        (0.5, 1.0, 2.36),
        (0.8, 1.0, 2.25),
        (0.8, 3.0, 2.10),
        (0.8, 10.0, 2.25),
        (0.1, 3.0, 1.46),
        (0.1, 10.0, 1.27),
        (0.1, 0.1, 1.05),
        (0.8, 0.1, 1.09),
    ],
)
def test_sliding_is_costed_as_measured_at_n_400(ratio, nf, measured):
    import sys

    sys.path.insert(0, str(SCENES.parent / "scripts"))
    from fig5 import make_scene

    solid = {"kind": "hertz-mindlin", "shear_stiffness_ratio": ratio, "rotation": "held"}
    stick = estimate_cost(load_scene(make_scene(400, nf, seed=1, solid=solid)))
    slide = estimate_cost(load_scene(make_scene(400, nf, seed=1, solid=solid | {"friction": 0.3})))
    assert within(slide.wall_seconds / stick.wall_seconds, measured, 1.3)
    assert slide.drained == stick.drained and slide.mechanical_updates == stick.mechanical_updates
