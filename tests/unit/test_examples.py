"""Every example scene in examples/scenes validates (plugin scenes when the plugin loads)."""

from __future__ import annotations

from pathlib import Path

import pytest

from porenet.config.loading import load_scene, read_toml
from porenet.hooks import build_registry

SCENES = sorted((Path(__file__).resolve().parents[2] / "examples" / "scenes").glob("*.toml"))


@pytest.mark.parametrize("path", SCENES, ids=[p.stem for p in SCENES])
def test_example_scene_validates(path):
    registry = build_registry()
    kind = read_toml(path)["lattice"].get("kind", "square")
    if ("lattice", kind) not in registry:
        import sys

        sys.path.insert(0, str(path.parents[2] / "plugins" / "porenet-correlated" / "src"))
        import porenet_correlated.plugin

        registry = build_registry(extra_plugins={"correlated": porenet_correlated.plugin})
    load_scene(path, registry=registry)


def test_fig5_script_runs_on_a_small_lattice(tmp_path):
    import subprocess
    import sys

    script = Path(__file__).resolve().parents[2] / "examples" / "scripts" / "fig5.py"
    table = tmp_path / "fig5.md"
    out = subprocess.run(
        [sys.executable, str(script), "--n", "20", "--nf", "10", "0.01", "--table", str(table)],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert out.returncode == 0, out.stderr
    assert "N_f = 10" in out.stdout and "rigid" in out.stdout
    assert table.read_text().count("\n| ") == 4  # the header row and three runs


def test_accuracy_seeds_script_runs_on_a_small_lattice(tmp_path):
    import subprocess
    import sys

    script = Path(__file__).resolve().parents[2] / "examples" / "scripts" / "accuracy_seeds.py"
    table = tmp_path / "seeds.md"
    args = ["--n", "12", "--ca", "1e-4", "--seeds", "1", "--table", str(table)]
    out = subprocess.run(
        [sys.executable, str(script), *args], capture_output=True, text=True, timeout=300
    )
    assert out.returncode == 0, out.stderr
    rows = [line for line in table.read_text().splitlines() if line.startswith("| ")]
    assert len(rows) == 1 + 5  # the header and every setting
    assert "| explicit, tight (reference) | 1.000 | 1.000 | 0.00e+00 |" in table.read_text()
