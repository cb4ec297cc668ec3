"""Phase diagrams of a sweep drawn: regimes on the paper's Ca–λ (Fig. 2) or N_f–Ca* (Fig. 3)
axes, and D_f against one swept key (Figs. 4-5).

What is drawn comes from :mod:`porenet.analysis.phase` (the summary's runs aggregated into
points, replicates by majority label; its docstring says how coordinates are found), which
loads no matplotlib; this module only draws.

Axes (``axes=``):

* ``"ca-lambda"`` (rigid media, Fig. 2): x = disorder λ (linear, 0 to 1), y = Ca (log), and
  the theoretical CF/VF line ``Ca = [λ/(1-λ²)] a/L`` (``L = n a``; one line per lattice
  size in the table) with the intermediate band ``INTERMEDIATE_HALF_WIDTH`` decades either
  side of it. The paper's text names the plane "Ca–λ" and says the crossover curve diverges
  as λ -> 1; it does not say which variable is horizontal. Here λ is, so the curve rises.
* ``"nf-castar"`` (deformable media, Fig. 3): x = ``Ca* = Ca (L/a) / [λ/(1-λ²)]`` (log),
  y = fracturing number N_f (log), dashed lines ``N_f = 1`` and ``Ca* = 1`` (below
  ``N_f = 1``, where fingering is left), as the grey dashed lines of Fig. 3.
* ``"auto"``: :func:`porenet.analysis.phase.choose_axes`.

Markers: one per point, shaped by its majority label; the colour is the mean D_f of the
finished replicates on a fixed scale (:data:`DIMENSION_RANGE`, viridis) so that diagrams
compare, with the paper's values (FR 1.43, VF 1.64, CF 1.82) marked on the colour bar; when
the replicates disagree, the fraction that voted for the label (e.g. "2/3") is written next
to it. Points with failed runs get a grey cross (on top of the marker if some replicates
finished).
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from porenet.analysis.numbers import disorder_factor
from porenet.analysis.phase import (
    LABELS,
    UNCLASSIFIED,
    PhasePoint,
    dimension_curve,
    phase_points,
)
from porenet.analysis.regimes import INTERMEDIATE_HALF_WIDTH
from porenet.core.errors import ConfigError
from porenet.sweep.records import SummaryLike, as_summary
from porenet.viz.style import SEQUENTIAL, styled

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes
    from matplotlib.axis import Axis
    from matplotlib.figure import Figure

#: Marker of each regime label (distinct shapes; "unclassified" for runs without a label).
MARKERS: dict[str, str] = {
    "CF": "o",
    "VF": "^",
    "FR": "s",
    "CF/VF": "D",
    "FR/VF": "v",
    "FR/CF": "P",
    UNCLASSIFIED: "h",
}

#: The paper's fractal dimensions (Figs. 2-5 and the Appendix).
PAPER_DIMENSIONS: dict[str, float] = {"FR": 1.43, "VF": 1.64, "CF": 1.82}

#: Fixed colour scale of D_f (values outside are drawn at the ends; the bar says so).
DIMENSION_RANGE: tuple[float, float] = (1.3, 1.95)

_FAILED_GREY = "0.45"


def _log_limits(values: list[float], pad: float = 2.0) -> tuple[float, float]:
    lo, hi = min(values), max(values)
    return lo / pad, hi * pad


#: A log axis spanning fewer decades than this gets short plain labels (matplotlib would label
#: its minor ticks as "2 x 10^-1", "3 x 10^-1", ..., which overlap).
SHORT_LABEL_DECADES = 1.5


def _short_log_labels(axis: Axis, lo: float, hi: float) -> None:
    """Plain labels ("0.3", "1", "2") on a log axis from ``lo`` to ``hi`` when it spans few
    decades (a sweep over a narrow range, or one still running): every decade and its 2, 3
    and 5 multiples."""
    from matplotlib.ticker import FuncFormatter

    if hi / lo >= 10.0**SHORT_LABEL_DECADES:
        return

    def label(value: float, _pos: int) -> str:
        mantissa = value / 10.0 ** math.floor(math.log10(value) + 1e-9)
        return f"{value:g}" if min(abs(mantissa - m) for m in (1, 2, 3, 5)) < 1e-6 else ""

    axis.set_major_formatter(FuncFormatter(label))
    axis.set_minor_formatter(FuncFormatter(label))


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
    _short_log_labels(ax.yaxis, y_lo, y_hi)
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
    _short_log_labels(ax.xaxis, x_lo, x_hi)
    _short_log_labels(ax.yaxis, y_lo, y_hi)
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
        marker = MARKERS.get(p.regime, MARKERS[UNCLASSIFIED])
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

    order = [r for r in LABELS if r in seen]
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

    curve = dimension_curve(table, key)
    runs = curve.runs
    if ax is None:
        fig = Figure(figsize=(5.0, 3.6), dpi=150, layout="constrained")
        ax = fig.add_subplot()
    else:
        fig = ax.figure  # type: ignore[assignment]
    xs = np.array([x for x, _, _ in runs])
    log = bool(np.all(xs > 0) and xs.max() / xs.min() >= 10.0)  # axis: a factor 10 or more
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
    for label in [r for r in LABELS if any(g == r for _, _, g in runs)]:
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
    ax.errorbar(
        curve.values,
        curve.means,
        yerr=curve.sds,
        color="k",
        lw=1.2,
        capsize=2.5,
        zorder=2,
        label="mean ± sd over seeds",
    )
    if log:
        ax.set_xscale("log")
    ax.set_xlabel(_KEY_LABELS.get(curve.key, curve.key))
    ax.set_ylabel(r"fractal dimension $D_f$ (-)")
    ax.legend(loc="best", fontsize=7, ncol=2)
    heading = title if title is not None else curve.name
    if heading:
        ax.set_title(heading, loc="left", fontsize=8)
    return fig


__all__ = [
    "DIMENSION_RANGE",
    "MARKERS",
    "PAPER_DIMENSIONS",
    "PhasePoint",
    "plot_dimension_curve",
    "plot_phase_diagram",
]
