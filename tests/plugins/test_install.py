"""The example plugin really installs and works through porenet's entry points and CLI.

``plugins/porenet-correlated`` is installed with pip into a temporary ``--target`` directory
(``--no-deps``: porenet itself is never reinstalled; ``--no-build-isolation``: the build uses
the setuptools already installed, no network). porenet is then run in subprocesses with that
directory on ``PYTHONPATH`` and strict plugin loading, so a plugin that fails to load fails the
test instead of being skipped.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import h5py
import pytest

ROOT = Path(__file__).resolve().parents[2]
PLUGIN = ROOT / "plugins" / "porenet-correlated"

SCENE = """\
seed = 2

[lattice]
kind = "correlated.gaussian"
n = 40
disorder = 0.3
correlation_length = 4

[fluid]
kind = "invasion-percolation"
"""


@pytest.fixture(scope="module")
def site(tmp_path_factory) -> Path:
    """Directory into which pip installed the plugin."""
    work = tmp_path_factory.mktemp("plugin-install")
    # build from a copy, so that pip's in-tree build leaves nothing in the repository
    source = work / "source"
    shutil.copytree(
        PLUGIN,
        source,
        ignore=shutil.ignore_patterns(
            "build", "*.egg-info", "__pycache__", ".pytest_cache", "tests"
        ),
    )
    target = work / "site"
    cmd = [
        sys.executable, "-m", "pip", "install", "--no-deps", "--no-build-isolation",
        "--no-input", "--disable-pip-version-check", "--target", str(target), str(source),
    ]  # fmt: skip
    proc = subprocess.run(cmd, capture_output=True, text=True, check=False)
    if proc.returncode != 0:
        pytest.fail(
            f"pip install failed (exit {proc.returncode}):\n{proc.stdout}\n{proc.stderr}",
            pytrace=False,
        )
    assert (target / "porenet_correlated" / "lattice.py").is_file()
    assert not (target / "porenet").exists(), "--no-deps must not install porenet"
    return target


def porenet_cli(site: Path, cwd: Path, *args: str) -> subprocess.CompletedProcess[str]:
    env = {**os.environ, "PYTHONPATH": str(site), "PORENET_STRICT_PLUGINS": "1"}
    env.pop("PORENET_PLUGINS", None)
    return subprocess.run(
        [sys.executable, "-m", "porenet", *args],
        capture_output=True,
        text=True,
        check=False,
        env=env,
        cwd=cwd,
        timeout=120,
    )


def test_plugins_lists_the_kind_and_its_package(site, tmp_path):
    proc = porenet_cli(site, tmp_path, "plugins")
    assert proc.returncode == 0, proc.stderr
    rows = [line.split() for line in proc.stdout.splitlines()]
    assert ["lattice", "correlated.gaussian", "porenet-correlated", "correlated"] in rows, (
        proc.stdout
    )
    assert "failed" not in proc.stderr, proc.stderr


def test_scene_runs_and_records_the_kind(site, tmp_path):
    (tmp_path / "scene.toml").write_text(SCENE)
    proc = porenet_cli(site, tmp_path, "run", "scene.toml", "-o", "out.h5", "-q")
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout == ""
    with h5py.File(tmp_path / "out.h5", "r") as f:
        scene = json.loads(f.attrs["scene"])
    assert scene["lattice"]["kind"] == "correlated.gaussian"
    assert scene["lattice"]["correlation_length"] == 4


def test_misspelt_field_exits_2_naming_it(site, tmp_path):
    bad = SCENE.replace("correlation_length = 4", "corelation_length = 4")
    (tmp_path / "bad.toml").write_text(bad)
    proc = porenet_cli(site, tmp_path, "run", "bad.toml", "-o", "bad.h5", "-q")
    assert proc.returncode == 2, (proc.stdout, proc.stderr)
    assert "lattice.corelation_length" in proc.stderr
    assert "did you mean 'correlation_length'" in proc.stderr
    assert "Traceback" not in proc.stderr
    assert not (tmp_path / "bad.h5").exists()
