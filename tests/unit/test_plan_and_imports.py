"""Only the effects a scene calls for are built; importing porenet stays light."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

import porenet
from porenet.config.loading import load_scene
from porenet.core.plan import make_plan
from porenet.hooks import get_registry
from porenet.simulation import Simulation


def test_rigid_ip_scene_builds_no_solid_coupler_or_pressure(scene_dict):
    reg = get_registry()
    plan = make_plan(load_scene(scene_dict), reg)
    assert not plan.builds("solid") and not plan.builds("coupler")
    assert plan.effects["viscous_dissipation"] is False and plan.effects["deformation"] is False
    sim = Simulation(plan, reg)
    assert sim.solid is None and sim.coupler is None and sim.observers == []
    assert type(sim.fluid).solves_pressure is False
    result = sim.run()
    assert result.state.pressure is None and result.data.pressure is None
    assert result.data.final_apertures is None
    assert "rigid: apertures never change" in plan.describe()
    fluid = next(m for m in plan.models if m.family == "fluid")
    assert fluid.reason == "quasi-static: no pressure solve"
    # the plan predicts capillary fingering, one step per drained pore and no solid update
    assert plan.regime is not None and plan.regime[0] == "CF"
    assert plan.cost.steps == plan.cost.drained and plan.cost.mechanical_updates == 0


def test_apertures_never_change_in_rigid_medium(scene_dict):
    result = porenet.run(scene_dict | {"stop": {"at": "complete"}})
    assert (result.state.apertures == result.lattice.initial_apertures).all()


def test_import_porenet_loads_no_plugin_numba_h5py_matplotlib():
    code = (
        "import sys, porenet; "
        "heavy = [m for m in ('numba', 'h5py', 'matplotlib', 'porenet.kinds', 'pluggy') "
        "if m in sys.modules]; print(heavy)"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]"


SCENES = Path(__file__).resolve().parents[2] / "examples" / "scenes"

#: Packages no light command may import (``porenet.x`` also forbids ``porenet.x.y``).
HEAVY_PACKAGES = (
    "numba",
    "llvmlite",
    "scipy",
    "h5py",
    "matplotlib",
    "porenet.kernels",
    "porenet.viz",
    "porenet.simulation",
    "porenet.io",
    "porenet.sweep",
    "porenet.analysis.classify",
    "porenet.analysis.features",
    "porenet.analysis.fractal",
)
#: The built-ins' implementation modules: a light command imports only their configs
#: (``porenet/kinds/*/config.py``).
IMPLEMENTATIONS = (
    "porenet.kinds.square.model",
    "porenet.kinds.invasion.model",
    "porenet.kinds.viscous.model",
    "porenet.kinds.viscous.local_steps",
    "porenet.kinds.hertz.model",
    "porenet.kinds.pressure_aperture.model",
    "porenet.io.progress",
    "porenet.io.writer",
    "porenet.kinds.rules.model",
    "porenet.kinds.theory.model",
)

#: Run in a fresh interpreter: ``import porenet`` (argv null) or ``porenet.cli.main.main(argv)``
#: (its output swallowed), then report the exit status and every loaded module as JSON.
_PROBE = """
import contextlib, io, json, sys
argv = json.loads(sys.argv[1])
status = None
if argv is None:
    import porenet
else:
    from porenet.cli.main import main
    with contextlib.redirect_stdout(io.StringIO()):
        try:
            status = main(argv)
        except SystemExit as exc:  # --help
            status = exc.code
print(json.dumps({"status": status, "modules": sorted(sys.modules)}))
"""

LIGHT_COMMANDS = {
    "import porenet": None,
    "--help": ["--help"],
    "validate fig1b (viscous, rigid)": ["validate", str(SCENES / "fig1b.toml")],
    "validate fig5 (viscous, hertz)": ["validate", str(SCENES / "fig5.toml")],
    "validate ip-400 --show": ["validate", "--show", str(SCENES / "ip-400.toml")],
    "plan fig1b": ["plan", str(SCENES / "fig1b.toml")],
    "plan fig5": ["plan", str(SCENES / "fig5.toml")],
    "plan ip-400": ["plan", str(SCENES / "ip-400.toml")],
    "schema": ["schema"],
    "plugins": ["plugins"],
}


@pytest.mark.parametrize("argv", LIGHT_COMMANDS.values(), ids=LIGHT_COMMANDS.keys())
def test_light_commands_import_no_numerics_plotting_or_implementation(argv):
    """``porenet --help``, ``validate``, ``plan``, ``schema`` and ``plugins`` build the scene
    schema from the built-ins' config modules alone: no numba, scipy, h5py or matplotlib, no
    kernels, and no built-in implementation (registered as ``"module:Class"`` strings). Only
    the built-ins are loaded (``PORENET_PLUGINS=``), so an unrelated plugin installed in the
    environment cannot make the test fail."""
    env = os.environ | {"PORENET_PLUGINS": ""}
    out = subprocess.run(
        [sys.executable, "-c", _PROBE, json.dumps(argv)],
        capture_output=True,
        text=True,
        check=True,
        env=env,
    )
    report = json.loads(out.stdout)
    assert report["status"] in (None, 0), out.stderr
    modules = report["modules"]
    heavy = [m for m in modules for p in HEAVY_PACKAGES if m == p or m.startswith(p + ".")]
    assert heavy == []
    assert [m for m in modules if m in IMPLEMENTATIONS] == []
    if argv is not None and argv != ["--help"]:  # the schema was built from every config
        assert {"porenet.kinds.square.plugin", "porenet.kinds.viscous.config"} <= set(modules)


def test_a_fluid_model_that_stalls_is_reported_not_a_hang(scene_dict):
    import pytest

    from porenet.core.errors import NumericalError

    sim = Simulation.from_scene(scene_dict)
    sim.fluid.advance = lambda state, max_events: 0  # a broken model: never drains, no time
    with pytest.raises(NumericalError, match="made no progress"):
        sim.run()


def test_wall_time_includes_the_build(scene_dict):
    sim = Simulation.from_scene(scene_dict)
    result = sim.run()
    assert result.summary["wall_time_s"] >= sim.build_time > 0


def test_viscous_scene_plans_a_pressure_solve_and_reports_ca_star():
    scene = {
        "lattice": {"n": 400, "disorder": 0.3, "pore_size": 1e-7},
        "fluid": {"kind": "viscous", "capillary_number": 9e-4},
    }
    reg = get_registry()
    plan = make_plan(load_scene(scene), reg)
    assert plan.effects["viscous_dissipation"] is True
    assert not plan.builds("solid")
    # Fig. 1b sits at the CF/VF crossover: Ca* = 9e-4 * 400 / (0.3 / 0.91) = 1.092
    ca_star = plan.numbers["Ca* = Ca (L/a) / [lambda/(1-lambda^2)]"]
    assert abs(ca_star - 9e-4 * 400 / (0.3 / (1 - 0.09))) < 1e-12
    sim = Simulation(plan, reg)
    assert type(sim.fluid).solves_pressure is True and sim.solid is None
    fluid = next(m for m in plan.models if m.family == "fluid")
    assert fluid.built and fluid.reason == "pressure solve in the defending fluid"
    assert plan.regime is not None and plan.regime[0] == "CF/VF"
    text = plan.describe()
    for expected in ("predicted regime: CF/VF", "estimated cost", "fluid steps", "wall time"):
        assert expected in text


def test_hertz_scene_builds_solid_and_coupler():
    scene = {
        "lattice": {"n": 20, "disorder": 0.1},
        "fluid": {"kind": "viscous", "capillary_number": 2.5e-3},
        "solid": {"kind": "hertz", "fracturing_number": 10.0, "prestrain": 0.05},
    }
    reg = get_registry()
    plan = make_plan(load_scene(scene), reg)
    assert plan.builds("solid") and plan.builds("coupler")
    assert plan.effects["deformation"] is True
    coupler = next(m for m in plan.models if m.family == "coupler")
    assert coupler.kind == "pressure-aperture" and "adaptive" in coupler.reason
    assert plan.numbers["fracturing number N_f"] == 10.0 and plan.regime[0] == "FR"
    assert plan.cost.mechanical_updates > 0
    sim = Simulation(plan, reg)
    assert sim.solid is not None and sim.coupler is not None


def test_the_simulation_runs_the_plan_make_plan_returns(scene_dict):
    reg = get_registry()
    plan = make_plan(load_scene(scene_dict), reg)
    assert Simulation(plan, reg).plan is plan
    assert Simulation.from_scene(scene_dict, registry=reg).plan == plan


def test_classifier_slot_in_the_plan(scene_dict):
    reg = get_registry()
    plan = make_plan(load_scene(scene_dict), reg)
    slot = [m for m in plan.models if m.family == "classifier"]
    assert len(slot) == 1
    if ("classifier", "none") in reg:
        plan = make_plan(load_scene(scene_dict | {"classifier": {"kind": "none"}}), reg)
        slot = next(m for m in plan.models if m.family == "classifier")
        assert not slot.built and slot.reason == "not requested"
