"""Re-make the tables (and the D_f figure) of docs/fracture-shear-n400.md from its records.

    python examples/scripts/fracture_shear_doc.py            # rewrite the page's tables
    python examples/scripts/fracture_shear_doc.py --figure   # ... and its figure of D_f
    python examples/scripts/fracture_shear_doc.py --check    # exit 1 naming each stale table

The n = 400 study's records are committed in docs/data/fracture-shear-n400/ (the page's
section "Where the records are"). Every table the page makes from them sits between a line
``<!-- table: NAME -->`` and the next ``<!-- end table -->``; NAME picks the report of
``fracture_shear.py`` that fills it (:data:`TABLES`: the flags, the same as the command the
page shows above the table), written without its first paragraph (the report's caption,
which the page words itself). A table the page marks but :data:`TABLES` does not know, or
one without its end line, is an error naming it; nothing is written then. ``--check``
writes nothing and names every table that differs from what the records give (the test
suite runs it, so that a record committed without its tables fails).
"""

from __future__ import annotations

import argparse
import contextlib
import io
import re
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

import fracture_shear

from porenet.io.atomic import atomic_output

ROOT = Path(__file__).resolve().parents[2]
PAGE = ROOT / "docs" / "fracture-shear-n400.md"
RECORDS = ROOT / "docs" / "data" / "fracture-shear-n400"
FIGURE = ROOT / "docs" / "figures" / "fracture-shear-n400.png"

#: The study's plan, as the page's commands give it (with sliding: three of the four ratios).
_ALL = ["--n", "400", "--ratio", "0.1", "0.3", "0.5", "0.8"]
_SLIDING = ["--n", "400", "--ratio", "0.1", "0.5", "0.8"]
_REPORT = [*_ALL, "--no-run", "--friction", "none", "0.3"]
#: Each marked table's report: ``fracture_shear.py``'s flags, the last one taking the file.
TABLES: dict[str, list[str]] = {
    "committed records": [*_REPORT, "--table"],
    "by N_f, committed records": [*_REPORT, "--by-nf"],
    "sliding cost": ["--n", "400", "--sliding-cost"],
    "status without sliding": [*_ALL, "--friction", "none", "--skip-settled", "--status"],
    "status with sliding": [*_SLIDING, "--friction", "0.3", "--skip-settled", "--status"],
}
MARK = re.compile(r"^<!-- table: (?P<name>.+?) -->$", re.MULTILINE)
END = "<!-- end table -->"


class PageError(Exception):
    """The page's marks do not name a known table or do not close."""


def records(folder: Path = RECORDS) -> list[Path]:
    """The study's records files, in a fixed order (the report does not depend on it)."""
    return sorted(folder.glob("*.jsonl"))


def report(name: str, files: list[Path]) -> str:
    """The table NAME as ``fracture_shear.py`` writes it from ``files``, without its first
    paragraph."""
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "table.md"
        argv = [*TABLES[name], str(out), "--records", *map(str, files)]
        with contextlib.redirect_stdout(io.StringIO()):
            fracture_shear.main(argv)
        text = out.read_text()
    return text.split("\n\n", 1)[-1].strip()  # a report without a caption: all of it


def fill(page: str, files: list[Path]) -> tuple[str, list[str]]:
    """``page`` with every marked table made again from ``files``, and the names of the
    tables that changed."""
    pieces, changed, at = [], [], 0
    for mark in MARK.finditer(page):
        name = mark.group("name")
        if name not in TABLES:
            raise PageError(f"table {name!r} is not one of {sorted(TABLES)}")
        end = page.find(END, mark.end())
        if end < 0 or MARK.search(page, mark.end(), end):
            raise PageError(f"table {name!r} has no {END!r} line before the next table")
        new = "\n" + report(name, files) + "\n"
        if page[mark.end() : end] != new:
            changed.append(name)
        pieces += [page[at : mark.end()], new]
        at = end
    return "".join(pieces) + page[at:], changed


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--page", type=Path, default=PAGE, help="the page (markdown)")
    parser.add_argument("--records", type=Path, default=RECORDS,
                        help="the folder of the study's records (*.jsonl)")  # fmt: skip
    parser.add_argument(
        "--check", action="store_true", help="write nothing; exit 1 naming each stale table"
    )
    parser.add_argument(
        "--figure",
        type=Path,
        nargs="?",
        const=FIGURE,
        help=f"also draw D_f against N_f ({FIGURE.relative_to(ROOT)})",
    )
    args = parser.parse_args(argv)
    files = records(args.records)
    if not files:
        parser.error(f"--records: no *.jsonl in {args.records}")
    try:
        page = args.page.read_text()
    except OSError as exc:
        parser.error(f"--page: cannot read {args.page} ({exc.strerror})")
    except UnicodeDecodeError as exc:
        parser.error(f"--page: {args.page} is not UTF-8 text (byte {exc.start})")
    try:
        new, changed = fill(page, files)
    except PageError as exc:
        parser.error(f"{args.page}: {exc}")
    if args.check:
        for name in changed:
            print(f"{args.page}: table {name!r} differs from what the records give; "
                  f"make it again with python {Path(__file__).relative_to(ROOT)}")  # fmt: skip
        if not changed:
            print(f"{args.page}: every table is what the records give")
        return 1 if changed else 0
    if changed:
        with atomic_output(args.page, what="page") as tmp:
            tmp.write_text(new)
    print(f"{args.page}: {len(changed)} of {len(MARK.findall(page))} tables made again"
          + (f" ({', '.join(changed)})" if changed else ""))  # fmt: skip
    if args.figure:
        with contextlib.redirect_stdout(io.StringIO()):
            fracture_shear.main([*_REPORT, "--out", str(args.figure), "--records",
                                 *map(str, files)])  # fmt: skip
        print(f"figure: {args.figure}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
