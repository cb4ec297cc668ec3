"""Which regression scenes give their stored outcome to the bit (not only to round-off).

    python tests/regression/exact.py            # every scene
    python tests/regression/exact.py --only viscous-rkc viscous-implicit

For a change that must not alter a single bit (a helper taking over code written in several
places), run it before and after: a scene that was bit-equal before must stay so. Not a test
(the suite's test compares to round-off, which survives harmless reordering of sums).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from outcome import differences, outcome  # noqa: E402
from scenes import SCENES  # noqa: E402


def main() -> None:
    from porenet.simulation import Simulation

    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--only", nargs="+", choices=list(SCENES), default=list(SCENES))
    args = parser.parse_args()
    equal = 0
    for name in args.only:
        with np.load(HERE / "outcomes" / f"{name}.npz") as stored:
            expected = dict(stored)
        problems = differences(expected, outcome(Simulation.from_scene(SCENES[name]).run().data),
                               exact=True)  # fmt: skip
        equal += not problems
        print(f"{name}: {'to the bit' if not problems else '; '.join(problems[:3])}", flush=True)
    print(f"{equal} of {len(args.only)} scenes equal to the bit")


if __name__ == "__main__":
    main()
