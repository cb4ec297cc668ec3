"""Checks that keep a plugin tutorial of docs/plugins.md true to the plugin's source.

A tutorial section cites the plugin's code in blocks preceded by ``<!-- excerpt: PATH -->``
(``PATH`` relative to the repository root); a line ``# (...)`` in a block marks an elision.
A plugin's ``tests/test_tutorial.py`` uses these helpers to check that

* every piece of every excerpt (the text between elisions) appears verbatim in its file
  (:func:`excerpts`, :func:`missing_pieces`);
* every plugin file the section names exists (:func:`named_paths`);
* the plugin imports nothing private from porenet: no module or name component starting with
  ``_``, and of porenet's own kinds only a kind's kernel package (``porenet.kinds.<kind>.
  kernels``, whose ``__init__`` names its stable entry points), never their models, configs
  or kernel modules (:func:`porenet_imports`, :func:`private_imports`);
* the plugin's README lists exactly what it imports from porenet (:func:`readme_imports`).

Pure Python (``ast`` and ``re``): importing it imports nothing else of porenet.
"""

from __future__ import annotations

import ast
import re
from pathlib import Path

#: A kind's kernel package, the only part of porenet's own kinds a plugin may import.
KIND_KERNELS = re.compile(r"porenet\.kinds\.\w+\.kernels")

#: A line of an excerpt that stands for lines left out.
ELISION = "# (...)"

#: An excerpt: the marker line, then a fenced code block.
EXCERPT = re.compile(r"<!-- excerpt: (?P<path>\S+) -->\n```[a-z]*\n(?P<code>.*?)\n```", re.S)


def section(document: str | Path, heading: str) -> str:
    """The text of ``document`` (a Markdown file) after the line ``heading`` (e.g.
    ``"## Adding a fluid model"``) up to the next heading of the same level.

    Raises
    ------
    AssertionError
        If the document has no such heading.
    """
    text = Path(document).read_text(encoding="utf-8")
    assert f"\n{heading}\n" in text, f"{document} lost its section {heading!r}"
    level = heading.split(" ", 1)[0]  # "##"
    body = text.split(f"\n{heading}\n", 1)[1]
    return body.split(f"\n{level} ", 1)[0]


def excerpts(text: str) -> list[tuple[str, str]]:
    """``(path, code)`` of each excerpt in ``text``, in order."""
    return [(m["path"], m["code"]) for m in EXCERPT.finditer(text)]


def missing_pieces(root: str | Path, path: str, code: str) -> list[str]:
    """The pieces of the excerpt ``code`` (split at :data:`ELISION` lines) that do not appear
    verbatim in ``root / path``; an empty piece counts as missing."""
    source = (Path(root) / path).read_text(encoding="utf-8")
    pieces = [p.strip("\n") for p in code.split(ELISION)]
    return [piece for piece in pieces if not piece or piece not in source]


def named_paths(text: str, prefix: str) -> list[str]:
    """The paths starting with ``prefix`` (e.g. ``"plugins/porenet-front/"``) that ``text``
    names, without a trailing dot or slash."""
    return re.findall(re.escape(prefix) + r"[\w./-]*\w", text)


def porenet_imports(package: str | Path) -> dict[str, set[str]]:
    """``{module: names}`` imported with ``from porenet.x import ...`` by the ``.py`` files
    of ``package`` (a directory, not recursive).

    Raises
    ------
    AssertionError
        On ``import porenet.x`` (the helpers check names, so imports must name them).
    """
    found: dict[str, set[str]] = {}
    for file in sorted(Path(package).glob("*.py")):
        for node in ast.walk(ast.parse(file.read_text(encoding="utf-8"))):
            if isinstance(node, ast.ImportFrom) and (node.module or "").startswith("porenet."):
                found.setdefault(node.module or "", set()).update(a.name for a in node.names)
            elif isinstance(node, ast.Import):
                for alias in node.names:
                    assert not alias.name.startswith("porenet."), (file, alias.name)
    return found


def private_imports(imports: dict[str, set[str]]) -> list[str]:
    """The imports of :func:`porenet_imports` that are not public: a module or name component
    starting with ``_``, or anything of porenet's own kinds (``porenet.kinds``) but a kind's
    kernel package ``porenet.kinds.<kind>.kernels``, whose stable entry points its
    ``__init__`` names."""
    bad = []
    for module, names in sorted(imports.items()):
        kind_module = module == "porenet.kinds" or module.startswith("porenet.kinds.")
        if kind_module and not KIND_KERNELS.fullmatch(module):
            bad.append(module)
        bad += [f"{module}: {part}" for part in [*module.split("."), *sorted(names)]
                if part.startswith("_")]  # fmt: skip
    return bad


def readme_imports(
    readme: str | Path, heading: str = "## What it imports from porenet"
) -> dict[str, set[str]]:
    """``{module: names}`` listed in the table under ``heading`` of a plugin's README: rows
    ``| `porenet.x` | `Name`, `other` | ... |``."""
    text = Path(readme).read_text(encoding="utf-8")
    assert heading in text, f"{readme} lost its section {heading!r}"
    table = text.split(heading, 1)[1].split("\n\n## ", 1)[0]
    listed: dict[str, set[str]] = {}
    for module, names in re.findall(r"^\| `(porenet[\w.]*)` \| (.+?) \|", table, re.M):
        listed[module] = set(re.findall(r"`(\w+)`", names))
    return listed
