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

:func:`plugin_checks` makes these checks for one plugin's section, each a named callable, and
:func:`tutorial_test` the test that runs them, so that a plugin's tutorial test is one line::

    test_tutorial = tutorial_test(__file__, "## Adding an observer",
                                  ["config.py", "observer.py", "plugin.py"], "front.toml")

Pure Python (``ast`` and ``re``): importing it imports nothing else of porenet.
"""

from __future__ import annotations

import ast
import re
from collections.abc import Callable
from dataclasses import dataclass
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


@dataclass(frozen=True)
class TutorialCheck:
    """One check of a tutorial section: call it (AssertionError when the text and the source
    part); ``str(check)`` is its test id."""

    name: str
    function: Callable[[], None]

    def __str__(self) -> str:
        return self.name

    def __call__(self) -> None:
        self.function()


def plugin_checks(
    plugin: str | Path,
    heading: str,
    modules: list[str] | tuple[str, ...],
    example: str,
    document: str | Path | None = None,
) -> list[TutorialCheck]:
    """The checks (module docstring) of the tutorial section ``heading`` of ``document``
    (default ``docs/plugins.md``) on the plugin in the folder ``plugin``
    (``plugins/<name>``, in the repository): the section has excerpts of each of ``modules``
    (file names in the plugin's package under ``src/``), of ``pyproject.toml`` and of
    ``examples/<example>``; each excerpt is verbatim; the files it names exist; the package
    imports nothing private from porenet, and its README lists exactly what it imports."""
    plugin = Path(plugin).resolve()
    root = plugin.parents[1]
    text = section(document or root / "docs" / "plugins.md", heading)
    found = excerpts(text)
    (source,) = [p for p in sorted((plugin / "src").iterdir()) if (p / "__init__.py").is_file()]
    prefix = f"plugins/{plugin.name}/"
    cited = [f"src/{source.name}/{m}" for m in modules] + ["pyproject.toml", f"examples/{example}"]

    def cites_every_file() -> None:
        paths = {path for path, _ in found}
        missing = [prefix + c for c in cited if prefix + c not in paths]
        assert not missing, f"{heading!r} has no excerpt of {', '.join(missing)}"

    def verbatim(path: str, code: str) -> Callable[[], None]:
        def check() -> None:
            assert missing_pieces(root, path, code) == [], f"not verbatim in {path}"

        return check

    def named_files_exist() -> None:
        missing = [p for p in named_paths(text, prefix) if not (root / p).exists()]
        assert not missing, f"{heading!r} names files that do not exist: {missing}"

    def imports_nothing_private() -> None:
        assert private_imports(porenet_imports(source)) == []

    def readme_lists_the_imports() -> None:
        assert readme_imports(plugin / "README.md") == porenet_imports(source)

    return [
        TutorialCheck("cites-every-file", cites_every_file),
        *(
            TutorialCheck(f"excerpt-{k}:{path}", verbatim(path, code))
            for k, (path, code) in enumerate(found)
        ),
        TutorialCheck("named-files-exist", named_files_exist),
        TutorialCheck("imports-nothing-private", imports_nothing_private),
        TutorialCheck("readme-lists-the-imports", readme_lists_the_imports),
    ]


def tutorial_test(
    test_file: str | Path,
    heading: str,
    modules: list[str] | tuple[str, ...],
    example: str,
    document: str | Path | None = None,
) -> Callable[[TutorialCheck], None]:
    """A pytest test, one case per check of :func:`plugin_checks`, for the plugin whose
    ``tests/`` folder holds ``test_file`` (give it ``__file__``); name it ``test_...``."""
    from porenet.testing.contract import parametrized

    plugin = Path(test_file).resolve().parents[1]
    return parametrized(plugin_checks(plugin, heading, modules, example, document))
