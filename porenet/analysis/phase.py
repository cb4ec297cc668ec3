"""A sweep's runs aggregated into the points of a phase diagram (docs/model.md section 6).

The input is a sweep's summary (:func:`porenet.sweep.records.read_summary`: one row per run,
the swept keys under their dotted names, ``seed``, ``status``, ``fractal_dimension``,
``regime``, ``run_file``, ...). Nothing here draws: :mod:`porenet.viz.phase` draws these
points, and importing this module loads no matplotlib.

Axis kinds (:data:`AXES_KINDS`): ``"ca-lambda"`` (rigid media, the paper's Fig. 2: x =
disorder λ, y = Ca), ``"nf-castar"`` (deformable media, Fig. 3: x = ``Ca* = Ca (L/a) /
[λ/(1-λ²)]``, y = fracturing number N_f), and ``"auto"``, which stands for ``nf-castar`` when
the table has a fracturing-number column (``solid.fracturing_number``) or its runs are
deformable, ``ca-lambda`` otherwise (:func:`choose_axes`). All quantities are dimensionless.

Coordinates come from the table's columns when the key was swept (``lattice.disorder``,
``fluid.capillary_number``, ``lattice.n``, ``ca_star``, ``solid.fracturing_number``), else
from the point's scene in ``DIR/sweep.json`` (written by ``porenet sweep``), else from a run
file of the point (``RunData.scene``; N_f from its summary for scenes that give E* only).
``Ca*`` is computed from the point's ``n``, ``λ`` and ``Ca`` when it is not a column.

Decision: **replicates are aggregated**. The rows of one point (same swept values, different
seeds) give one :class:`PhasePoint`: the majority label (ties go to the label with the larger
summed ``regime_confidence``, then to the first of :data:`LABELS`), the mean and standard
deviation of D_f over the finished replicates, the votes of each label, and the counts of
finished and failed runs. This keeps one marker per point, as in the paper's figures, where
jitter would blur the grid.
"""

from __future__ import annotations

import math
from collections import Counter
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from porenet.analysis.numbers import modified_capillary_number
from porenet.analysis.regimes import REGIMES
from porenet.config.loading import get_dotted
from porenet.core.errors import ConfigError
from porenet.core.plan import scene_is_deformable
from porenet.sweep.records import SummaryLike, SweepSummary, as_summary

#: Axis kinds of :func:`phase_points` (and of ``porenet phase-diagram --axes``).
AXES_KINDS: tuple[str, ...] = ("auto", "ca-lambda", "nf-castar")

#: The label of a finished run that has none (not classified).
UNCLASSIFIED = "unclassified"

#: Every label a run can carry, in the order ties and legends use.
LABELS: tuple[str, ...] = (*REGIMES, UNCLASSIFIED)

_LAMBDA, _CA, _N = "lattice.disorder", "fluid.capillary_number", "lattice.n"
_NF_COLUMNS = ("solid.fracturing_number", "fracturing_number")


def finite_number(value: Any) -> float | None:
    """``value`` as a finite float, or None (empty cell, text, boolean, NaN or infinity)."""
    if value is None or isinstance(value, bool):
        return None
    try:
        x = float(value)
    except (TypeError, ValueError):
        return None
    return x if math.isfinite(x) else None


def run_label(row: dict[str, Any]) -> str:
    """A summary row's regime label, :data:`UNCLASSIFIED` when it has none."""
    label = row.get("regime")
    return label if isinstance(label, str) else UNCLASSIFIED


def measured_runs(table: SweepSummary) -> list[tuple[dict[str, Any], float]]:
    """The finished runs that have a fractal dimension: each row with its D_f (-)."""
    return [
        (row, d_f)
        for row in table.rows
        if row.get("status") == "done"
        and (d_f := finite_number(row.get("fractal_dimension"))) is not None
    ]


@dataclass
class PhasePoint:
    """One point of a sweep (its replicates aggregated) on a phase diagram; every quantity is
    dimensionless."""

    params: dict[str, Any]
    x: float | None
    y: float | None
    regime: str | None  # majority label of the finished runs; None if none finished
    agreement: float  # fraction of the finished runs with that label (0 if none)
    labels: dict[str, int]
    dimension: float  # mean D_f of the finished runs (nan if none has one)
    dimension_sd: float  # their standard deviation (nan for fewer than two)
    n_runs: int
    n_done: int
    n_failed: int
    disorder: float | None = None
    capillary_number: float | None = None
    ca_star: float | None = None
    fracturing_number: float | None = None
    n: int | None = None

    @property
    def placed(self) -> bool:
        """Whether the point has finite, plottable coordinates."""
        return self.x is not None and self.y is not None


class _RunCache:
    """Scenes and summaries of run files, read at most once each."""

    def __init__(self, root: Path) -> None:
        self.root = root
        self._cache: dict[Path, tuple[dict[str, Any], dict[str, Any]] | None] = {}

    def get(self, run_file: Any) -> tuple[dict[str, Any], dict[str, Any]] | None:
        if not run_file or not isinstance(run_file, str):
            return None
        path = Path(run_file)
        path = path if path.is_absolute() else self.root / path
        if path not in self._cache:
            from porenet.core.errors import PorenetError
            from porenet.io.runfile import read_run

            try:
                data = read_run(path)
                self._cache[path] = (data.scene, data.summary)
            except PorenetError:
                self._cache[path] = None
        return self._cache[path]


def _fracturing_number(scene: dict[str, Any], summary: dict[str, Any]) -> float | None:
    if not scene_is_deformable(scene, summary):
        return None
    nf = finite_number(summary.get("fracturing_number"))
    return nf if nf is not None else finite_number(get_dotted(scene, "solid.fracturing_number"))


def _group(table: SweepSummary) -> list[list[dict[str, Any]]]:
    keys = table.parameter_columns
    groups: dict[tuple[Any, ...], list[dict[str, Any]]] = {}
    for row in table.rows:
        groups.setdefault(tuple(row.get(k) for k in keys), []).append(row)
    return list(groups.values())


def _deformable(table: SweepSummary, runs: _RunCache) -> bool:
    if any(c in table.columns for c in _NF_COLUMNS):
        return True
    for scene in table.scenes.values():
        return scene_is_deformable(scene)
    for row in table.rows:
        info = runs.get(row.get("run_file"))
        if info is not None:
            return scene_is_deformable(info[0], info[1])
    return False


def choose_axes(table: SummaryLike) -> str:
    """The axis kind ``"auto"`` stands for: ``"nf-castar"`` when the table has an N_f
    column or its runs are deformable, ``"ca-lambda"`` otherwise."""
    table = as_summary(table)
    return "nf-castar" if _deformable(table, _RunCache(table.root)) else "ca-lambda"


def _majority(done: list[dict[str, Any]]) -> tuple[str | None, float, dict[str, int]]:
    labels = [run_label(r) for r in done]
    counts = Counter(labels)
    if not counts:
        return None, 0.0, {}
    weight: dict[str, float] = {}
    for r, label in zip(done, labels, strict=True):
        confidence = finite_number(r.get("regime_confidence")) or 0.0
        weight[label] = weight.get(label, 0.0) + confidence
    order = {name: i for i, name in enumerate(LABELS)}
    best = max(counts, key=lambda k: (counts[k], weight[k], -order.get(k, len(order))))
    return best, counts[best] / len(done), dict(counts)


def _mean_sd(values: list[float]) -> tuple[float, float]:
    """Mean and sample standard deviation; nan for no values, sd nan for fewer than two."""
    dims = np.array(values)
    mean = float(dims.mean()) if dims.size else math.nan
    return mean, float(dims.std(ddof=1)) if dims.size > 1 else math.nan


def phase_points(table: SummaryLike, axes: str = "auto") -> tuple[str, list[PhasePoint]]:
    """Aggregate a summary into the points of a phase diagram.

    Parameters
    ----------
    table : SweepSummary, path or list of dict
        What :func:`~porenet.sweep.records.read_summary` returns, a sweep directory or
        ``summary.csv`` path, or rows as dicts (``run_file`` entries then relative to the
        current directory).
    axes : {"auto", "ca-lambda", "nf-castar"}

    Returns
    -------
    tuple of str and list of PhasePoint
        The axis kind used (``axes``, or what ``"auto"`` picked) and one :class:`PhasePoint`
        per distinct combination of swept values, in the table's order. Rows whose status is
        neither ``done`` nor ``failed`` (pending) count in ``n_runs`` only.

    Raises
    ------
    ConfigError
        For an unknown ``axes``.
    """
    if axes not in AXES_KINDS:
        raise ConfigError(f"axes {axes!r}: unknown; use one of {', '.join(AXES_KINDS)}")
    table = as_summary(table)
    runs = _RunCache(table.root)
    if axes == "auto":
        axes = "nf-castar" if _deformable(table, runs) else "ca-lambda"
    points = []
    for rows in _group(table):
        first = rows[0]
        # the point's scene (sweep.json, else one readable run file) for what the columns lack
        listed = next(
            (table.scenes[k] for r in rows if (k := str(r.get("run_id"))) in table.scenes), None
        )
        missing = any(c not in table.columns for c in (_LAMBDA, _CA, _N))
        nf_column = any(c in table.columns for c in _NF_COLUMNS)
        need_nf = axes == "nf-castar" and not nf_column
        listed_nf = _fracturing_number(listed, {}) if listed is not None else None
        info = None
        if (missing and listed is None) or (need_nf and listed_nf is None):
            info = next((i for r in rows if (i := runs.get(r.get("run_file"))) is not None), None)
        scene = listed if listed is not None else (info[0] if info else {})

        def value(column: str, first: dict[str, Any] = first, scene: dict = scene) -> float | None:
            v = finite_number(first.get(column))
            if v is None and column not in table.columns:
                v = finite_number(get_dotted(scene, column))
            return v

        lam, ca, n_val = value(_LAMBDA), value(_CA), value(_N)
        ca_star = finite_number(first.get("ca_star"))
        if ca_star is None and None not in (lam, ca, n_val) and 0 < lam < 1:  # type: ignore[operator]
            ca_star = modified_capillary_number(ca, int(n_val), lam)  # type: ignore[arg-type]
        nf = next((finite_number(first.get(c)) for c in _NF_COLUMNS if c in table.columns), None)
        if nf is None:
            nf = _fracturing_number(*info) if info is not None else listed_nf
        if axes == "ca-lambda":
            x, y = lam, ca if ca is not None and ca > 0 else None
        else:
            x = ca_star if ca_star is not None and ca_star > 0 else None
            y = nf if nf is not None and nf > 0 else None
        done = [r for r in rows if r.get("status") == "done"]
        regime, agreement, labels = _majority(done)
        dims = [d for r in done if (d := finite_number(r.get("fractal_dimension"))) is not None]
        dimension, dimension_sd = _mean_sd(dims)
        points.append(
            PhasePoint(
                params={k: first.get(k) for k in table.parameter_columns},
                x=x,
                y=y,
                regime=regime,
                agreement=agreement,
                labels=labels,
                dimension=dimension,
                dimension_sd=dimension_sd,
                n_runs=len(rows),
                n_done=len(done),
                n_failed=sum(r.get("status") == "failed" for r in rows),
                disorder=lam,
                capillary_number=ca,
                ca_star=ca_star,
                fracturing_number=nf,
                n=int(n_val) if n_val is not None else None,
            )
        )
    return axes, points


def points_table(points: list[PhasePoint]) -> str:
    """A markdown table of aggregated points (what the phase diagram shows, as numbers)."""
    header = (
        "| λ | Ca | Ca* | N_f | runs (done/failed) | regime (votes) | D_f mean ± sd |\n"
        "|---|---|---|---|---|---|---|"
    )

    def fmt(v: float | None, spec: str = ".3g") -> str:
        return "" if v is None or (isinstance(v, float) and math.isnan(v)) else format(v, spec)

    lines = [header]
    for p in points:
        votes = ", ".join(f"{k} {v}" for k, v in sorted(p.labels.items(), key=lambda kv: -kv[1]))
        d_f = fmt(p.dimension, ".3f")
        if d_f and not math.isnan(p.dimension_sd):
            d_f += f" ± {p.dimension_sd:.3f}"
        lines.append(
            f"| {fmt(p.disorder)} | {fmt(p.capillary_number)} | {fmt(p.ca_star)} | "
            f"{fmt(p.fracturing_number)} | {p.n_done}/{p.n_failed} | {p.regime or ''}"
            f"{f' ({votes})' if votes else ''} | {d_f} |"
        )
    return "\n".join(lines) + "\n"


def regime_dimensions(table: SummaryLike) -> dict[str, tuple[float, float, int]]:
    """Per regime label: mean D_f (-), standard deviation and count over the finished runs with
    that label (each run counts with its own label, replicates not aggregated), in the order
    of :data:`LABELS`."""
    by_label: dict[str, list[float]] = {}
    for row, d_f in measured_runs(as_summary(table)):
        by_label.setdefault(run_label(row), []).append(d_f)
    return {
        label: (*_mean_sd(by_label[label]), len(by_label[label]))
        for label in LABELS
        if label in by_label
    }


@dataclass
class DimensionCurve:
    """D_f (-) against one swept key, as in the paper's Figs. 4-5: every finished run, and
    the mean and standard deviation over the replicates at each value of the key."""

    key: str  # the swept column on x
    runs: list[tuple[float, float, str]]  # (x, D_f, label) of each finished run with a D_f
    values: list[float]  # the distinct x, ascending
    means: list[float]  # mean D_f at each value
    sds: list[float]  # sample standard deviation at each value (0 for a single run)
    name: str  # the summary's name (its directory), for titles


def dimension_curve(table: SummaryLike, key: str | None = None) -> DimensionCurve:
    """The points of a D_f curve over ``key`` (default: the parameter column with the most
    distinct values).

    Raises
    ------
    ConfigError
        If the table has no swept column (``key`` not given), no column ``key``, or no
        finished run with a D_f; the message names the summary file.
    """
    table = as_summary(table)
    where = table.source or "the table"
    params = table.parameter_columns
    if key is None:
        if not params:
            raise ConfigError(f"{where}: no swept column to draw D_f over")
        key = max(params, key=lambda c: len({r.get(c) for r in table.rows}))
    if key not in table.columns:
        raise ConfigError(f"{where}: no column {key!r}")
    runs = [
        (x, d_f, run_label(row))
        for row, d_f in measured_runs(table)
        if (x := finite_number(row.get(key))) is not None
    ]
    if not runs:
        raise ConfigError(f"{where}: no finished run with a D_f")
    xs = np.array([x for x, _, _ in runs])
    values = sorted(set(xs.tolist()))
    means = [float(np.mean([d for x, d, _ in runs if x == v])) for v in values]
    sds = [
        float(np.std([d for x, d, _ in runs if x == v], ddof=1)) if sum(xs == v) > 1 else 0.0
        for v in values
    ]
    return DimensionCurve(key, runs, values, means, sds, table.name)


__all__ = [
    "AXES_KINDS",
    "LABELS",
    "UNCLASSIFIED",
    "DimensionCurve",
    "PhasePoint",
    "choose_axes",
    "dimension_curve",
    "finite_number",
    "measured_runs",
    "phase_points",
    "points_table",
    "regime_dimensions",
]
