"""docs/plugins.md "Adding a fluid model" and the README stay true to the source.

* Every code block of the tutorial preceded by ``<!-- excerpt: PATH -->`` appears verbatim in
  ``PATH`` (relative to the repository root); a line ``# (...)`` in a block marks an elision,
  and each piece between elisions must appear on its own.
* The plugin imports from porenet exactly what its README lists, and nothing private
  (no name or module component starting with ``_``, nothing from ``porenet.kinds``).

The checks are :mod:`porenet.testing.tutorial`'s, shared with the other tutorials' plugins.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from porenet.testing import tutorial

PLUGIN = Path(__file__).resolve().parents[1]
ROOT = PLUGIN.parents[1]
SOURCE = PLUGIN / "src" / "porenet_gravity"
TEXT = tutorial.section(ROOT / "docs" / "plugins.md", "## Adding a fluid model")
EXCERPTS = tutorial.excerpts(TEXT)


def test_the_tutorial_has_excerpts_of_every_module():
    paths = {path for path, _ in EXCERPTS}
    for name in ("config.py", "model.py", "plugin.py"):
        assert f"plugins/porenet-gravity/src/porenet_gravity/{name}" in paths
    assert "plugins/porenet-gravity/pyproject.toml" in paths
    assert "plugins/porenet-gravity/examples/gravity.toml" in paths


@pytest.mark.parametrize(("path", "code"), EXCERPTS, ids=lambda v: str(v)[:60])
def test_excerpt_is_verbatim_in_the_source(path, code):
    assert tutorial.missing_pieces(ROOT, path, code) == [], f"not verbatim in {path}"


def test_commands_name_files_that_exist():
    for path in tutorial.named_paths(TEXT, "plugins/porenet-gravity/"):
        assert (ROOT / path).exists(), path


def test_imports_nothing_private_from_porenet():
    assert tutorial.private_imports(tutorial.porenet_imports(SOURCE)) == []


def test_readme_lists_exactly_the_porenet_imports():
    assert tutorial.readme_imports(PLUGIN / "README.md") == tutorial.porenet_imports(SOURCE)
