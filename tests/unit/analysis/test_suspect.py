"""Suspect results are flagged in /summary (docs/stability.md, "Suspect results")."""

from __future__ import annotations

from pathlib import Path

import porenet
from porenet.analysis.suspect import CA_FACTOR, LIMIT_FRACTION, suspect_physics
from porenet.config.loading import load_scene

FIG1B = str(Path(__file__).resolve().parents[3] / "examples" / "scenes" / "fig1b.toml")


def test_a_sound_run_has_no_warning():
    summary = {"capillary_number": 9e-4, "capillary_number_measured": 8.99e-4,
               "apertures_at_cap": 53, "apertures_at_floor": 0}  # fmt: skip
    assert suspect_physics(summary, 1740) == []


def test_most_throats_at_a_limit_are_flagged():
    m = 1740
    at = int(LIMIT_FRACTION * m) + 1
    cap = suspect_physics({"apertures_at_cap": at}, m)
    floor = suspect_physics({"apertures_at_floor": at}, m)
    assert len(cap) == 1 and f"{at} of {m} throats reached the aperture cap" in cap[0]
    assert len(floor) == 1 and "floor" in floor[0]
    assert suspect_physics({"apertures_at_cap": int(LIMIT_FRACTION * m)}, m) == []


def test_a_measured_ca_far_from_the_requested_one_is_flagged():
    off = suspect_physics({"capillary_number": 1e6, "capillary_number_measured": 1.6e4}, 100)
    assert len(off) == 1 and "measured Ca = 1.6e+04" in off[0]
    near = {"capillary_number": 1.0, "capillary_number_measured": 1.0 / (0.99 * CA_FACTOR)}
    assert suspect_physics(near, 100) == []
    assert suspect_physics({"capillary_number": None, "capillary_number_measured": 0.0}, 9) == []


def test_the_run_stores_and_logs_them(caplog):
    """Ca = 1e4 on 15 x 15: the pump cannot deliver it (measured ~1.6e3)."""
    scene = load_scene(
        FIG1B, ["lattice.n=15", "fluid.capillary_number=1e4", "classifier.kind=none"]
    )
    with caplog.at_level("WARNING"):
        summary = porenet.run(scene).summary
    assert "measured Ca" in summary["physics_warnings"]
    assert any("suspect result" in r.getMessage() for r in caplog.records)
    quiet = porenet.run(load_scene(FIG1B, ["lattice.n=15", "classifier.kind=none"]))
    assert quiet.summary["physics_warnings"] == ""
