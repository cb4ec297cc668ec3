"""docs/plugins.md "Adding an observer" and the README stay true to the source, with the
checks of :mod:`porenet.testing.tutorial` (the gravity plugin's tutorial uses the same)."""

from __future__ import annotations

from pathlib import Path

import pytest

from porenet.testing import tutorial

PLUGIN = Path(__file__).resolve().parents[1]
ROOT = PLUGIN.parents[1]
SOURCE = PLUGIN / "src" / "porenet_front"
TEXT = tutorial.section(ROOT / "docs" / "plugins.md", "## Adding an observer")
EXCERPTS = tutorial.excerpts(TEXT)


def test_the_tutorial_has_excerpts_of_every_module():
    paths = {path for path, _ in EXCERPTS}
    for name in ("config.py", "front.py", "observer.py", "plugin.py"):
        assert f"plugins/porenet-front/src/porenet_front/{name}" in paths
    assert "plugins/porenet-front/pyproject.toml" in paths
    assert "plugins/porenet-front/examples/front.toml" in paths


@pytest.mark.parametrize(("path", "code"), EXCERPTS, ids=lambda v: str(v)[:60])
def test_excerpt_is_verbatim_in_the_source(path, code):
    assert tutorial.missing_pieces(ROOT, path, code) == [], f"not verbatim in {path}"


def test_commands_name_files_that_exist():
    for path in tutorial.named_paths(TEXT, "plugins/porenet-front/"):
        assert (ROOT / path).exists(), path


def test_imports_nothing_private_from_porenet():
    assert tutorial.private_imports(tutorial.porenet_imports(SOURCE)) == []


def test_readme_lists_exactly_the_porenet_imports():
    assert tutorial.readme_imports(PLUGIN / "README.md") == tutorial.porenet_imports(SOURCE)
