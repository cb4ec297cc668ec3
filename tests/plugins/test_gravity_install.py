"""The gravity plugin really installs and works through porenet's entry points and CLI.

As ``test_install.py`` does for ``porenet-correlated``: ``plugins/porenet-gravity`` is
installed with pip into a temporary ``--target`` directory (``--no-deps``: porenet is never
reinstalled; ``--no-build-isolation``: the build uses the installed setuptools, no network),
then porenet runs in subprocesses with that directory on ``PYTHONPATH`` and strict plugin
loading, on the plugin's example scene (``plugins/porenet-gravity/examples/gravity.toml``).
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
PLUGIN = ROOT / "plugins" / "porenet-gravity"
SCENE = PLUGIN / "examples" / "gravity.toml"


@pytest.fixture(scope="module")
def site(tmp_path_factory) -> Path:
    """Directory into which pip installed the plugin."""
    work = tmp_path_factory.mktemp("gravity-install")
    source = work / "source"  # build from a copy: pip's in-tree build leaves nothing behind
    shutil.copytree(
        PLUGIN,
        source,
        ignore=shutil.ignore_patterns(
            "build", "*.egg-info", "__pycache__", ".pytest_cache", "tests", "docs", "examples"
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
    assert (target / "porenet_gravity" / "model.py").is_file()
    assert (target / "porenet_gravity" / "py.typed").is_file()
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
    assert ["fluid", "gravity.invasion-percolation", "porenet-gravity", "gravity"] in rows, (
        proc.stdout
    )
    assert "failed" not in proc.stderr, proc.stderr


def test_example_scene_runs_and_records_the_kind(site, tmp_path):
    proc = porenet_cli(site, tmp_path, "run", str(SCENE), "-o", "out.h5", "-q")
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout == ""
    with h5py.File(tmp_path / "out.h5", "r") as f:
        scene = json.loads(f.attrs["scene"])
        summary = dict(f["summary"].attrs)
    assert scene["fluid"]["kind"] == "gravity.invasion-percolation"
    assert scene["fluid"]["bond_number"] == 0.005
    assert summary["bond_number"] == 0.005
    assert summary["hydrostatic_gradient"] == pytest.approx(1400.0)  # Bo gamma / a^2
    assert summary["stop_reason"] == "breakthrough"
    assert 0 < summary["front_width"] < summary["front_position"]


def test_centre_injection_exits_2_naming_the_requirement(site, tmp_path):
    proc = porenet_cli(
        site, tmp_path, "run", str(SCENE), "--set", "injection.at=centre", "-o", "bad.h5", "-q"
    )
    assert proc.returncode == 2, (proc.stdout, proc.stderr)
    assert "left-edge" in proc.stderr
    assert "Traceback" not in proc.stderr
    assert not (tmp_path / "bad.h5").exists()
