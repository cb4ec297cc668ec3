"""The figure kinds of ``porenet plot --kind KIND``, by name, with their one-line descriptions.

Kept apart from :mod:`porenet.viz.figures` (which pairs each name with the function that draws
it and takes its descriptions from here) so that building the command line imports no
plotting code.
"""

from __future__ import annotations

#: kind -> one-line description, in the order ``porenet plot --help`` lists them.
PLOT_KIND_DESCRIPTIONS: dict[str, str] = {
    "pattern": "drained pores coloured by drainage order; trapped defender grey",
    "time": "drained pores coloured by invasion time (dynamic runs)",
    "pressure": "log10(p / p_inv) around the pattern, Fig. 1b (viscous runs)",
    "fractal": "M(R) against distance from the inlet and box counts, with D_f fits",
    "mechanics": "aperture change r / r0 - 1 and removed springs (deformable runs)",
    "timeseries": "p_inv, volumes and Ca against time (dynamic) or entry pressure per step "
    "(static)",
}
