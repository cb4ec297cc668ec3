"""Benchmark: the invasion-percolation kernels stage by stage (not a test; no assertions).

    python tests/benchmarks/bench_kernels.py                      # n = 400 and 2000
    python tests/benchmarks/bench_kernels.py --sizes 400 --repeat 21
    python tests/benchmarks/bench_kernels.py --baseline 35c6db6   # also time older kernels

Full invasion (``stop_at_outlet=False``, ``max_steps=n_pores``) of an n x n square lattice from
the centre pore, outlet = the outer ring, apertures uniform in [0.7a, 1.3a] (seed 0), with and
without trapping. Every number is a median over ``--repeat`` runs in this process after a
warm-up run (numba compilation or cache load excluded). The stages are the pieces that
``porenet.kinds.invasion.kernels.ip.invasion_sequence`` runs (with the padded adjacency layout it
picks for the square lattice), timed separately on the same inputs; "total" is ``invasion_sequence``
itself, timed in a separate round (so the stages need not add up to it exactly: the small rest is
argument checks, allocations and copies).

With ``--baseline REV`` the kernels of git revision REV (``porenet/kernels`` only) are copied
to a cache directory as package ``porenet_baseline`` and timed in the same process, with the
same inputs, interleaved with the current kernels, so that the comparison sees the same machine
load. Their results are checked to be identical. Its stages are those of the kernels before
the rank-pair layout (``throat_ranks``, the ``rank[throats]`` gather, ``invade``,
``trapped_steps``), e.g. revision 35c6db6.
"""

from __future__ import annotations

import argparse
import importlib
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np

from porenet.kernels.graph import csr_adjacency, max_degree, rank_pairs
from porenet.kinds.invasion.kernels import ip
from porenet.kinds.square.model import canonical_throats

REPO = Path(__file__).resolve().parents[2]


def problem(n: int):
    throat_pores = canonical_throats(n)
    adjacency = csr_adjacency(throat_pores, n * n)
    apertures = np.random.default_rng(0).uniform(0.7, 1.3, len(throat_pores))
    entry = ip.entry_pressures(apertures)
    inlets = np.array([(n // 2) * n + n // 2], dtype=np.int64)
    outlet = np.zeros((n, n), dtype=bool)
    outlet[0, :] = outlet[-1, :] = outlet[:, 0] = outlet[:, -1] = True
    return adjacency, entry, inlets, outlet.ravel()


def current_stages(adjacency, entry, inlets, outlet, trapping: bool) -> dict[str, Callable]:
    """The stages of ``ip.invasion_sequence`` as separate callables (same order, same data)."""
    indptr, neighbours, throats = adjacency
    n, m = indptr.shape[0] - 1, len(entry)
    width = max_degree(indptr)
    by_rank, rank, keys, pairs, order, via, key, target, state, stack, trapped = ip._arena(
        (m, np.int32),
        (m, np.int32),
        (m, np.uint64),
        (2 * width * n, np.int32),
        (n, np.int32),
        (n, np.int32),
        (n, np.int32),
        (m, np.int32),
        (n, np.uint8),
        (n, np.int32),
        (n, np.bool_),
    )

    graph = ip.RankedGraph(indptr, width, pairs, m)
    stops = ip.InvasionStops(False, n, trapping)
    work = ip.InvasionWork(order, via, key, target)

    def invade():
        return ip.invade_pairs(graph, inlets, outlet, stops, work)

    stages = {
        "ranks (sort)": lambda: ip._ranks_into(entry, by_rank, rank, keys),
        "pairs (gather)": lambda: rank_pairs(indptr, neighbours, throats, rank, width, pairs),
        "invade": invade,
    }
    for fn in stages.values():
        k = fn()
    if trapping:
        o, v = order.copy(), via.copy()

        def drop():
            o[:], v[:] = order, via  # (~0.1 ms at n = 400)
            adjacency = ip.Adjacency(indptr, width, pairs, 2)
            scratch = ip.TrapWork(state, stack, trapped)
            return ip.drop_trapped(adjacency, o, v, k, outlet, scratch)

        stages["drop trapped"] = drop
    throat = np.empty(k, dtype=np.int64)
    stages["via to throats"] = lambda: ip._rank_to_throat(via[:k], by_rank, throat)
    return stages


def baseline_stages(base, adjacency, entry, inlets, outlet, trapping: bool) -> dict[str, Callable]:
    """Stages of the kernels before this optimisation (sort, gather, invade, trapping, via)."""
    indptr, neighbours, throats = adjacency
    n = indptr.shape[0] - 1
    _, rank = base.throat_ranks(entry)
    neighbour_rank = rank.astype(np.int32)[throats]
    stages = {
        "ranks (sort)": lambda: base.throat_ranks(entry),
        "pairs (gather)": lambda: rank.astype(np.int32)[throats],
        "invade": lambda: base.invade(indptr, neighbours, neighbour_rank, inlets, outlet, False, n),
    }
    order, _ = base.invade(indptr, neighbours, neighbour_rank, inlets, outlet, False, n)
    if trapping:
        stages["drop trapped"] = lambda: base.trapped_steps(
            indptr, neighbours, order, outlet, len(inlets)
        )
    return stages


def load_baseline(rev: str):
    """git ``rev``'s ``porenet/kernels`` as package ``porenet_baseline.kernels``."""
    sha = subprocess.run(
        ["git", "-C", str(REPO), "rev-parse", rev], check=True, capture_output=True, text=True
    ).stdout.strip()
    root = Path(tempfile.gettempdir()) / f"porenet_bench_baseline_{sha[:12]}"
    pkg = root / "porenet_baseline"
    if not (pkg / "kernels").exists():
        (pkg / "kernels").mkdir(parents=True, exist_ok=True)
        (pkg / "__init__.py").write_text("")
        files = subprocess.run(
            ["git", "-C", str(REPO), "ls-tree", "-r", "--name-only", sha, "porenet/kernels/"],
            check=True,
            capture_output=True,
            text=True,
        ).stdout.split()
        for path in files:
            if not path.endswith(".py"):
                continue
            text = subprocess.run(
                ["git", "-C", str(REPO), "show", f"{sha}:{path}"],
                check=True,
                capture_output=True,
                text=True,
            ).stdout
            text = text.replace("from porenet.kernels", "from porenet_baseline.kernels")
            target = pkg / Path(path).relative_to("porenet")
            target.parent.mkdir(parents=True, exist_ok=True)
            target.write_text(text)
    sys.path.insert(0, str(root))
    # the kernels moved into subpackages by model (porenet/kinds/invasion/kernels/ip.py) in 2026-12
    for name in ("porenet_baseline.kernels.invasion.ip", "porenet_baseline.kernels.ip"):
        try:
            return importlib.import_module(name), sha[:12]
        except ModuleNotFoundError:
            continue
    raise ModuleNotFoundError(f"no invasion kernels in revision {rev}")


def interleaved_medians(fns: dict, repeat: int, block: int = 1) -> dict:
    """Median wall time (ms) of each callable over ``repeat`` runs after a warm-up call each:
    runs of ``block`` consecutive calls of each callable, taking turns, so that all see the
    same machine load."""
    for fn in fns.values():
        fn()
    times: dict = {name: [] for name in fns}
    for _ in range(-(-repeat // block)):
        for name, fn in fns.items():
            for _ in range(block):
                t0 = time.perf_counter()
                fn()
                times[name].append(time.perf_counter() - t0)
    return {name: 1e3 * float(np.median(t)) for name, t in times.items()}


def run_case(n: int, trapping: bool, repeat: int, base, base_name: str) -> None:
    adjacency, entry, inlets, outlet = problem(n)

    def total(module=ip):
        return module.invasion_sequence(
            adjacency,
            entry,
            inlets,
            outlet,
            trapping=trapping,
            stop_at_outlet=False,
            max_steps=n * n,
        )

    stages: dict = {}
    for name, fn in current_stages(adjacency, entry, inlets, outlet, trapping).items():
        stages["now", name] = fn
    totals: dict = {("now", "total"): total}
    head = f"n={n} ({n * n} pores) trapping={trapping}: medians of {repeat} (ms)"
    if base is not None:
        for name, fn in baseline_stages(base, adjacency, entry, inlets, outlet, trapping).items():
            stages["base", name] = fn
        totals["base", "total"] = lambda: total(base)
        same = all(np.array_equal(x, y) for x, y in zip(total(), total(base), strict=True))
        head += f"; same result as {base_name}: {same}"
    # The totals are timed on their own, in blocks of consecutive calls: interleaving calls of
    # different code changes how the allocator reuses memory between calls (and so the page
    # faults), which is not what repeated calls in an application see.
    medians = interleaved_medians(totals, repeat, block=max(1, min(5, repeat // 3)))
    medians.update(interleaved_medians(stages, repeat))
    print(head)
    print(f"  {'stage':16s} {'now':>10s}" + (f" {base_name:>14s}" if base is not None else ""))
    names = list(dict.fromkeys([name for _, name in stages] + ["total"]))
    for name in names:
        row = f"  {name:16s}"
        for who in ("now", "base") if base is not None else ("now",):
            value = medians.get((who, name))
            width = 10 if who == "now" else 14
            row += f" {value:{width}.2f}" if value is not None else f" {'-':>{width}s}"
        print(row, flush=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[400, 2000])
    parser.add_argument("--repeat", type=int, default=11, help="repeats for n < 1000")
    parser.add_argument("--repeat-large", type=int, default=3, help="repeats for n >= 1000")
    parser.add_argument("--baseline", metavar="REV", help="also time git REV's kernels")
    args = parser.parse_args()
    base, base_name = load_baseline(args.baseline) if args.baseline else (None, "")
    for n in args.sizes:
        for trapping in (False, True):
            repeat = args.repeat if n < 1000 else args.repeat_large
            run_case(n, trapping, repeat, base, base_name)


if __name__ == "__main__":
    main()
