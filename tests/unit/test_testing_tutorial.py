"""porenet.testing.tutorial, the checks behind the plugins' tests/test_tutorial.py, catch what
they are for: an excerpt that drifted from its source, a private import, a README that lists
other imports than the code makes."""

from __future__ import annotations

import subprocess
import sys

import pytest

from porenet.testing import tutorial

DOC = """# Plugins

## Adding a thing

Text.

<!-- excerpt: pkg/mod.py -->
```python
def f(x):
# (...)
    return x + 1
```

<!-- excerpt: pkg/mod.py -->
```python
def g():
```

See pkg/mod.py and pkg/examples/scene.toml.

## Next section

<!-- excerpt: pkg/other.py -->
```python
outside
```
"""

SOURCE = """from porenet.core.interfaces import Observer
from porenet.core.state import State


def f(x):
    y = 2
    return x + 1
"""

README = """# pkg

## What it imports from porenet

| module | names | used in |
|---|---|---|
| `porenet.core.interfaces` | `Observer` | `mod.py` |
| `porenet.core.state` | `State` | `mod.py` |

## Tests
"""


@pytest.fixture
def tree(tmp_path):
    (tmp_path / "docs").mkdir()
    (tmp_path / "docs" / "plugins.md").write_text(DOC)
    (tmp_path / "pkg").mkdir()
    (tmp_path / "pkg" / "mod.py").write_text(SOURCE)
    (tmp_path / "pkg" / "README.md").write_text(README)
    return tmp_path


def test_section_and_its_excerpts(tree):
    text = tutorial.section(tree / "docs" / "plugins.md", "## Adding a thing")
    assert "Next section" not in text
    found = tutorial.excerpts(text)
    assert [path for path, _ in found] == ["pkg/mod.py", "pkg/mod.py"]
    assert found[0][1] == "def f(x):\n# (...)\n    return x + 1"
    with pytest.raises(AssertionError, match="lost its section"):
        tutorial.section(tree / "docs" / "plugins.md", "## Adding a solid")


def test_pieces_between_elisions_must_each_be_verbatim(tree):
    text = tutorial.section(tree / "docs" / "plugins.md", "## Adding a thing")
    (first, code), (_, drifted) = tutorial.excerpts(text)
    assert tutorial.missing_pieces(tree, first, code) == []
    assert tutorial.missing_pieces(tree, first, drifted) == ["def g():"]
    assert tutorial.missing_pieces(tree, first, "# (...)\nreturn") == [""]  # empty piece


def test_named_paths(tree):
    text = tutorial.section(tree / "docs" / "plugins.md", "## Adding a thing")
    assert sorted(set(tutorial.named_paths(text, "pkg/"))) == [
        "pkg/examples/scene.toml",
        "pkg/mod.py",
    ]


def test_imports_private_names_and_readme(tree):
    imports = tutorial.porenet_imports(tree / "pkg")
    assert imports == {"porenet.core.interfaces": {"Observer"}, "porenet.core.state": {"State"}}
    assert tutorial.private_imports(imports) == []
    assert tutorial.readme_imports(tree / "pkg" / "README.md") == imports
    bad = {
        "porenet._version": {"__version__"},
        "porenet.kinds.hertz.model": {"HertzSolid"},
        "porenet.simulation": {"_shorthand_observers"},
    }
    assert tutorial.private_imports(bad) == [
        "porenet._version: _version",
        "porenet._version: __version__",
        "porenet.kinds.hertz.model",
        "porenet.simulation: _shorthand_observers",
    ]
    (tree / "pkg" / "more.py").write_text("import porenet.core.state\n")
    with pytest.raises(AssertionError):
        tutorial.porenet_imports(tree / "pkg")


def test_importing_it_imports_nothing_else_of_porenet():
    code = (
        "import sys, porenet.testing.tutorial; "
        "print(' '.join(sorted(m for m in sys.modules if m.startswith('porenet'))))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    expected = ["porenet", "porenet._version", "porenet.testing", "porenet.testing.tutorial"]
    assert out.stdout.split() == expected
