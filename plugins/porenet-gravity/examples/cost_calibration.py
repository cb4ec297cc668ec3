"""Runs that calibrate the cost estimate of ``gravity.invasion-percolation``
(``porenet_gravity.cost``): drained pores at breakthrough and wall time against the lattice's
size, the Bond number and the field's sign.

    python plugins/porenet-gravity/examples/cost_calibration.py            # runs, then the fit
    python plugins/porenet-gravity/examples/cost_calibration.py --fit-only # the fit of the records

Writes ``plugins/porenet-gravity/study/cost_runs.jsonl`` (one JSON record a run; the first line
holds the provenance: porenet's version, the git commit, the machine, the date) and prints
the fitted constants with the worst ratio of estimate to measurement; ``porenet_gravity.cost``
holds the constants of the committed records. Each run is made twice and the faster wall time
kept (the first pays numba's compilation once per kernel; the second is what the estimate
models: build and run, no imports, no compilation).
"""

from __future__ import annotations

import argparse
import json
import platform
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
RECORDS = HERE.parent / "study" / "cost_runs.jsonl"
sys.path.insert(0, str(HERE.parent / "src"))

SIZES = (50, 100, 200, 400, 800)
BONDS = (0.0, 1e-4, 1e-3, 1e-2, 1e-1)
SIGNS = ("stabilising", "destabilising")
SEEDS = (1, 2, 3)


def scene(n: int, bond: float, gravity: str, seed: int) -> dict:
    """The calibration scene: the plugin's example geometry (left edge to the right one, at
    breakthrough) on an ``n x n`` square lattice."""
    return {
        "seed": seed,
        "lattice": {"kind": "square", "n": n, "disorder": 0.3, "pore_size": 5e-4},
        "injection": {"at": "left-edge"},
        "fluid": {"kind": "gravity.invasion-percolation", "bond_number": bond, "gravity": gravity},
        "classifier": {"kind": "none"},
    }


def provenance() -> dict:
    """What made the records: code version, machine, date."""
    import porenet

    try:
        commit = subprocess.run(
            ["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True, cwd=HERE
        ).stdout.strip()
    except OSError:
        commit = ""
    return {
        "provenance": {
            "porenet": porenet.__version__,
            "commit": commit,
            "machine": f"{platform.node()} {platform.machine()} {platform.processor()}",
            "python": platform.python_version(),
            "date": time.strftime("%Y-%m-%d %H:%M:%S %Z"),
        }
    }


def run_all(path: Path) -> None:
    import porenet_gravity.plugin

    from porenet.simulation import Simulation
    from porenet.testing.contract import plugin_registry

    # this source tree's plugin, whether or not a porenet-gravity is installed
    registry = plugin_registry({"gravity": porenet_gravity.plugin})
    path.parent.mkdir(parents=True, exist_ok=True)
    with path.open("w") as out:
        out.write(json.dumps(provenance()) + "\n")
        for n in SIZES:
            for bond in BONDS:
                for gravity in SIGNS if bond > 0 else SIGNS[:1]:
                    for seed in SEEDS:
                        walls = []
                        for _ in range(2):
                            sim = Simulation.from_scene(
                                scene(n, bond, gravity, seed), registry=registry
                            )
                            result = sim.run()
                            walls.append(result.data.summary["wall_time_s"])
                        record = {
                            "n": n, "bond_number": bond, "gravity": gravity, "seed": seed,
                            "drained": int(result.data.summary["n_drained"]),
                            "wall_s": min(walls),
                        }  # fmt: skip
                        out.write(json.dumps(record) + "\n")
                        out.flush()
                        print(record, flush=True)


def read(path: Path) -> list[dict]:
    lines = [json.loads(line) for line in path.read_text().splitlines() if line.strip()]
    return [r for r in lines if "provenance" not in r]


def fit(records: list[dict]) -> None:
    """The constants of ``porenet_gravity.cost`` from the records, and how well they do."""
    from porenet_gravity import cost

    worst_drained, worst_wall = 1.0, 1.0
    for r in records:
        est = cost.drained_fraction(r["n"], r["bond_number"], r["gravity"]) * r["n"] ** 2
        worst_drained = max(worst_drained, est / r["drained"], r["drained"] / est)
        if r["n"] >= 200:  # below, fixed costs of a few ms dominate and vary with the machine
            wall = cost.wall_seconds(r["n"] ** 2)
            worst_wall = max(worst_wall, wall / r["wall_s"], r["wall_s"] / wall)
    print(f"drained: every run within {worst_drained:.2f}x of the estimate")
    print(f"wall time (n >= 200): every run within {worst_wall:.2f}x of the estimate")
    by_point: dict[tuple, list[dict]] = {}
    for r in records:
        by_point.setdefault((r["n"], r["bond_number"], r["gravity"]), []).append(r)
    print(f"{'n':>5} {'Bo':>8} {'gravity':>13} {'measured':>9} {'estimate':>9} {'wall s':>8}")
    for (n, bond, gravity), rs in sorted(by_point.items()):
        measured = sum(r["drained"] for r in rs) / len(rs) / n**2
        wall = min(r["wall_s"] for r in rs)
        est = cost.drained_fraction(n, bond, gravity)
        print(f"{n:5d} {bond:8.0e} {gravity:>13} {measured:9.3f} {est:9.3f} {wall:8.3f}")


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--fit-only", action="store_true", help="fit the committed records")
    parser.add_argument("--records", type=Path, default=RECORDS)
    args = parser.parse_args()
    if not args.fit_only:
        run_all(args.records)
    fit(read(args.records))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
