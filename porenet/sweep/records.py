"""The sweep's records: ``summary.csv`` (its writer and its reader) and the error records of
failed runs.

:class:`SummaryWriter` (the runner's) and the error records are written with
:func:`porenet.sweep.files.atomic_write_text`; :func:`read_summary` reads the table back as a
:class:`SweepSummary` (what the phase diagram, :mod:`porenet.analysis.phase`, aggregates).
The columns and the directory's layout are docs/sweeps.md, "The output directory"; the file
names are :mod:`porenet.sweep.layout`'s.
"""

from __future__ import annotations

import contextlib
import csv
import io
import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from porenet.core.errors import ConfigError
from porenet.sweep.files import atomic_write_text, read_text
from porenet.sweep.layout import SUMMARY_CSV, SWEEP_JSON
from porenet.sweep.spec import DERIVED, RunSpec

#: Values taken from each run's summary into ``summary.csv``.
SUMMARY_FIELDS = (
    "fractal_dimension",
    "fractal_dimension_error",
    "regime",
    "regime_confidence",
    "capillary_number_measured",
    "wall_time_s",
)


def plain(value: Any) -> Any:
    """``value`` as a plain Python value (a numpy scalar becomes its Python twin)."""
    return value.item() if isinstance(value, np.generic) else value


def _cell(value: Any) -> str:
    value = plain(value)
    if value is None:
        return ""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return repr(value)
    if isinstance(value, list | dict):
        return json.dumps(value)
    return str(value)


def _flatten(data: Any, prefix: str = "") -> dict[str, Any]:
    if not isinstance(data, dict):
        return {prefix: data}
    out: dict[str, Any] = {}
    for key, value in data.items():
        out.update(_flatten(value, f"{prefix}.{key}" if prefix else str(key)))
    return out


def scene_difference(recorded: dict[str, Any], intended: dict[str, Any], limit: int = 3) -> str:
    """The first few dotted keys on which two scenes differ, ``key: old -> new``."""
    a, b = _flatten(recorded), _flatten(intended)
    keys = [k for k in dict.fromkeys([*a, *b]) if a.get(k, "<unset>") != b.get(k, "<unset>")]
    shown = [f"{k}: {a.get(k, '<unset>')!r} -> {b.get(k, '<unset>')!r}" for k in keys[:limit]]
    more = f" (and {len(keys) - limit} more)" if len(keys) > limit else ""
    return "; ".join(shown) + more


def error_text(run: RunSpec, outcome: dict[str, Any]) -> str:
    """The error record of a failed run: its message, traceback, wall time and scene."""
    return (
        f"{outcome['error']}\n\n{outcome.get('traceback') or ''}\n"
        f"run_id: {run.run_id}\n"
        f"wall_time_s: {outcome.get('wall_time_s', float('nan'))!r}\n"
        f"scene: {json.dumps(run.scene, sort_keys=True)}\n"
    )


def read_error(path: Path) -> tuple[str, float | None, dict[str, Any] | None]:
    """Message, wall time and scene of a failed run's error record."""
    lines = read_text(path).splitlines()
    message = lines[0] if lines else "failed"
    wall: float | None = None
    scene: dict[str, Any] | None = None
    for line in reversed(lines[-3:]):
        if line.startswith("scene: "):
            with contextlib.suppress(ValueError):
                scene = json.loads(line[len("scene: ") :])
        elif line.startswith("wall_time_s: "):
            with contextlib.suppress(ValueError):
                wall = float(line[len("wall_time_s: ") :])
    return message, wall, scene


#: Columns of ``summary.csv`` read back as text (never parsed as numbers).
TEXT_COLUMNS: tuple[str, ...] = ("run_id", "status", "regime", "run_file", "error")


class SummaryWriter:
    """Writes ``DIR/summary.csv``: the rows of the finished runs, in run order; :meth:`write`
    replaces the file atomically, so it always holds a whole table."""

    def __init__(self, out_dir: Path, runs: list[RunSpec], swept: list[str]) -> None:
        self.path = out_dir / SUMMARY_CSV
        self.order = {run.run_id: i for i, run in enumerate(runs)}
        self.header = ["run_id", *swept, "seed", "status", *SUMMARY_FIELDS, "run_file", "error"]
        self.rows: dict[str, dict[str, str]] = {}

    def record(self, run: RunSpec, status: str, values: dict[str, Any], error: str = "") -> None:
        row = {"run_id": run.run_id}
        row.update({k: _cell(v) for k, v in run.params.items()})
        row.update(seed=str(run.seed), status=status)
        row.update({k: _cell(values.get(k)) for k in SUMMARY_FIELDS})
        row.update(run_file=run.run_file if status == "done" else "", error=error)
        self.rows[run.run_id] = row

    def counts(self) -> tuple[int, int]:
        done = sum(r["status"] == "done" for r in self.rows.values())
        return done, len(self.rows) - done

    def sorted_rows(self) -> list[dict[str, str]]:
        return [self.rows[k] for k in sorted(self.rows, key=self.order.__getitem__)]

    def write(self) -> None:
        buf = io.StringIO()
        writer = csv.DictWriter(buf, fieldnames=self.header, lineterminator="\n")
        writer.writeheader()
        writer.writerows(self.sorted_rows())
        atomic_write_text(self.path, buf.getvalue())


@dataclass
class SweepSummary:
    """A sweep's summary as read back: its rows (values parsed: numbers as float, empty cells
    as None, :data:`TEXT_COLUMNS` and other text as str), its columns in file order, and the
    directory its ``run_file`` entries are relative to."""

    rows: list[dict[str, Any]]
    columns: list[str]
    root: Path = field(default_factory=Path.cwd)
    source: Path | None = None
    #: Each run's scene by run_id, from ``DIR/sweep.json`` when the sweep wrote one.
    scenes: dict[str, dict[str, Any]] = field(default_factory=dict)

    @classmethod
    def from_rows(cls, rows: list[dict[str, Any]]) -> SweepSummary:
        """A summary of rows given as dicts (values taken as they are; columns in order of
        first appearance; ``run_file`` entries relative to the current directory)."""
        rows = [dict(r) for r in rows]
        columns: list[str] = []
        for r in rows:
            columns += [k for k in r if k not in columns]
        return cls(rows=rows, columns=columns)

    @property
    def parameter_columns(self) -> list[str]:
        """The columns that identify a point: dotted scene keys and derived keys
        (:data:`porenet.sweep.spec.DERIVED`)."""
        return [c for c in self.columns if "." in c or c in DERIVED]

    def to_dataframe(self) -> Any:
        """The rows as a pandas DataFrame, one row a run and the columns in the file's order
        (numbers as float, empty cells as NaN or None); ``df.attrs["parameters"]`` lists the
        columns that identify a point, ``df.attrs["root"]`` the directory the ``run_file``
        entries are relative to.

        Raises
        ------
        ImportError
            Without pandas, saying how to install it (``pip install "porenet[pandas]"``).
        """
        try:
            import pandas as pd
        except ImportError as exc:
            raise ImportError(
                'a sweep as a DataFrame needs pandas: pip install "porenet[pandas]" (or read '
                "it without pandas: porenet.sweep.records.read_summary(DIR).rows)"
            ) from exc
        frame = pd.DataFrame(self.rows, columns=self.columns)
        frame.attrs["parameters"] = self.parameter_columns
        frame.attrs["root"] = str(self.root)
        return frame

    @property
    def name(self) -> str:
        """A short name for titles: the sweep directory's name ("" for rows given as dicts)."""
        return self.root.name if self.source is not None else ""


#: What the readers of a summary accept: a summary, a sweep directory or its ``summary.csv``,
#: or rows as dicts.
SummaryLike = SweepSummary | str | Path | list[dict[str, Any]]


def _parse(value: str | None, column: str) -> Any:
    if value is None:
        return None
    text = value.strip()
    if text == "":
        return None
    if column in TEXT_COLUMNS:
        return text
    try:
        return float(text)
    except ValueError:
        return text


def read_summary(path: str | Path) -> SweepSummary:
    """Read ``DIR/summary.csv`` (give the directory or the CSV file itself), and every run's
    scene from ``DIR/sweep.json`` when it is there and readable.

    Raises
    ------
    ConfigError
        If there is no summary (saying to run ``porenet sweep`` first) or it is not a sweep
        summary (no ``status`` column); the message names the file or directory.
    """
    path = Path(path)
    csv_path = path if path.suffix.lower() == ".csv" else path / SUMMARY_CSV
    if not csv_path.is_file():
        where = csv_path.parent
        if not where.exists():
            raise ConfigError(
                f"{where}: no such directory; run `porenet sweep SWEEP.toml -o {where}` first"
            )
        raise ConfigError(
            f"{where}: no {SUMMARY_CSV}; run `porenet sweep SWEEP.toml -o {where}` first"
        )
    with csv_path.open(newline="", encoding="utf-8") as f:
        reader = csv.DictReader(f)
        columns = list(reader.fieldnames or [])
        rows = [{k: _parse(v, k) for k, v in row.items() if k is not None} for row in reader]
    if "status" not in columns:
        raise ConfigError(f"{csv_path}: column 'status' missing; not a `porenet sweep` summary")
    scenes: dict[str, dict[str, Any]] = {}
    resolved = csv_path.parent / SWEEP_JSON
    if resolved.is_file():
        with contextlib.suppress(OSError, ValueError, TypeError, AttributeError):
            runs = json.loads(resolved.read_text(encoding="utf-8")).get("runs", [])
            scenes = {
                str(r["run_id"]): r["scene"] for r in runs if isinstance(r.get("scene"), dict)
            }
    return SweepSummary(
        rows=rows, columns=columns, root=csv_path.parent, source=csv_path, scenes=scenes
    )


def read_sweep(path: str | Path) -> Any:
    """A sweep's ``summary.csv`` as a pandas DataFrame (:meth:`SweepSummary.to_dataframe`):
    ``porenet.read_sweep("fig2-small")`` after ``porenet sweep ... -o fig2-small``.

    Raises
    ------
    ConfigError
        No summary there, or not a sweep's (:func:`read_summary`).
    ImportError
        Without pandas (an optional extra: ``pip install "porenet[pandas]"``).
    """
    return read_summary(path).to_dataframe()


def as_summary(table: SummaryLike) -> SweepSummary:
    """``table`` as a :class:`SweepSummary`: itself, read with :func:`read_summary` (a path),
    or :meth:`SweepSummary.from_rows` (a list of dicts)."""
    if isinstance(table, SweepSummary):
        return table
    if isinstance(table, str | Path):
        return read_summary(table)
    return SweepSummary.from_rows(table)


__all__ = [
    "SUMMARY_FIELDS",
    "TEXT_COLUMNS",
    "SummaryLike",
    "SummaryWriter",
    "SweepSummary",
    "as_summary",
    "error_text",
    "plain",
    "read_error",
    "read_summary",
    "read_sweep",
    "scene_difference",
]
