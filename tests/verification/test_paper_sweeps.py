"""The small twins of the paper's sweeps (examples/sweeps/*-small.toml), run as a user would,
and checked against the paper's phase diagrams where the regime is not in doubt.

Each twin takes ~0.5-2 minutes on 2 cores (docs/reproduction.md), so they form the ``paper``
tier, outside the default run (``pytest -m paper``; docs/verification.md); the default run
checks the same labels at one deep point each (tests/verification/test_deep_regimes.py). The
checks are the deep regimes only: labels near the theoretical lines vary with the seed
(docs/classification.md).
"""

from __future__ import annotations

import csv
from collections import defaultdict
from pathlib import Path

import pytest

from porenet.cli.main import main

SWEEPS = Path(__file__).resolve().parents[2] / "examples" / "sweeps"


def run_twin(name: str, tmp_path: Path) -> list[dict[str, str]]:
    out = tmp_path / name
    assert (
        main(["sweep", str(SWEEPS / f"{name}.toml"), "-o", str(out), "--workers", "2", "-q"]) == 0
    )
    with open(out / "summary.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    assert rows and all(r["status"] == "done" for r in rows), [r["error"] for r in rows]
    assert main(["phase-diagram", str(out), "-o", str(tmp_path / f"{name}.png")]) == 0
    return rows


def labels_by(rows: list[dict[str, str]], *keys: str) -> dict[tuple[float, ...], list[str]]:
    out: dict[tuple[float, ...], list[str]] = defaultdict(list)
    for r in rows:
        out[tuple(float(r[k]) for k in keys)].append(r["regime"])
    return out


@pytest.mark.paper
def test_fig5_small_fracturing_sets_in_near_nf_1(tmp_path):
    """Ca* = 10: FR at N_f = 3 and 10, no fracturing label at N_f <= 0.1 (paper's Fig. 5)."""
    labels = labels_by(run_twin("fig5-small", tmp_path), "solid.fracturing_number")
    for (nf,), regimes in labels.items():
        if nf >= 3:
            assert set(regimes) == {"FR"}, (nf, regimes)
        if nf <= 0.1:
            assert not any(r.startswith("FR") for r in regimes), (nf, regimes)


@pytest.mark.paper
def test_fig4_small_goes_from_viscous_to_capillary_fingering(tmp_path):
    """λ = 0.1, Ca from 3e-2 (Ca* ~ 30) down to 1e-4 (Ca* ~ 0.1): VF at the top, CF at the
    bottom (paper's Fig. 4)."""
    labels = labels_by(run_twin("fig4-small", tmp_path), "fluid.capillary_number")
    top, bottom = labels[max(labels)], labels[min(labels)]
    assert set(top) == {"VF"}, top
    assert "CF" in bottom and "VF" not in bottom, bottom


@pytest.mark.paper
def test_fig2_small_viscous_at_high_ca_capillary_at_low_ca_and_low_disorder(tmp_path):
    """n = 100: VF everywhere at Ca = 0.1; CF at Ca = 3e-4 for λ <= 0.5 (paper's Fig. 2).
    (At λ >= 0.7 porenet's boundary departs from the theory: docs/reproduction.md.)"""
    labels = labels_by(
        run_twin("fig2-small", tmp_path), "lattice.disorder", "fluid.capillary_number"
    )
    cas = sorted({ca for _, ca in labels})
    for (lam, ca), regimes in labels.items():
        if ca == cas[-1]:
            assert regimes == ["VF"], (lam, ca, regimes)
        if ca == cas[0] and lam <= 0.5:
            assert regimes == ["CF"], (lam, ca, regimes)
