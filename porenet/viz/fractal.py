"""A fractal-dimension fit: the measured curve on log-log axes, the fitted range and the line."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from porenet.viz.style import OKABE_ITO, length_unit, styled

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from porenet.analysis.fractal import FractalFit

_AXES = {
    "mass-radius": ("distance from the inlet $R$", "drained pores within $R$, $M(R)$"),
    "box-counting": ("box side $s$", "occupied boxes $N(s)$"),
}


@styled
def plot_fractal_fit(
    fit: FractalFit,
    ax: Axes | None = None,
    label: str | None = None,
    spacing: float | None = None,
    color: str | None = None,
) -> Figure:
    """Log-log plot of a :class:`~porenet.analysis.fractal.FractalFit`.

    All measured points are drawn as open markers, the points inside the fitting range
    filled, and the fitted power law as a line over that range; the legend gives
    ``D_f ± error`` (error: standard error and the estimator's bias, see docs/fractal.md).

    Parameters
    ----------
    fit : FractalFit
    ax : matplotlib Axes, optional
    label : str, optional
        Prefix of the legend entry (e.g. the run's name).
    spacing : float, optional
        Lattice spacing ``2a`` (m): the scale axis is then drawn in physical length units;
        in lattice spacings otherwise.
    color : str, optional
        Colour of the points and line (default: the first Okabe-Ito colour).
    """
    from matplotlib.figure import Figure

    if ax is None:
        fig = Figure(figsize=(4.4, 3.6), dpi=150, layout="constrained")
        ax = fig.add_subplot()
    else:
        fig = ax.figure  # type: ignore[assignment]
    color = color or OKABE_ITO[0]
    scales = np.asarray(fit.scales, dtype=float)
    counts = np.asarray(fit.counts, dtype=float)
    fitted = np.asarray(fit.fitted, dtype=bool)
    if spacing:
        unit, factor = length_unit(float(np.max(scales)) * spacing)
        x, x_unit = scales * spacing / factor, unit
    else:
        x, x_unit = scales, "lattice spacings"
    positive = counts > 0
    ax.loglog(x[positive & ~fitted], counts[positive & ~fitted], "o", mfc="none", color=color,
              label="outside the fit")  # fmt: skip
    ax.loglog(x[positive & fitted], counts[positive & fitted], "o", color=color,
              label="fitted")  # fmt: skip
    slope = fit.dimension if fit.method != "box-counting" else -fit.dimension
    if fitted.any():
        s = np.geomspace(scales[fitted].min(), scales[fitted].max(), 50)
        ratio = x[fitted].min() / scales[fitted].min()
        name = f"{label}: " if label else ""
        err = f" ± {fit.error:.2f}" if np.isfinite(fit.error) else ""
        ax.loglog(s * ratio, np.exp(fit.intercept) * s**slope, "-", color="k", lw=1.0,
                  label=f"{name}$D_f$ = {fit.dimension:.2f}{err}")  # fmt: skip
    x_label, y_label = _AXES.get(fit.method, ("scale", "count"))
    ax.set_xlabel(f"{x_label} ({x_unit})")
    ax.set_ylabel(f"{y_label} (-)")
    ax.legend(loc="upper left" if slope > 0 else "upper right")
    ax.grid(True, which="major", alpha=0.25, lw=0.5)
    _plain_log_ticks(ax)
    return fig


def _plain_log_ticks(ax: Axes) -> None:
    """Log axes labelled 0.2, 0.5, 1, 2, 5 ... (plain numbers), not 2 × 10⁻¹."""
    from matplotlib.ticker import FuncFormatter, LogLocator, NullFormatter

    plain = FuncFormatter(lambda v, _: f"{v:g}")
    ax.autoscale_view()
    for axis, (lo, hi) in ((ax.xaxis, ax.get_xlim()), (ax.yaxis, ax.get_ylim())):
        axis.set_major_formatter(plain)
        if hi / lo < 100.0:
            axis.set_minor_locator(LogLocator(base=10.0, subs=(2.0, 5.0)))
            axis.set_minor_formatter(plain)
        else:
            axis.set_minor_formatter(NullFormatter())
