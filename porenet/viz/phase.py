"""Phase diagrams of a sweep: regimes on the paper's Ca–λ (Fig. 2) or N_f–Ca* (Fig. 3) axes.

The input is the summary table that ``porenet sweep SWEEP.toml -o DIR`` writes
(``DIR/summary.csv``, one row per run: the swept keys under their dotted names, ``seed``,
``status``, ``fractal_dimension``, ``regime``, ``run_file``, ...), read with
:func:`porenet.sweep.records.read_summary` (the csv module; no pandas).

Axes (``axes=``):

* ``"ca-lambda"`` (rigid media, Fig. 2): x = disorder λ (linear, 0 to 1), y = Ca (log), and
  the theoretical CF/VF line ``Ca = [λ/(1-λ²)] a/L`` (``L = n a``; one line per lattice
  size in the table) with the intermediate band ``INTERMEDIATE_HALF_WIDTH`` decades either
  side of it. The paper's text names the plane "Ca–λ" and says the crossover curve diverges
  as λ -> 1; it does not say which variable is horizontal. Here λ is, so the curve rises.
* ``"nf-castar"`` (deformable media, Fig. 3): x = ``Ca* = Ca (L/a) / [λ/(1-λ²)]`` (log),
  y = fracturing number N_f (log), dashed lines ``N_f = 1`` and ``Ca* = 1`` (below
  ``N_f = 1``, where fingering is left), as the grey dashed lines of Fig. 3.
* ``"auto"``: ``nf-castar`` when the table has a fracturing-number column
  (``solid.fracturing_number``) or its runs are deformable, ``ca-lambda`` otherwise.

Coordinates come from the table's columns when the key was swept (``lattice.disorder``,
``fluid.capillary_number``, ``lattice.n``, ``ca_star``, ``solid.fracturing_number``), else
from the point's scene in ``DIR/sweep.json`` (written by ``porenet sweep``), else from a run
file of the point (``RunData.scene``; N_f from its summary for scenes that give E* only).
``Ca*`` is computed from the point's ``n``, ``λ`` and ``Ca`` when it is not a column.

Decision: **replicates are aggregated**. The rows of one point (same swept values, different
seeds) give one marker: the majority label (ties go to the label with the larger summed
``regime_confidence``, then to the first of :data:`~porenet.analysis.regimes.REGIMES`), the
mean D_f of the finished replicates as its colour, and, when the replicates disagree, the
fraction that voted for the label (e.g. "2/3") written next to it. This keeps one marker per
point, as in the paper's figures, where jitter would blur the grid. Points with failed runs get
a grey cross (on top of the marker if some replicates finished). Markers are shaped by
regime; the colour is D_f on a fixed scale (:data:`DIMENSION_RANGE`, viridis) so that
diagrams compare, with the paper's values (FR 1.43, VF 1.64, CF 1.82) marked on the colour bar.
"""

from __future__ import annotations

import math
from collections import Counter
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from porenet.analysis.numbers import disorder_factor, modified_capillary_number
from porenet.analysis.regimes import INTERMEDIATE_HALF_WIDTH, REGIMES
from porenet.config.loading import get_dotted
from porenet.core.errors import ConfigError
from porenet.sweep.records import SummaryLike, SweepSummary, as_summary
from porenet.viz.style import SEQUENTIAL, styled

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

#: Axis kinds of :func:`plot_phase_diagram`.
AXES_KINDS: tuple[str, ...] = ("auto", "ca-lambda", "nf-castar")

#: Marker of each regime label (distinct shapes; "unclassified" for runs without a label).
MARKERS: dict[str, str] = {
    "CF": "o",
    "VF": "^",
    "FR": "s",
    "CF/VF": "D",
    "FR/VF": "v",
    "FR/CF": "P",
    "unclassified": "h",
}

#: The paper's fractal dimensions (Figs. 2-5 and the Appendix).
PAPER_DIMENSIONS: dict[str, float] = {"FR": 1.43, "VF": 1.64, "CF": 1.82}

#: Fixed colour scale of D_f (values outside are drawn at the ends; the bar says so).
DIMENSION_RANGE: tuple[float, float] = (1.3, 1.95)

_LAMBDA, _CA, _N = "lattice.disorder", "fluid.capillary_number", "lattice.n"
_NF_COLUMNS = ("solid.fracturing_number", "fracturing_number")
_FAILED_GREY = "0.45"


def _number(value: Any) -> float | None:
    if value is None or isinstance(value, bool):
        return None
    try:
        x = float(value)
    except (TypeError, ValueError):
        return None
    return x if math.isfinite(x) else None


@dataclass
class PhasePoint:
    """One point of a sweep (its replicates aggregated) on a phase diagram."""

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
    if (scene.get("solid") or {}).get("kind", "rigid") == "rigid":
        return None
    nf = _number(summary.get("fracturing_number"))
    return nf if nf is not None else _number(get_dotted(scene, "solid.fracturing_number"))


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
        return (scene.get("solid") or {}).get("kind", "rigid") != "rigid"
    for row in table.rows:
        info = runs.get(row.get("run_file"))
        if info is not None:
            return (info[0].get("solid") or {}).get("kind", "rigid") != "rigid"
    return False


def choose_axes(table: SummaryLike) -> str:
    """The axis kind ``"auto"`` stands for: ``"nf-castar"`` when the table has an N_f
    column or its runs are deformable, ``"ca-lambda"`` otherwise."""
    table = as_summary(table)
    return "nf-castar" if _deformable(table, _RunCache(table.root)) else "ca-lambda"


def _majority(done: list[dict[str, Any]]) -> tuple[str | None, float, dict[str, int]]:
    labels = [r.get("regime") if isinstance(r.get("regime"), str) else "unclassified" for r in done]
    counts = Counter(labels)
    if not counts:
        return None, 0.0, {}
    weight: dict[str, float] = {}
    for r, label in zip(done, labels, strict=True):
        weight[label] = weight.get(label, 0.0) + (_number(r.get("regime_confidence")) or 0.0)
    order = {name: i for i, name in enumerate((*REGIMES, "unclassified"))}
    best = max(counts, key=lambda k: (counts[k], weight[k], -order.get(k, len(order))))
    return best, counts[best] / len(done), dict(counts)


def phase_points(table: SummaryLike, axes: str = "auto") -> tuple[str, list[PhasePoint]]:
    """Aggregate a summary into the points of a phase diagram.

    Returns the axis kind used (``axes``, or what ``"auto"`` picked) and one
    :class:`PhasePoint` per distinct combination of swept values, in the table's order.
    Rows whose status is neither ``done`` nor ``failed`` (pending) count in ``n_runs`` only.

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
            v = _number(first.get(column))
            if v is None and column not in table.columns:
                v = _number(get_dotted(scene, column))
            return v

        lam, ca, n_val = value(_LAMBDA), value(_CA), value(_N)
        ca_star = _number(first.get("ca_star"))
        if ca_star is None and None not in (lam, ca, n_val) and 0 < lam < 1:  # type: ignore[operator]
            ca_star = modified_capillary_number(ca, int(n_val), lam)  # type: ignore[arg-type]
        nf = next((_number(first.get(c)) for c in _NF_COLUMNS if c in table.columns), None)
        if nf is None:
            nf = _fracturing_number(*info) if info is not None else listed_nf
        if axes == "ca-lambda":
            x, y = lam, ca if ca is not None and ca > 0 else None
        else:
            x = ca_star if ca_star is not None and ca_star > 0 else None
            y = nf if nf is not None and nf > 0 else None
        done = [r for r in rows if r.get("status") == "done"]
        regime, agreement, labels = _majority(done)
        dims = np.array([d for r in done if (d := _number(r.get("fractal_dimension"))) is not None])
        points.append(
            PhasePoint(
                params={k: first.get(k) for k in table.parameter_columns},
                x=x,
                y=y,
                regime=regime,
                agreement=agreement,
                labels=labels,
                dimension=float(dims.mean()) if dims.size else math.nan,
                dimension_sd=float(dims.std(ddof=1)) if dims.size > 1 else math.nan,
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


def _log_limits(values: list[float], pad: float = 2.0) -> tuple[float, float]:
    lo, hi = min(values), max(values)
    return lo / pad, hi * pad


def _draw_ca_lambda(ax: Axes, points: list[PhasePoint]) -> None:
    ys = [p.y for p in points if p.placed]
    y_lo, y_hi = _log_limits(ys) if ys else (1e-5, 1e-1)  # type: ignore[arg-type]
    lam = np.linspace(0.002, 0.998, 400)
    sizes = sorted({p.n for p in points if p.n})
    band = 10.0**INTERMEDIATE_HALF_WIDTH
    for i, n in enumerate(sizes):
        line = disorder_factor(lam) / n
        label = rf"Ca = $[\lambda/(1-\lambda^2)]\,a/L$, L = {n}a"
        ax.plot(
            lam, line, color="k", lw=1.2, zorder=2, label=label, ls=("-", "--", ":", "-.")[i % 4]
        )
        ax.fill_between(
            lam,
            line / band,
            line * band,
            color="0.88",
            lw=0,
            zorder=1,
            label=f"CF/VF band, Ca* = $10^{{\\pm{INTERMEDIATE_HALF_WIDTH:g}}}$" if i == 0 else None,
        )
    ax.set_yscale("log")
    ax.set_xlim(0.0, 1.0)
    ax.set_ylim(y_lo, y_hi)
    ax.set_xlabel(r"disorder $\lambda$ (-)")
    ax.set_ylabel("capillary number Ca (-)")
    text = {"color": "0.45", "fontsize": 10, "fontweight": "bold", "zorder": 1.5}
    ax.text(0.015, 0.985, "VF", transform=ax.transAxes, ha="left", va="top", **text)
    ax.text(0.985, 0.015, "CF", transform=ax.transAxes, ha="right", va="bottom", **text)


def _draw_nf_castar(ax: Axes, points: list[PhasePoint]) -> None:
    xs = [p.x for p in points if p.placed]
    ys = [p.y for p in points if p.placed]
    x_lo, x_hi = _log_limits([*xs, 1.0]) if xs else (1e-2, 1e2)  # type: ignore[list-item]
    y_lo, y_hi = _log_limits([*ys, 1.0]) if ys else (1e-2, 1e2)  # type: ignore[list-item]
    line = {"color": "0.35", "ls": "--", "lw": 1.1, "zorder": 2}
    ax.plot([x_lo, x_hi], [1.0, 1.0], label=r"$N_f$ = 1 (FR above)", **line)
    ax.plot([1.0, 1.0], [y_lo, 1.0], label="Ca* = 1 (CF/VF)", **{**line, "ls": ":"})
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlim(x_lo, x_hi)
    ax.set_ylim(y_lo, y_hi)
    ax.set_xlabel(r"modified capillary number Ca* = Ca $(L/a)\,/\,[\lambda/(1-\lambda^2)]$ (-)")
    ax.set_ylabel(r"fracturing number $N_f$ (-)")
    text = {"color": "0.45", "fontsize": 10, "fontweight": "bold", "zorder": 1.5}
    ax.text(0.5, 0.97, "FR", transform=ax.transAxes, ha="center", va="top", **text)
    ax.text(0.03, 0.03, "CF", transform=ax.transAxes, ha="left", va="bottom", **text)
    ax.text(0.97, 0.03, "VF", transform=ax.transAxes, ha="right", va="bottom", **text)


@styled
def plot_phase_diagram(
    table: SummaryLike,
    ax: Axes | None = None,
    axes: str = "auto",
    title: str | None = None,
) -> Figure:
    """Draw a sweep's phase diagram (see the module's docstring for axes and markers).

    Parameters
    ----------
    table : SweepSummary, path or list of dict
        What :func:`~porenet.sweep.records.read_summary` returns, a sweep directory or
        ``summary.csv`` path, or rows as dicts (``run_file`` entries then relative to the
        current directory).
    ax : matplotlib Axes, optional
    axes : {"auto", "ca-lambda", "nf-castar"}
    title : str, optional
        Default: the sweep directory's name and the number of runs.

    Raises
    ------
    ConfigError
        For an unknown ``axes``, or when no point can be placed on the axes (a column is
        missing and no run file gives it).
    """
    from matplotlib.colors import Normalize
    from matplotlib.figure import Figure
    from matplotlib.lines import Line2D

    table = as_summary(table)
    kind, points = phase_points(table, axes)
    placed = [p for p in points if p.placed]
    if not placed:
        need = (
            "lattice.disorder and fluid.capillary_number"
            if kind == "ca-lambda"
            else "ca_star (or lattice.n, lattice.disorder, fluid.capillary_number) and "
            "solid.fracturing_number"
        )
        where = table.source or "the table"
        raise ConfigError(
            f"{where}: no point can be placed on {kind} axes: columns {need} "
            f"missing and no run file gives them"
        )
    if ax is None:
        fig = Figure(figsize=(5.6, 4.6), dpi=150, layout="constrained")
        ax = fig.add_subplot()
    else:
        fig = ax.figure  # type: ignore[assignment]
    if kind == "ca-lambda":
        _draw_ca_lambda(ax, placed)
    else:
        _draw_nf_castar(ax, placed)

    import matplotlib

    cmap = matplotlib.colormaps[SEQUENTIAL]
    norm = Normalize(*DIMENSION_RANGE)
    seen: list[str] = []
    for p in placed:
        if p.regime is None:
            continue
        marker = MARKERS.get(p.regime, MARKERS["unclassified"])
        face = "white" if math.isnan(p.dimension) else cmap(norm(p.dimension))
        ax.scatter(
            [p.x], [p.y], marker=marker, s=46, c=[face], edgecolors="k", linewidths=0.6, zorder=3
        )
        if p.regime not in seen:
            seen.append(p.regime)
        if p.n_done > 1 and p.agreement < 1.0:
            votes = p.labels[p.regime]
            ax.annotate(
                f"{votes}/{p.n_done}",
                (p.x, p.y),
                xytext=(5, 4),  # type: ignore[arg-type]
                textcoords="offset points",
                fontsize=6,
                color="0.25",
                zorder=4,
            )
    failed = [p for p in placed if p.n_failed]
    if failed:
        ax.scatter(
            [p.x for p in failed],
            [p.y for p in failed],
            marker="x",
            s=60,
            c=_FAILED_GREY,
            linewidths=1.4,
            zorder=5,
        )

    order = [r for r in (*REGIMES, "unclassified") if r in seen]
    handles = [
        Line2D([], [], ls="", marker=MARKERS[r], mfc="0.8", mec="k", mew=0.6, ms=6, label=r)
        for r in order
    ]
    if failed:
        n_failed = sum(p.n_failed for p in failed)
        handles.append(
            Line2D(
                [],
                [],
                ls="",
                marker="x",
                color=_FAILED_GREY,
                mew=1.4,
                ms=7,
                label=f"failed ({n_failed} run{'s' * (n_failed != 1)})",
            )
        )

    from matplotlib.cm import ScalarMappable

    bar = fig.colorbar(ScalarMappable(norm=norm, cmap=cmap), ax=ax, extend="both", pad=0.02)
    bar.set_label(r"fractal dimension $D_f$ (mean over replicates)")
    ticks = sorted(PAPER_DIMENSIONS.items(), key=lambda kv: kv[1])
    bar.set_ticks([v for _, v in ticks], labels=[f"{v:.2f} {k}" for k, v in ticks])
    bar.ax.tick_params(labelsize=7)

    n_runs = sum(p.n_runs for p in points)
    not_placed = sum(p.n_runs for p in points if not p.placed)
    reps = {p.n_runs for p in points}
    lines = [title if title is not None else (table.name or "sweep")]
    detail = f"{len(placed)} points, {n_runs} runs"
    if reps and max(reps) > 1:
        detail += f" ({'/'.join(str(r) for r in sorted(reps))} per point, aggregated)"
    if not_placed:
        detail += f"; {not_placed} runs not placed (coordinates unknown)"
    lines.append(detail)
    line_handles, _ = ax.get_legend_handles_labels()
    n_cols = max(2, -(-len(handles) // 2))
    ax.legend(
        handles=[*handles, *line_handles],
        loc="lower left",
        bbox_to_anchor=(0.0, 1.01),
        ncol=n_cols,
        fontsize=7,
        borderaxespad=0.0,
        handletextpad=0.3,
        columnspacing=1.0,
        title=": ".join(x for x in lines if x),
        title_fontsize=7.5,
        alignment="left",
    )
    return fig


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


def regime_dimensions(
    table: SummaryLike,
) -> dict[str, tuple[float, float, int]]:
    """Per regime label: mean D_f, standard deviation and count over the finished runs with
    that label (each run counts with its own label, replicates not aggregated)."""
    table = as_summary(table)
    by_label: dict[str, list[float]] = {}
    for row in table.rows:
        d_f = _number(row.get("fractal_dimension"))
        if row.get("status") != "done" or d_f is None:
            continue
        label = row.get("regime") if isinstance(row.get("regime"), str) else "unclassified"
        by_label.setdefault(label, []).append(d_f)
    out: dict[str, tuple[float, float, int]] = {}
    for label in (*REGIMES, "unclassified"):
        if label in by_label:
            dims = np.array(by_label[label])
            sd = float(dims.std(ddof=1)) if dims.size > 1 else math.nan
            out[label] = (float(dims.mean()), sd, int(dims.size))
    return out


_KEY_LABELS = {
    "fluid.capillary_number": "capillary number Ca (-)",
    "lattice.disorder": r"disorder $\lambda$ (-)",
    "solid.fracturing_number": r"fracturing number $N_f$ (-)",
    "ca_star": "modified capillary number Ca* (-)",
}


@styled
def plot_dimension_curve(
    table: SummaryLike,
    key: str | None = None,
    ax: Axes | None = None,
    title: str | None = None,
) -> Figure:
    """D_f against one swept key, as in the paper's Figs. 4-5 (D_f across Ca, or across N_f).

    Every finished run is a small marker shaped by its regime label; the mean over the
    replicates of each value of ``key`` is joined by a line, with the standard deviation as
    an error bar; the paper's values (FR 1.43, VF 1.64, CF 1.82) are dashed lines. The x axis
    is logarithmic when the values span a factor 10 or more.

    Parameters
    ----------
    key : str, optional
        The swept column for x; default: the parameter column with the most distinct values.

    Raises
    ------
    ConfigError
        If the table has no such column or no finished run with a D_f.
    """
    from matplotlib.figure import Figure

    table = as_summary(table)
    params = table.parameter_columns
    if key is None:
        if not params:
            raise ConfigError(f"{table.source or 'the table'}: no swept column to draw D_f over")
        key = max(params, key=lambda c: len({r.get(c) for r in table.rows}))
    if key not in table.columns:
        raise ConfigError(f"{table.source or 'the table'}: no column {key!r}")
    runs = [
        (x, d, r.get("regime") if isinstance(r.get("regime"), str) else "unclassified")
        for r in table.rows
        if r.get("status") == "done"
        and (x := _number(r.get(key))) is not None
        and (d := _number(r.get("fractal_dimension"))) is not None
    ]
    if not runs:
        raise ConfigError(f"{table.source or 'the table'}: no finished run with a D_f")
    if ax is None:
        fig = Figure(figsize=(5.0, 3.6), dpi=150, layout="constrained")
        ax = fig.add_subplot()
    else:
        fig = ax.figure  # type: ignore[assignment]
    xs = np.array([x for x, _, _ in runs])
    log = bool(np.all(xs > 0) and xs.max() / xs.min() >= 10.0)
    for name, value in PAPER_DIMENSIONS.items():
        ax.axhline(value, color="0.6", ls="--", lw=0.9, zorder=1)
        ax.annotate(
            f"{name} {value:.2f} (paper)",
            (1.0, value),
            xycoords=("axes fraction", "data"),
            xytext=(-3, 2),
            textcoords="offset points",
            ha="right",
            va="bottom",
            fontsize=6.5,
            color="0.4",
        )
    for label in [r for r in (*REGIMES, "unclassified") if any(g == r for _, _, g in runs)]:
        sel = [(x, d) for x, d, g in runs if g == label]
        ax.plot(
            *zip(*sel, strict=True),
            ls="",
            marker=MARKERS[label],
            ms=4.5,
            mfc="0.8",
            mec="k",
            mew=0.5,
            zorder=3,
            label=label,
        )
    grid = sorted(set(xs.tolist()))
    means = [np.mean([d for x, d, _ in runs if x == v]) for v in grid]
    sds = [
        np.std([d for x, d, _ in runs if x == v], ddof=1) if sum(xs == v) > 1 else 0.0 for v in grid
    ]
    ax.errorbar(
        grid,
        means,
        yerr=sds,
        color="k",
        lw=1.2,
        capsize=2.5,
        zorder=2,
        label="mean ± sd over seeds",
    )
    if log:
        ax.set_xscale("log")
    ax.set_xlabel(_KEY_LABELS.get(key, key))
    ax.set_ylabel(r"fractal dimension $D_f$ (-)")
    ax.legend(loc="best", fontsize=7, ncol=2)
    heading = title if title is not None else table.name
    if heading:
        ax.set_title(heading, loc="left", fontsize=8)
    return fig
