"""The documentation site (mkdocs.yml, docs/index.md): it builds with ``mkdocs build
--strict`` (every link, page and docstring resolves), its generated pages (the API and the
command-line reference) are what their scripts write, every public module is in the API
reference, and the Getting started tutorial's Python runs as written."""

from __future__ import annotations

import importlib.util
import re
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
SCRIPTS = ROOT / "examples" / "scripts"


def _script(name: str):
    spec = importlib.util.spec_from_file_location(name, SCRIPTS / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_the_api_reference_is_current_and_covers_every_public_module():
    api = _script("make_api_reference")
    text = (ROOT / "docs" / "api.md").read_text()
    assert text == api.page(), "run python examples/scripts/make_api_reference.py"
    listed = re.findall(r"^::: (\S+)$", text, re.M)
    assert sorted(listed) == sorted(api.public_modules())
    assert len(listed) == len(set(listed))


def test_the_cli_reference_is_current(monkeypatch):
    monkeypatch.setenv("COLUMNS", "80")
    cli = _script("make_cli_reference")
    assert (ROOT / "docs" / "cli.md").read_text() == cli.page(), (
        "run python examples/scripts/make_cli_reference.py"
    )


def test_the_site_builds_strictly(tmp_path):
    """Broken links, pages missing from the nav's files, docstrings mkdocstrings cannot
    parse: each is a warning, and --strict makes it an error."""
    done = subprocess.run(
        [sys.executable, "-m", "mkdocs", "build", "--strict", "-d", str(tmp_path / "site")],
        cwd=ROOT, capture_output=True, text=True, check=False,
        env={"NO_MKDOCS_2_WARNING": "1", "PATH": "/usr/bin:/bin", "HOME": str(tmp_path)},
    )  # fmt: skip
    assert done.returncode == 0, done.stderr[-3000:]
    assert (tmp_path / "site" / "api" / "index.html").is_file()


def _python_blocks(page: str) -> list[str]:
    text = (ROOT / "docs" / page).read_text()
    return re.findall(r"```python\n(.*?)```", text, re.S)


def test_getting_started_runs_as_written(monkeypatch):
    """The tutorial's runs (the sweep's needs the sweep it makes before; docs/sweeps.md's
    tests cover read_sweep)."""
    monkeypatch.chdir(ROOT)
    blocks = [b for b in _python_blocks("getting-started.md") if "porenet.run(" in b]
    assert len(blocks) == 2
    for block in blocks:
        namespace: dict[str, object] = {}
        exec(compile(block, "getting-started.md", "exec"), namespace)
        assert namespace["result"].summary["n_drained"] > 0
