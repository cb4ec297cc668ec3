"""How well the classifiers label patterns whose regime is not in doubt.

    python examples/scripts/classifier_calibration.py --n 100 --seeds 10 \
        --table docs/classification-table.md

Runs seed ensembles of scenes deep inside each regime of the paper's phase diagrams (labels by
docs/model.md section 6, far from the lines Ca* = 1 and N_f = 1), measures the pattern features the
rule-based classifier uses, and prints, per scene, their means and the labels each classifier
gives. The thresholds of ``rules`` (porenet/kinds/rules/model.py) were read off this
table; docs/classification.md quotes it.
"""

from __future__ import annotations

import argparse
from collections import Counter
from pathlib import Path

import numpy as np

import porenet
from porenet.analysis.classify import classify_run
from porenet.analysis.features import pattern_features
from porenet.analysis.numbers import capillary_number_at
from porenet.kinds.rules.model import RulesClassifier
from porenet.kinds.theory.model import TheoryClassifier

FEATURES = (
    "fractal_dimension",
    "finger_width_mean",
    "thin_run_fraction",
    "longest_thin_run",
    "trapped_fraction",
    "drained_fraction",
)


def scenes(n: int) -> dict[str, tuple[str, dict]]:
    """Name -> (expected regime, scene without seed)."""

    def viscous(ca_star: float, lam: float) -> dict:
        return {"kind": "viscous", "capillary_number": capillary_number_at(ca_star, n, lam)}

    lattice = {"n": n, "disorder": 0.1}
    return {
        "IP, trapping (Ca* -> 0)": ("CF", {"lattice": lattice, "fluid": {"trapping": True}}),
        "viscous, λ = 0.5, Ca* = 0.05": (
            "CF",
            {"lattice": {"n": n, "disorder": 0.5}, "fluid": viscous(0.05, 0.5)},
        ),
        "viscous, λ = 0.1, Ca* = 30": ("VF", {"lattice": lattice, "fluid": viscous(30, 0.1)}),
        "viscous, λ = 0.3, Ca* = 30": (
            "VF",
            {"lattice": {"n": n, "disorder": 0.3}, "fluid": viscous(30, 0.3)},
        ),
        "viscous, Ca* = 10, hertz N_f = 10": (
            "FR",
            {
                "lattice": lattice,
                "fluid": viscous(10, 0.1),
                "solid": {"kind": "hertz", "fracturing_number": 10},
            },
        ),
        "IP, hertz N_f = 10": (
            "FR",
            {"lattice": lattice, "fluid": {}, "solid": {"kind": "hertz", "fracturing_number": 10}},
        ),
        # on the theoretical lines: the expected label is the intermediate one, but the
        # crossover is gradual, so these rows are reported, not scored
        "viscous, λ = 0.3, Ca* = 1 (line)": (
            "(CF/VF)",
            {"lattice": {"n": n, "disorder": 0.3}, "fluid": viscous(1, 0.3)},
        ),
        "viscous, Ca* = 10, hertz N_f = 1 (line)": (
            "(FR/VF)",
            {
                "lattice": lattice,
                "fluid": viscous(10, 0.1),
                "solid": {"kind": "hertz", "fracturing_number": 1},
            },
        ),
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=100, help="pores per side")
    parser.add_argument("--seeds", type=int, default=10, help="seeds per scene")
    parser.add_argument("--table", type=Path, help="also write the table (markdown) here")
    args = parser.parse_args()
    head = ["scene", "expected", *FEATURES, "rules", "theory"]
    lines = [
        f"Classifier calibration, n = {args.n}, {args.seeds} seeds per scene "
        f"(`python examples/scripts/classifier_calibration.py --n {args.n} "
        f"--seeds {args.seeds}`); features are means ± standard deviations over seeds, "
        "labels are counts. Expected labels in parentheses (scenes on a theoretical line) "
        "are not scored.",
        "",
        "| " + " | ".join(head) + " |",
        "|" + "---|" * len(head),
    ]
    classifiers = {"rules": RulesClassifier(), "theory": TheoryClassifier()}
    agree = {kind: 0 for kind in classifiers}
    total = 0
    for name, (expected, base) in scenes(args.n).items():
        rows, labels = [], {"rules": Counter(), "theory": Counter()}
        for seed in range(args.seeds):
            scene = dict(base, seed=seed)
            data = porenet.run(scene | {"classifier": {"kind": "none"}}).data
            features = pattern_features(data)
            for kind, classifier in classifiers.items():
                verdict = classify_run(data, classifier, kind)
                labels[kind][verdict["regime"]] += 1
            features["fractal_dimension"] = verdict["fractal_dimension"]
            rows.append(features)
        if not expected.startswith("("):
            for kind in agree:
                agree[kind] += labels[kind][expected]
            total += args.seeds
        cells = [name, expected]
        for key in FEATURES:
            v = np.array([r[key] for r in rows], dtype=float)
            cells.append(f"{np.nanmean(v):.3f} ± {np.nanstd(v):.3f}")
        for kind in ("rules", "theory"):
            cells.append(", ".join(f"{k} {c}" for k, c in labels[kind].most_common()))
        lines.append("| " + " | ".join(cells) + " |")
        print(lines[-1], flush=True)
    lines += [
        "",
        "Agreement with the expected label, scenes inside a regime: "
        f"rules {agree['rules']}/{total}, "
        f"theory {agree['theory']}/{total}.",
    ]
    print(lines[-1])
    if args.table:
        args.table.write_text("\n".join(lines) + "\n")
        print(f"table: {args.table}")


if __name__ == "__main__":
    main()
