"""Work-precision figures: error against wall time, one panel per error measure."""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.figure import Figure

MARKERS = "os^vDP"


def _plain_log_ticks(ax: Any) -> None:
    """Label a log axis that spans less than a decade or two with plain numbers at a few
    ticks (matplotlib's default labels every minor tick of a narrow log axis as ``a x 10^b``,
    and they overlap)."""
    from matplotlib.ticker import LogLocator, NullFormatter, StrMethodFormatter

    ax.autoscale_view()  # the limits the data give (or were set), before the ticks are chosen
    for axis, (lo, hi) in ((ax.xaxis, ax.get_xlim()), (ax.yaxis, ax.get_ylim())):
        if lo > 0 and hi / lo < 100:
            subs = (1.0, 1.5, 2.0, 3.0, 5.0, 7.0) if hi / lo < 10 else (1.0, 2.0, 5.0)
            axis.set_major_locator(LogLocator(subs=subs))
            axis.set_major_formatter(StrMethodFormatter("{x:.3g}"))
            axis.set_minor_formatter(NullFormatter())


def error_vs_wall(
    groups: Sequence[tuple[str, Sequence[dict[str, Any]], str]],
    metrics: Sequence[str],
    title: str,
    *,
    zero_at: float | None = None,
    reference_wall: float | None = None,
    reference_label: str = "reference",
) -> Figure:
    """Log-log error against wall time, one panel per metric, one line per group.

    Parameters
    ----------
    groups : sequence of (label, rows, linestyle)
        Each row is a dict with ``"wall"`` (s), ``"value"`` (the setting, written beside its
        point) and one error per metric.
    metrics : sequence of str
        Keys of the errors, one panel each (``"breakthrough_time"`` is labelled
        "breakthrough time error").
    title : str
        Figure title.
    zero_at : float, optional
        Where an error of exactly 0 is drawn; default a third of the smallest non-zero error
        of the panel. A panel with such errors marks that level with a dashed line labelled
        "exactly 0".
    reference_wall : float, optional
        Draws the reference run's wall time as a dotted vertical line.
    """
    from matplotlib.figure import Figure
    from matplotlib.ticker import NullFormatter

    fig = Figure(figsize=(10, 3.4), dpi=130, layout="constrained")
    axes = fig.subplots(1, len(metrics), squeeze=False)[0]
    rows = [r for _, members, _ in groups for r in members]
    for ax, metric in zip(axes, metrics, strict=True):
        floor = zero_at
        if floor is None:
            floor = min((r[metric] for r in rows if r[metric] > 0), default=1e-6) / 3
        for (label, members, style), marker in zip(groups, MARKERS, strict=False):
            pts = [(r["wall"], max(r[metric], floor), r["value"]) for r in members]
            ax.loglog([p[0] for p in pts], [p[1] for p in pts], marker=marker,
                      linestyle=style, label=label)  # fmt: skip
            for w, e, v in pts:
                ax.annotate(f"{v}", (w, e), fontsize=7, xytext=(3, 3), textcoords="offset points")
        all_zero = all(r[metric] == 0 for r in rows)
        if all_zero:
            ax.set_ylim(floor / 10, floor * 10)  # nothing else to scale the axis by
        if any(r[metric] == 0 for r in rows):
            ax.axhline(floor, color="0.5", lw=0.7, ls="--")
            ax.annotate(
                "every run: exactly 0" if all_zero else "exactly 0", (0.01, floor),
                xycoords=("axes fraction", "data"), xytext=(0, 3), textcoords="offset points",
                fontsize=7, color="0.4",
            )  # fmt: skip
        if reference_wall is not None:
            ax.axvline(reference_wall, color="k", lw=0.8, ls=":", label=reference_label)
        _plain_log_ticks(ax)
        if all_zero:  # the axis has no scale to show
            ax.yaxis.set_major_formatter(NullFormatter())
            ax.yaxis.set_minor_formatter(NullFormatter())
        ax.set_xlabel("wall time (s)")
        ax.set_ylabel(f"{metric.replace('_', ' ')} error")
        ax.grid(True, which="both", alpha=0.3)
    axes[0].legend(fontsize=8)
    fig.suptitle(title, fontsize=10)
    return fig
