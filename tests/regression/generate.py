"""Store the outcomes of the regression scenes, with their provenance.

    python tests/regression/generate.py            # every scene
    python tests/regression/generate.py --only viscous-rkc

Run it only to record a deliberate change of results, and say why in the commit.
"""

from __future__ import annotations

import argparse
import json
import platform
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from outcome import outcome  # noqa: E402
from scenes import SCENES  # noqa: E402

OUT = HERE / "outcomes"


def main() -> None:
    import numba

    import porenet
    from porenet.simulation import Simulation

    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--only", nargs="+", choices=list(SCENES), default=list(SCENES))
    args = parser.parse_args()
    OUT.mkdir(exist_ok=True)
    commit = subprocess.run(["git", "rev-parse", "HEAD"], capture_output=True, text=True,
                            cwd=HERE, check=False).stdout.strip()  # fmt: skip
    dirty = subprocess.run(["git", "status", "--porcelain", "porenet"], capture_output=True,
                           text=True, cwd=HERE.parents[1], check=False).stdout.strip()  # fmt: skip
    provenance_file = OUT / "provenance.json"
    provenance = json.loads(provenance_file.read_text()) if provenance_file.exists() else {}
    for name in args.only:
        data = Simulation.from_scene(SCENES[name]).run().data
        np.savez_compressed(OUT / f"{name}.npz", **outcome(data))
        provenance[name] = {
            "commit": commit + (" (with uncommitted changes to porenet/)" if dirty else ""),
            "date": time.strftime("%Y-%m-%d"),
            "porenet": porenet.__version__,
            "numpy": np.__version__,
            "numba": numba.__version__,
            "python": platform.python_version(),
            "machine": platform.machine(),
            "command": "python tests/regression/generate.py",
        }
        print(f"{name}: {data.summary['n_drained']} drained, stored")
    provenance_file.write_text(json.dumps(provenance, indent=1, sort_keys=True) + "\n")


if __name__ == "__main__":
    main()
