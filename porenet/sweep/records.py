"""The sweep's records: the rows of ``summary.csv`` and the error records of failed runs.

Both are written with :func:`porenet.sweep.files.atomic_write_text` (docs/sweeps.md,
"The output directory").
"""

from __future__ import annotations

import contextlib
import csv
import io
import json
from pathlib import Path
from typing import Any

import numpy as np

from porenet.sweep.files import atomic_write_text, read_text
from porenet.sweep.layout import SUMMARY_CSV
from porenet.sweep.spec import RunSpec

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


class SummaryTable:
    """The rows of ``summary.csv`` (finished runs, in run order); :meth:`write` replaces the
    file atomically, so it always holds a whole table."""

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


__all__ = [
    "SUMMARY_FIELDS",
    "SummaryTable",
    "error_text",
    "plain",
    "read_error",
    "scene_difference",
]
