"""The classifier's labels at the deep ends of the paper's phase diagrams, one run each.

The paper's regimes (docs/classification.md) at points where they are not in doubt, on the
paper's own scenes at n = 100: viscous fingering (VF) at high Ca and capillary fingering
(CF) at low Ca and low disorder in a rigid medium (paper's Figs. 2 and 4), fracturing (FR)
at a high fracturing number and none at a low one in a deformable medium (Fig. 5). The
small twins of the paper's sweeps, every point of each figure's axis with several seeds,
check the same at a few minutes each (tests/verification/test_paper_sweeps.py, marker
``paper``); every seed of those twins gave these labels at these points, so one seed here
is a check, not a draw.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from porenet.simulation import Simulation

SCENES = Path(__file__).resolve().parents[2] / "examples" / "scenes"

#: Ca at Ca* = 10 for n = 100 and λ = 0.1: Ca* = Ca (L/a) (1 - λ²)/λ (docs/model.md).
CA_STAR_10 = 10 * 0.1 / (1 - 0.1**2) / 100

#: (scene, overrides, what the label must be, or must not start with for "not FR").
POINTS = {
    "fig2: high Ca is VF": ("fig1b.toml", ["lattice.disorder=0.5", "fluid.capillary_number=0.1"],
                            "VF"),
    "fig2: low Ca, low disorder is CF": ("fig1b.toml", ["lattice.disorder=0.5",
                                                        "fluid.capillary_number=3e-4"], "CF"),
    "fig4: lambda 0.1, Ca* 30 is VF": ("fig1b.toml", ["lattice.disorder=0.1",
                                                      "fluid.capillary_number=3e-2"], "VF"),
    "fig5: N_f 10 is FR": ("fig5.toml", [f"fluid.capillary_number={CA_STAR_10}",
                                         "solid.fracturing_number=10"], "FR"),
    "fig5: N_f 0.01 is not FR": ("fig5.toml", [f"fluid.capillary_number={CA_STAR_10}",
                                               "solid.fracturing_number=0.01"], "not FR"),
}  # fmt: skip


@pytest.mark.parametrize("point", list(POINTS))
def test_the_label_at_a_deep_point(point):
    scene, overrides, expected = POINTS[point]
    result = Simulation.from_scene(SCENES / scene, ["lattice.n=100", "seed=2010", *overrides]).run()
    regime = result.summary["regime"]
    if expected == "not FR":
        assert not regime.startswith("FR"), regime
    else:
        assert regime == expected, regime
