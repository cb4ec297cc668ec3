"""The paper's sweep files (examples/sweeps/): each parses, every expanded point is a valid
scene (the engine's own loader, porenet.sweep.spec), full-size files are at the paper's
n = 400 and their small twins at n = 64-100, cheap enough for CI by the cost model."""

from __future__ import annotations

from pathlib import Path

import pytest

from porenet.config.loading import load_scene
from porenet.core.cost import estimate_cost
from porenet.sweep.spec import columns, expand, load_sweep

SWEEPS = Path(__file__).resolve().parents[2] / "examples" / "sweeps"
FILES = sorted(SWEEPS.glob("*.toml"))
FIGURES = ("fig2", "fig3", "fig4", "fig5")


@pytest.fixture(scope="module")
def expanded():
    return {path.stem: (load_sweep(path), expand(load_sweep(path))) for path in FILES}


def test_every_figure_has_a_full_size_file_and_a_small_twin():
    names = {path.stem for path in FILES}
    assert {*FIGURES, *(f"{f}-small" for f in FIGURES)} <= names


@pytest.mark.parametrize("path", FILES, ids=lambda p: p.name)
def test_sweep_file_expands_into_valid_scenes(path, expanded):
    sweep, runs = expanded[path.stem]
    assert sweep.spec.name == path.stem
    assert runs and len({r.run_id for r in runs}) == len(runs)
    for run in runs:
        scene = load_scene(run.scene)  # validated again, as `porenet run` would
        assert scene.seed == run.seed
        if path.stem.removesuffix("-small") in FIGURES:  # the paper's n, or a small twin
            n = scene.lattice.n
            assert n == 400 if "-small" not in path.stem else 64 <= n <= 100


def test_the_axes_are_the_papers(expanded):
    spec2, runs2 = expanded["fig2"]
    assert len({r.point for r in runs2}) >= 36  # the paper's Fig. 2 has at least 36 points
    assert {"lattice.disorder", "fluid.capillary_number"} <= set(columns(spec2.spec))
    for name in ("fig3", "fig3-small", "fig5", "fig5-small"):
        spec, runs = expanded[name]
        assert {"ca_star", "solid.fracturing_number"} <= set(columns(spec.spec))
        assert all(r.scene["solid"]["kind"] == "hertz" for r in runs)
    for name in ("fig4", "fig4-small"):
        _, runs = expanded[name]
        assert {r.scene["lattice"]["disorder"] for r in runs} == {0.1}
        cas = [r.params["fluid.capillary_number"] for r in runs]
        assert cas == sorted(cas, reverse=True)  # Ca decreasing: VF to CF
    _, runs5 = expanded["fig5"]
    assert {round(r.params["ca_star"], 9) for r in runs5} == {10}


@pytest.mark.parametrize("name", [f"{f}-small" for f in FIGURES])
def test_small_twins_are_cheap(name, expanded):
    """The cost model (docs/cost.md, a factor ~2-3) gives under a minute of runs on 2 workers."""
    _, runs = expanded[name]
    wall = sum(estimate_cost(load_scene(r.scene)).wall_seconds for r in runs)
    assert wall / 2 < 60.0
