"""Time series of a run: invading pressure, volumes and capillary number against time.

Dynamic runs record them (``RunData.timeseries``, SI). Quasi-static runs have no clock: their
"time series" is the entry pressure overcome at each drainage step, the IP pressure signal.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from porenet.viz.style import (
    OKABE_ITO,
    pressure_unit,
    scene_title,
    styled,
    time_unit,
    volume_unit,
)

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from porenet.result import RunData

#: Volume series drawn in the volume panel, with their legend labels.
VOLUMES = {
    "injected": "injected (pump)",
    "drained": "invader in the medium",
    "stored": "stored (compressibility)",
    "outflow": "defender out",
    "released": "released on drainage",
}


@styled
def plot_timeseries(data: RunData) -> Figure:
    """Invading pressure, volumes and capillary number against time (dynamic runs), or the
    entry pressure of each drainage step (quasi-static runs).

    Dynamic runs: three panels sharing the time axis: ``p_inv`` (Pa, kPa or MPa), the volume
    series (injected, drained, stored, outflow, released; m³ with a readable prefix) and the
    measured capillary number with the requested one dashed.
    """
    if data.timeseries and "time" in data.timeseries:
        return _dynamic(data)
    return plot_entry_pressure(data)


def _dynamic(data: RunData) -> Figure:
    from matplotlib.figure import Figure

    ts = data.timeseries
    t_unit, t_factor = time_unit(float(np.max(ts["time"])) or 1.0)
    t = ts["time"] / t_factor
    panels = ["invading_pressure" in ts, any(k in ts for k in VOLUMES), "capillary_number" in ts]
    n = max(sum(panels), 1)
    fig = Figure(figsize=(5.0, 1.6 + 1.5 * n), dpi=150, layout="constrained")
    axes = list(fig.subplots(n, 1, sharex=True, squeeze=False)[:, 0])
    it = iter(axes)
    if panels[0]:
        ax = next(it)
        p_unit, p_factor = pressure_unit(float(np.max(np.abs(ts["invading_pressure"]))) or 1.0)
        ax.plot(t, ts["invading_pressure"] / p_factor, color=OKABE_ITO[0])
        ax.set_ylabel(f"$p_{{inv}}$ ({p_unit})")
        ax.set_ylim(bottom=0)
    if panels[1]:
        ax = next(it)
        present = [k for k in VOLUMES if k in ts]
        v_unit, v_factor = volume_unit(max(float(np.max(np.abs(ts[k]))) for k in present) or 1.0)
        for k, color in zip(present, OKABE_ITO, strict=False):
            style = "--" if k == "injected" else "-"
            ax.plot(t, ts[k] / v_factor, style, color=color, label=VOLUMES[k])
        ax.set_ylabel(f"volume ({v_unit})")
        ax.set_ylim(bottom=0)
        ax.legend(loc="upper left", ncols=2 if len(present) > 3 else 1)
    if panels[2]:
        ax = next(it)
        ax.plot(t, ts["capillary_number"], color=OKABE_ITO[2], label="measured")
        requested = data.summary.get(
            "capillary_number", data.scene.get("fluid", {}).get("capillary_number")
        )
        if requested:
            ax.axhline(requested, color="k", lw=0.9, ls="--", label="requested")
        ax.set_ylabel("Ca (-)")
        ax.set_ylim(bottom=0)
        ax.legend(loc="lower right")
    axes[-1].set_xlabel(f"time ({t_unit})")
    axes[-1].set_xlim(left=0)
    fig.suptitle(scene_title(data))
    return fig


@styled
def plot_entry_pressure(data: RunData, ax: Axes | None = None) -> Figure:
    """The quasi-static pressure signal: entry pressure overcome at each drainage step and its
    running maximum (the invading pressure needed so far; bursts start at its record highs)."""
    from matplotlib.figure import Figure

    if ax is None:
        fig = Figure(figsize=(5.0, 3.0), dpi=150, layout="constrained")
        ax = fig.add_subplot()
        ax.set_title(scene_title(data))
    else:
        fig = ax.figure  # type: ignore[assignment]
    p = np.asarray(data.invasion_pressure, dtype=float)
    inlets = np.asarray(data.throat) < 0
    step = np.arange(p.size)
    p_unit, p_factor = pressure_unit(float(np.max(p, initial=0.0)) or 1.0)
    ax.plot(step[~inlets], p[~inlets] / p_factor, ".", ms=2.5, color=OKABE_ITO[0],
            label="entry pressure $p_e$ of the step")  # fmt: skip
    running = np.maximum.accumulate(np.where(inlets, -np.inf, p))
    running[~np.isfinite(running)] = np.nan
    ax.plot(step, running / p_factor, drawstyle="steps-post", color=OKABE_ITO[3],
            label="running maximum")  # fmt: skip
    ax.set_xlabel("drainage step")
    ax.set_ylabel(f"pressure ({p_unit})")
    ax.set_xlim(left=0)
    ax.legend(loc="lower right")
    return fig
