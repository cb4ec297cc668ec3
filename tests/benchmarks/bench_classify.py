"""Benchmark: the pattern analysis at the end of a run (not a test).

    python tests/benchmarks/bench_classify.py --n 400 --repeat 9

Times ``porenet.analysis.classify.classify_run`` with the default ``rules`` classifier on an
invasion-percolation pattern at breakthrough (trapping, λ = 0.5, seed 0): features, D_f by
mass-radius and by box counting. Prints the median.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

import porenet
from porenet.analysis.classify import classify_run
from porenet.kinds.rules.model import RulesClassifier


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=400)
    parser.add_argument("--repeat", type=int, default=9)
    args = parser.parse_args()
    scene = {
        "lattice": {"n": args.n, "disorder": 0.5},
        "fluid": {"trapping": True},
        "classifier": {"kind": "none"},
    }
    result = porenet.run(scene)
    classifier = RulesClassifier()
    times = []
    for _ in range(args.repeat):
        t0 = time.perf_counter()
        classify_run(result.data, classifier, "rules")
        times.append(time.perf_counter() - t0)
    print(
        f"n = {args.n}: classify_run (rules) median {1e3 * np.median(times):.1f} ms over "
        f"{args.repeat} ({result.summary['n_drained']} drained pores)"
    )


if __name__ == "__main__":
    main()
