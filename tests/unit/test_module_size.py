"""Modules stay under ~500 lines unless their docstring says why (docs/architecture.md,
"Small modules, typed code"): a module of porenet/ or plugins/ over 500 lines must have a
paragraph starting "Length" in its module docstring."""

from __future__ import annotations

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
LIMIT = 500


def test_long_modules_say_why():
    unexplained = []
    for path in sorted([*ROOT.glob("porenet/**/*.py"), *ROOT.glob("plugins/*/src/**/*.py")]):
        text = path.read_text(encoding="utf-8")
        n_lines = text.count("\n") + 1
        if n_lines <= LIMIT:
            continue
        doc = ast.get_docstring(ast.parse(text)) or ""
        if not any(p.startswith("Length") for p in doc.split("\n\n")):
            unexplained.append(f"{path.relative_to(ROOT)} ({n_lines} lines)")
    assert not unexplained, "over 500 lines with no 'Length' paragraph: " + ", ".join(unexplained)
