"""porenet's modules import each other without a cycle, counting the imports inside functions
(docs/architecture.md, "No import cycle"): a cycle hides an order in which the modules must
load, and makes one part impossible to use without the others."""

from __future__ import annotations

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2] / "porenet"


def module_name(path: Path) -> str:
    parts = path.relative_to(ROOT.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def modules() -> dict[str, Path]:
    return {module_name(p): p for p in ROOT.rglob("*.py")}


def imports_of(path: Path, known: dict[str, Path], here: str | None = None) -> set[str]:
    """The porenet modules a file imports anywhere in it (top level, functions, methods);
    ``from a import b`` counts as importing ``a.b`` when that is a module, else ``a``; and
    importing ``a.b.c`` imports the packages ``a.b`` (their ``__init__`` runs) but porenet's
    own, which imports nothing eagerly. Imports only for type checking (under ``if
    TYPE_CHECKING:``) do not count. ``here``: the file's module name (default: from its
    path)."""
    tree = ast.parse(path.read_text())
    skip: set[int] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.If) and "TYPE_CHECKING" in ast.unparse(node.test):
            for inner in ast.walk(node):
                skip.add(id(inner))
    here = module_name(path) if here is None else here
    package = here if path.name == "__init__.py" else here.rpartition(".")[0]
    found: set[str] = set()
    for node in ast.walk(tree):
        if id(node) in skip:
            continue
        if isinstance(node, ast.Import):
            for alias in node.names:
                if alias.name.startswith("porenet"):
                    found.add(alias.name)
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                base = ".".join(package.split(".")[: len(package.split(".")) - node.level + 1])
                base = f"{base}.{node.module}" if node.module else base
            if not base.startswith("porenet"):
                continue
            for alias in node.names:
                full = f"{base}.{alias.name}"
                found.add(full if full in known else base)
    with_packages = set(found)
    for name in found:
        parts = name.split(".")
        with_packages.update(".".join(parts[:k]) for k in range(2, len(parts)))
    own = {here, *(".".join(here.split(".")[:k]) for k in range(1, len(here.split("."))))}
    return {m for m in with_packages if m in known and m not in own}


def cycles() -> list[list[str]]:
    """Strongly connected components of more than one module (Tarjan)."""
    known = modules()
    graph = {name: sorted(imports_of(path, known)) for name, path in known.items()}
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    out: list[list[str]] = []
    counter = [0]

    def visit(v: str) -> None:
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on_stack.add(v)
        for w in graph[v]:
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                out.append(sorted(component))

    for v in graph:
        if v not in index:
            visit(v)
    return out


def test_no_import_cycle() -> None:
    found = cycles()
    assert not found, "import cycles: " + "; ".join(" <-> ".join(c) for c in found)


def test_the_walker_sees_imports_inside_functions(tmp_path: Path) -> None:
    """A function-level import counts (the cycle the test exists for hid there)."""
    source = tmp_path / "m.py"
    source.write_text("def f():\n    from porenet.core import plan\n    return plan\n")
    found = imports_of(source, modules(), here="porenet.m")
    assert {"porenet.core.plan", "porenet.core"} <= found
