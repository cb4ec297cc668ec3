"""The core names no kind (docs/architecture.md, rule 13).

1. No module outside the kinds' folders (``porenet/kinds/<kind>/``) imports one of them, with
   an import statement or by a dotted name in a string (a lazy ``"module:Class"``); the one
   exception is the list of default plugin modules, :data:`porenet.hooks.DEFAULT_PLUGINS`, as
   pytest's ``default_plugins`` is.
2. The orchestration (everything outside the kinds' folders) holds no registered kind's name as
   a string literal: what differs between kinds is asked of the kind (porenet/core/kinds.py).
   Docstrings are prose and are not counted; the few literals that are not kinds though they
   spell one are listed in :data:`NOT_KINDS` with the reason.
"""

from __future__ import annotations

import ast
import re
from pathlib import Path

import porenet
from porenet.hooks import DEFAULT_PLUGINS, build_registry

PACKAGE = Path(porenet.__file__).resolve().parent
KINDS = PACKAGE / "kinds"

#: (module relative to porenet/, literal): strings that spell a kind's name but are not one.
NOT_KINDS = {
    ("io/runfile.py", "snapshots"): "the run file's group /snapshots (docs/run-file.md)",
    ("io/xdmf.py", "snapshots"): "the run file's group /snapshots, read for the export",
    ("simulation.py", "snapshots"): "the run data's field that observers fill (RUN_DATA_FIELDS)",
    ("config/lattice_fields.py", "none"): "English, in a message: a file with no arrays",
    ("core/registry.py", "none"): "English, in a message: a family with no kind registered",
    ("viz/fractal.py", "none"): "matplotlib's marker face colour 'none'",
    ("viz/style.py", "none"): "matplotlib's svg.fonttype 'none'",
}


def _core_modules() -> list[Path]:
    return sorted(p for p in PACKAGE.rglob("*.py") if KINDS not in p.parents)


def _docstrings(tree: ast.AST) -> set[int]:
    """ids of the string constants that are docstrings (or bare string statements)."""
    out = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Expr) and isinstance(node.value, ast.Constant):
            out.add(id(node.value))
    return out


#: A module of one of porenet's kinds, as an import or a lazy "module:Class" names it.
KIND_MODULE = re.compile(r"porenet\.kinds\.\w+")


def _names_a_kind_module(text: str) -> bool:
    return KIND_MODULE.match(text) is not None


def test_no_module_outside_the_kinds_imports_one():
    offenders = []
    for path in _core_modules():
        tree = ast.parse(path.read_text(encoding="utf-8"))
        docstrings = _docstrings(tree)
        for node in ast.walk(tree):
            if isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
                names = [node.module] + [f"{node.module}.{a.name}" for a in node.names]
                if any(_names_a_kind_module(n) for n in names):
                    offenders.append(f"{path.relative_to(PACKAGE)}:{node.lineno} {node.module}")
            elif isinstance(node, ast.Import):
                for alias in node.names:
                    if _names_a_kind_module(alias.name):
                        offenders.append(f"{path.relative_to(PACKAGE)}:{node.lineno} {alias.name}")
            elif (
                isinstance(node, ast.Constant)
                and isinstance(node.value, str)
                and id(node) not in docstrings
                and _names_a_kind_module(node.value)
                and node.value not in DEFAULT_PLUGINS.values()
            ):
                offenders.append(f"{path.relative_to(PACKAGE)}:{node.lineno} {node.value!r}")
    assert offenders == []


def test_the_default_plugins_are_the_kinds_folders():
    """Every folder of porenet/kinds/ is a kind registered by its own plugin module, and the
    default plugin list names exactly those modules."""
    folders = {p.parent.name for p in KINDS.glob("*/plugin.py")}
    listed = {module.split(".")[2] for module in DEFAULT_PLUGINS.values()}
    assert listed == folders
    assert all(m == f"porenet.kinds.{m.split('.')[2]}.plugin" for m in DEFAULT_PLUGINS.values())


def test_the_orchestration_holds_no_kind_name():
    registry = build_registry(strict=True)
    kinds = {entry.kind for entry in registry}
    offenders = []
    for path in _core_modules():
        relative = path.relative_to(PACKAGE).as_posix()
        tree = ast.parse(path.read_text(encoding="utf-8"))
        docstrings = _docstrings(tree)
        for node in ast.walk(tree):
            if (
                isinstance(node, ast.Constant)
                and isinstance(node.value, str)
                and id(node) not in docstrings
                and node.value in kinds
                and (relative, node.value) not in NOT_KINDS
            ):
                offenders.append(f"{relative}:{node.lineno} {node.value!r}")
    assert offenders == []


def test_the_kinds_not_kinds_list_is_still_needed():
    """Each exception of :data:`NOT_KINDS` still stands in its module (a stale one hides
    nothing, but says something untrue)."""
    for (relative, literal), _reason in NOT_KINDS.items():
        tree = ast.parse((PACKAGE / relative).read_text(encoding="utf-8"))
        values = {n.value for n in ast.walk(tree) if isinstance(n, ast.Constant)}
        assert literal in values, (relative, literal)
