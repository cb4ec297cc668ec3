"""Every reference to the documentation leads somewhere that exists in this repository.

Code comments, docstrings, docs, examples, tests and command output cite docs/ pages, the
numbered sections of the model's specification (docs/model.md, "The model as specified"), the
numbered rules of docs/architecture.md ("Rules of the house") and named sections of a page
(``docs/performance.md, "First run"``: a heading, or a bullet's bold title). This fails on a
reference to a page that is not in docs/, to a section number, rule or heading that the page
does not have, and on any file outside the repository (the specification used to be cited as
a file beside it).
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
DOCS = ROOT / "docs"
SCANNED = ["porenet", "plugins", "tests", "examples", "docs", "README.md"]
SUFFIXES = {".py", ".md", ".toml"}
OUTSIDE = re.compile(r"\.\./shared|" + "MODEL" + r"\.md")
PAGE = re.compile(r"\bdocs/([\w.-]+\.md)")
NUMBERED = re.compile(r"docs/model\.md,?\s+(?:section|§)\s*(\d+)")
NAMED = re.compile(r"docs/([\w-]+\.md),?\s+\(?\"([^\"]{3,80})\"")
RULE = re.compile(r"docs/architecture\.md,?\s+rules?\s+(\d+)")
BOLD = re.compile(r"^\s*(?:[*-]|\d+\.) \*\*([^*]+)\*\*")


def _files() -> list[Path]:
    found = []
    for name in SCANNED:
        path = ROOT / name
        if path.is_file():
            found.append(path)
            continue
        found += [
            p
            for p in path.rglob("*")
            if p.suffix in SUFFIXES and ".egg-info" not in str(p) and p.is_file()
        ]
    return sorted(found)


def _text(path: Path) -> str:
    return " ".join(path.read_text(encoding="utf-8").split())  # references wrap over lines


def _headings(page: str) -> list[str]:
    """The page's headings and the bold titles that open its bullets (named sections too)."""
    lines = (DOCS / page).read_text(encoding="utf-8").splitlines()
    found = [line.lstrip("#").strip() for line in lines if line.startswith("#")]
    return found + [m.group(1).strip() for line in lines if (m := BOLD.match(line))]


def _rules() -> set[str]:
    lines = (DOCS / "architecture.md").read_text(encoding="utf-8").splitlines()
    return {m.group(1) for line in lines if (m := re.match(r"^(\d+)\. \*\*", line))}


FILES = _files()


def test_the_scan_sees_the_sources():
    names = {p.name for p in FILES}
    assert {"model.md", "cost.py", "README.md"} <= names


@pytest.mark.parametrize("path", FILES, ids=lambda p: str(p.relative_to(ROOT)))
def test_references_lead_somewhere(path):
    text = _text(path)
    assert not OUTSIDE.search(text), f"{path}: cites a file outside the repository"
    for page in PAGE.findall(text):
        assert (DOCS / page).is_file(), f"{path}: docs/{page} does not exist"
    model = _headings("model.md")
    for number in NUMBERED.findall(text):
        assert any(h.startswith(f"{number}. ") for h in model), (
            f"{path}: docs/model.md has no section {number}"
        )
    for number in RULE.findall(text):
        assert number in _rules(), f"{path}: docs/architecture.md has no rule {number}"
    for page, section in NAMED.findall(text):
        if not (DOCS / page).is_file():
            continue  # reported above
        assert any(h.startswith(section) for h in _headings(page)), (
            f'{path}: docs/{page} has no section "{section}"'
        )
