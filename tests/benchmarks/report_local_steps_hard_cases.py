"""Report: the hard cases of local time steps, with their counters (not a test).

    python tests/benchmarks/report_local_steps_hard_cases.py

Runs the local-steps hard cases of ``tests/verification/test_viscous_integrators.py``
(``INTEGRATORS["rkc-local"].hard_cases``) as that file does (macro steps wherever a window
fits) and prints the table of docs/stability.md: macro steps (cut), fine steps and the volume
balance of each.
"""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "verification"))

from test_viscous_integrators import INTEGRATORS

from porenet.kinds.viscous.local_steps import LocalSteps
from porenet.testing.runs import simulate


def main() -> None:
    LocalSteps.gain = float("inf")  # as the test file's fixture: macro steps wherever they fit
    print("| case | drained | macro steps (cut) | fine steps | volume balance |")
    print("|---|---|---|---|---|")
    for name, (scene, _) in INTEGRATORS["rkc-local"].hard_cases.items():
        _, result = simulate(scene)
        s = result.summary
        print(f"| {name} | {s['n_drained']} | {s['macro_steps']} ({s['macro_cuts']}) | "
              f"{s['time_steps']} | {s['volume_balance_error']:.1e} |")  # fmt: skip


if __name__ == "__main__":
    main()
