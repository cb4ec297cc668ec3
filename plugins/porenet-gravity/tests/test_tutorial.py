"""docs/plugins.md "Adding a fluid model" and the README stay true to the source.

* Every code block of the tutorial preceded by ``<!-- excerpt: PATH -->`` appears verbatim in
  ``PATH`` (relative to the repository root); a line ``# (...)`` in a block marks an elision,
  and each piece between elisions must appear on its own.
* The plugin imports from porenet exactly what its README lists, and nothing private
  (no name or module component starting with ``_``, nothing from ``porenet.builtin``).
"""

from __future__ import annotations

import ast
import re
from pathlib import Path

import pytest

PLUGIN = Path(__file__).resolve().parents[1]
ROOT = PLUGIN.parents[1]
TUTORIAL = ROOT / "docs" / "plugins.md"
SECTION = "## Adding a fluid model"
ELISION = "# (...)"
EXCERPT = re.compile(r"<!-- excerpt: (?P<path>\S+) -->\n```[a-z]*\n(?P<code>.*?)\n```", re.S)


def tutorial() -> str:
    text = TUTORIAL.read_text()
    assert SECTION in text, f"{TUTORIAL} lost its section {SECTION!r}"
    section = text.split(SECTION, 1)[1]
    return section.split("\n## ", 1)[0]  # up to the next top-level section, if any


def excerpts() -> list[tuple[str, str]]:
    return [(m["path"], m["code"]) for m in EXCERPT.finditer(tutorial())]


def test_the_tutorial_has_excerpts_of_every_module():
    paths = {path for path, _ in excerpts()}
    for name in ("config.py", "model.py", "plugin.py"):
        assert f"plugins/porenet-gravity/src/porenet_gravity/{name}" in paths
    assert "plugins/porenet-gravity/pyproject.toml" in paths
    assert "plugins/porenet-gravity/examples/gravity.toml" in paths


@pytest.mark.parametrize(("path", "code"), excerpts(), ids=lambda v: str(v)[:60])
def test_excerpt_is_verbatim_in_the_source(path, code):
    source = (ROOT / path).read_text()
    pieces = [p.strip("\n") for p in code.split(ELISION)]
    for piece in pieces:
        assert piece, f"empty piece in an excerpt of {path}"
        assert piece in source, f"not in {path}:\n{piece}"


def test_commands_name_files_that_exist():
    text = tutorial()
    for path in re.findall(r"plugins/porenet-gravity/[\w./-]+\w", text):
        assert (ROOT / path).exists(), path


def porenet_imports() -> dict[str, set[str]]:
    """``{module: names}`` the plugin's source imports from porenet."""
    found: dict[str, set[str]] = {}
    for file in (PLUGIN / "src" / "porenet_gravity").glob("*.py"):
        for node in ast.walk(ast.parse(file.read_text())):
            if isinstance(node, ast.ImportFrom) and (node.module or "").startswith("porenet."):
                found.setdefault(node.module, set()).update(a.name for a in node.names)
            elif isinstance(node, ast.Import):
                for alias in node.names:
                    assert not alias.name.startswith("porenet."), (file, alias.name)
    return found


def test_imports_nothing_private_from_porenet():
    for module, names in porenet_imports().items():
        assert not module.startswith("porenet.builtin"), module
        for part in [*module.split("."), *names]:
            assert not part.startswith("_"), (module, part)


def test_readme_lists_exactly_the_porenet_imports():
    readme = (PLUGIN / "README.md").read_text()
    table = readme.split("## What it imports from porenet", 1)[1].split("\n\n## ", 1)[0]
    listed: dict[str, set[str]] = {}
    for row in re.findall(r"^\| `(porenet[\w.]*)` \| (.+?) \|", table, re.M):
        listed[row[0]] = set(re.findall(r"`(\w+)`", row[1]))
    assert listed == porenet_imports()
