"""Benchmark: the frictional solid's multigrid on one component, m x m grid (not a test).

    python tests/benchmarks/bench_multigrid.py               # m = 399 (the paper's lattice)
    python tests/benchmarks/bench_multigrid.py --m 199 --repeat 9
    python tests/benchmarks/bench_multigrid.py --against d23af9b   # this V-cycle vs that one's

Operators like those of ``u_x`` in an update: weights ~K across columns (normal stiffness of
x-springs, +-50 % disorder) and ~r_t K across rows, with a cross of open contacts (weights 1e-6
of the others) of half-length 150 at the centre; a right-hand side of 40 point forces. For
each stiffness ratio, the hierarchy's build time, then the conjugate gradient solve from zero
to round-off and to a deformation tolerance of 1e-3 a, with the smoother relaxing the lines of
the strong direction only (the default, :func:`porenet.kinds.mindlin.kernels.multigrid.
smoothing_lines`) and both directions (rows, then columns): iterations and median wall time
(docs/model.md, "Solver", quotes it).

``--against REV``: the multigrid of git revision ``REV`` (its ``multigrid.py`` and
``multigrid_smoothing.py``, loaded from ``git show`` beside today's) against today's, on the
same operators (rows relaxed at K_t / K_n = 0.1 and 0.5, columns at 0.5), solves to
round-off taken in turn: iterations, median time per iteration and the largest difference of
the solutions.
"""

from __future__ import annotations

import argparse
import importlib.util
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from porenet.kinds.mindlin.kernels import multigrid as mg


def operator(m: int, ratio: float, crack: int, seed: int = 1) -> mg.Operator:
    rng = np.random.default_rng(seed)
    wc = 2.0 * (1 + 0.5 * rng.random((m, m + 1)))
    wr = ratio * 2.0 * (1 + 0.5 * rng.random((m + 1, m)))
    c0 = m // 2
    lo, hi = max(c0 - crack, 0), min(c0 + crack, m)
    wc[c0, lo:hi] = 2e-6
    wr[lo:hi, c0] = 2e-6 * ratio
    return mg.Operator(wc, wr, np.zeros((m, m)))


def timed_solve(op, hierarchy, rhs, tolerance, repeat):
    work = mg.workspace(hierarchy)
    times, its = [], 0
    for _ in range(repeat):
        x = np.zeros_like(rhs)
        t0 = time.perf_counter()
        its = mg.solve(op, hierarchy, work, rhs, x, tolerance, 1e-13 * np.abs(rhs).max(), 500)
        times.append(time.perf_counter() - t0)
    return its, statistics.median(times)


def load_revision(rev: str):
    """The multigrid module of git revision ``rev``, importing that revision's smoother."""
    root = Path(__file__).resolve().parents[2]
    tmp = Path(tempfile.mkdtemp(prefix="porenet-mg-"))
    package = "porenet.kinds.hertz.kernels."
    for name in ("multigrid_smoothing", "multigrid"):
        source = subprocess.run(
            ["git", "show", f"{rev}:porenet/kinds/hertz/kernels/{name}.py"],
            cwd=root,
            check=True,
            capture_output=True,
            text=True,
        ).stdout
        source = source.replace(package + "multigrid_smoothing", "revision_multigrid_smoothing")
        (tmp / f"revision_{name}.py").write_text(source)
    sys.path.insert(0, str(tmp))
    spec = importlib.util.spec_from_file_location("revision_multigrid",
                                                  tmp / "revision_multigrid.py")  # fmt: skip
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def against(rev: str, m: int, repeat: int) -> None:
    old = load_revision(rev)
    rng = np.random.default_rng(3)
    print(
        f"| operator | lines | iterations ({rev}, now) | ms per iteration ({rev}) | "
        "ms per iteration (now) | ratio | largest difference / largest value |"
    )
    print("|---|---|---|---|---|---|---|")
    for ratio, flip in ((0.1, False), (0.5, False), (0.5, True)):
        op = operator(m, ratio, 150)
        if flip:  # the strong direction along columns, as u_y's
            op = mg.Operator(op.across_rows.T.copy(), op.across_columns.T.copy(), op.diagonal)
        rhs = np.zeros(m * m)
        rhs[rng.integers(0, m * m, 40)] = rng.normal(size=40)
        force = 1e-13 * np.abs(rhs).max()
        cases = []
        for module in (old, mg):
            h = module.build(op)
            cases.append((module, h, module.workspace(h), []))
        its, xs = [], []
        for _ in range(repeat + 1):  # the first compiles: not counted
            for module, h, work, times in cases:
                x = np.zeros_like(rhs)
                t0 = time.perf_counter()
                n = module.solve(op, h, work, rhs, x, 0.0, force, 500)
                times.append((time.perf_counter() - t0) / n)
                its.append(n)
                xs.append(x)
        t_old, t_new = (statistics.median(c[3][1:]) for c in cases)
        diff = np.abs(xs[-1] - xs[-2]).max() / np.abs(xs[-2]).max()
        print(
            f"| K_t/K_n = {ratio:g}{', transposed' if flip else ''} | "
            f"{'rows' if mg.smoothing_lines(op) == 1 else 'columns'} | {its[-2]}, {its[-1]} | "
            f"{1e3 * t_old:.2f} | {1e3 * t_new:.2f} | {t_new / t_old:.2f} | {diff:.1e} |"
        )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--m", type=int, default=399)
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument(
        "--against",
        default=None,
        metavar="REV",
        help="compare with the multigrid of this git revision",
    )
    args = parser.parse_args()
    m = args.m
    if args.against:
        against(args.against, m, args.repeat)
        return
    warm = operator(15, 0.5, 3)
    timed_solve(warm, mg.build(warm), np.ones(15 * 15), 0.0, 1)  # compile
    print("| K_t / K_n | build (ms) | lines | to round-off: iterations, ms | to 1e-3 a: "
          "iterations, ms |")  # fmt: skip
    print("|---|---|---|---|---|")
    for ratio in (1e-3, 0.1, 0.5, 1.0):
        op = operator(m, ratio, 150)
        rhs = np.zeros(m * m)
        rhs[np.random.default_rng(3).integers(0, m * m, 40)] = 1.0
        t0 = time.perf_counter()
        hierarchy = mg.build(op)
        build = time.perf_counter() - t0
        for label, h in (("strong", hierarchy), ("both", hierarchy._replace(sweeps=3))):
            exact = timed_solve(op, h, rhs, 0.0, args.repeat)
            loose = timed_solve(op, h, rhs, 1e-3, args.repeat)
            print(f"| {ratio:g} | {1e3 * build:.0f} | {label} | {exact[0]}, {1e3 * exact[1]:.0f} | "
                  f"{loose[0]}, {1e3 * loose[1]:.0f} |")  # fmt: skip


if __name__ == "__main__":
    main()
