"""Benchmark: the frictional solid (kind hertz-mindlin) at the paper's size (not a test).

    python tests/benchmarks/bench_frictional.py updates            # one update, n = 400
    python tests/benchmarks/bench_frictional.py run                # Fig. 5 at N_f = 10
    python tests/benchmarks/bench_frictional.py run --n 200 --set solid.friction=0.3
    python tests/benchmarks/bench_frictional.py run --threads 1 2 --loads 0 1
    python tests/benchmarks/bench_frictional.py tolerance --values 1e-3 1e-2 --max-drained 150
    python tests/benchmarks/bench_frictional.py tolerance --set solid.friction=0.3 \
        --variants solid.slip_tolerance=0,solid.solver_tolerance=1e-6 defaults
    python tests/benchmarks/bench_frictional.py profile --max-drained 60
    python tests/benchmarks/bench_frictional.py profile --set solid.friction=0.3
    python tests/benchmarks/bench_frictional.py sweep-cost    # Fig. 3 at n = 400 with it
    python tests/benchmarks/bench_frictional.py sparse-cost --n 50 100 200 400
    python tests/benchmarks/bench_frictional.py series RUN.h5 --windows 6
    python tests/benchmarks/bench_frictional.py compare REFERENCE.h5 RUN.h5
    python tests/benchmarks/bench_frictional.py anatomy --set lattice.n=200 --max-drained 40

``updates``: builds the 400 x 400 lattice (lambda = 0.1, N_f = 1, K_t / K_n = 0.5) and times
``HertzMindlinSolid.update`` from the prestressed state, as ``bench_mechanics.py`` does for
the Hertzian solid: under the pressure field of a drained disc of radius 0.2 L (the invader
at 2 gamma/a; the worst case), then one more pore drained at its edge (a typical update).
Each repeat starts from a fresh solver (its multigrid hierarchies are built in the first
update: "builds").

``run``: ``examples/scenes/fig5-mindlin.toml`` (Fig. 5's scene at N_f = 10 with the frictional
solid) to breakthrough, each run a new process (warm kernel cache), optionally at several
thread counts and beside busy processes (``python -c "while True: pass"``, started and stopped
here). Prints the wall time, the mechanical updates and the time the solid spent in them
(``mechanics_time_s``), so the amortised cost of an update.

``tolerance``: the same scene capped at ``--max-drained`` pores, once per solver tolerance,
all at the same time, each on one thread (two values fill the two cores: side by side, under
the same conditions). Prints each run's cost and how far it is from the first value's run:
the drained order, the open contacts, the largest differences of displacement and aperture
(in a) at the end (docs/accuracy.md, "Frictional solid"). ``--variants`` compares any
settings instead (each ``defaults`` or ``KEY=VALUE,KEY=VALUE``, the first the reference), and
``--set`` applies to every run (e.g. ``solid.friction=0.3``: "With sliding" there);
``--keep DIR`` keeps the run files (``run-0.h5``, ... in the variants' order).

``profile``: the scene capped at ``--max-drained`` pores in this process on one thread under
cProfile: each kernel's share of the time spent in the solid's updates (``tottime`` over
``mechanics_time_s``; docs/performance.md, "Frictional solid").

``sparse-cost``: one factorisation and one solve of the stiffness matrix with free rotations
(``solid.rotation = "free"``, which only the sparse direct solver handles) at the first
update of the scene, at each ``--n``: what a run with free rotations costs at the paper's
size (docs/accuracy.md, "With sliding").

``series``: where in a run (any run file of a hertz-mindlin solid) the solver's work went:
its V-cycles, contacts sliding, drained pores and open contacts in stretches of equal numbers
of updates (docs/performance.md, "Frictional solid").

``compare``: the ``tolerance`` table of run files made apart (the first the reference), for
runs too long to make side by side in one sitting: for example a reference run by ``porenet
run ... --checkpoint-every 10m`` over several sessions against a kept ``--keep`` run.

``anatomy``: the solver's work of the scene capped at ``--max-drained`` pores, without and
with sliding (``--variants``), split into linear solves an update (the contact iteration's)
and V-cycles a solve, once with the multigrid hierarchies kept across solves (the default)
and once rebuilt before every solve (docs/performance.md, "Frictional solid").

``sweep-cost``: the cost model's estimate (``porenet.core.cost.estimate_cost``) summed over
the points of ``examples/sweeps/fig3.toml`` with this scene as their base (docs/reproduction.md,
"Fig. 3 with frictional contacts").
"""

from __future__ import annotations

import argparse
import itertools
import json
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
SCENE = ROOT / "examples" / "scenes" / "fig5-mindlin.toml"


def updates(n: int, repeat: int) -> None:
    from porenet.simulation import Simulation

    scene = {
        "lattice": {"n": n, "disorder": 0.1},
        "fluid": {"kind": "invasion-percolation"},
        "solid": {"kind": "hertz-mindlin", "fracturing_number": 1.0, "shear_stiffness_ratio": 0.5},
    }
    xy = None
    disc_times, pore_times, notes = [], [], ""
    for _ in range(repeat + 1):  # the first builds and compiles: not counted
        sim = Simulation.from_scene(scene)
        solid, state = sim.solid, sim.state
        solid.setup(state)
        if xy is None:
            xy = sim.lattice.pore_coords
            centre = xy.mean(axis=0)
            pressure = np.where(np.hypot(*(xy - centre).T) < 0.2 * 2 * n, 2.0, 0.0)
            edge = int(np.flatnonzero((pressure == 0) & np.roll(pressure > 0, 1))[0])
            after = pressure.copy()
            after[edge] = 2.0
        t0 = time.perf_counter()
        solid.update(state, pressure)
        t1 = time.perf_counter()
        cycles, builds = solid.solver_iterations, solid.hierarchy_builds
        solid.update(state, after)
        t2 = time.perf_counter()
        disc_times.append(t1 - t0)
        pore_times.append(t2 - t1)
        notes = (f"disc: {cycles} V-cycles, {builds} builds, {solid.n_removed} contacts open; "
                 f"one pore: {solid.solver_iterations - cycles} V-cycles, "
                 f"{solid.hierarchy_builds - builds} builds")  # fmt: skip
    disc_times, pore_times = disc_times[1:], pore_times[1:]
    print(f"n = {n}: update under a new pressure disc: {1e3 * statistics.median(disc_times):.1f} "
          f"ms median of {repeat}; one more drained pore: "
          f"{1e3 * statistics.median(pore_times):.1f} ms ({notes})")  # fmt: skip


def check_overrides(parser: argparse.ArgumentParser, *overrides: list[str]) -> None:
    """Each list of scene overrides (``KEY=VALUE``) gives a valid scene, or the script stops
    here with the scene's message (exit 2) before any run starts."""
    from porenet.config.loading import load_scene
    from porenet.core.errors import ConfigError

    for pairs in overrides:
        try:
            load_scene(SCENE, pairs)
        except ConfigError as exc:
            parser.error(str(exc))


def set_flags(pairs: list[str]) -> list[str]:
    """``porenet run``'s options for scene overrides: ``["--set", "K=V", "--set", ...]``."""
    return [item for kv in pairs for item in ("--set", kv)]


def one_run(args: list[str], threads: str) -> dict:
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "run.h5"
        cmd = [sys.executable, "-m", "porenet", "run", str(SCENE), "-o", str(out), "-q",
               "--threads", threads, *args]  # fmt: skip
        t0 = time.perf_counter()
        subprocess.run(cmd, check=True)
        wall = time.perf_counter() - t0
        import h5py

        with h5py.File(out) as f:
            attrs = f["summary"].attrs
            summary = {k: (v.item() if hasattr(v, "item") else v) for k, v in attrs.items()}
    summary["process_wall_s"] = wall
    return summary


def runs(args: argparse.Namespace) -> None:
    extra = set_flags(args.set)
    if args.n:
        extra += ["--set", f"lattice.n={args.n}"]
    rows = []
    for load in args.loads:
        busy = [subprocess.Popen([sys.executable, "-c", "while True: pass"]) for _ in range(load)]
        try:
            for _ in range(args.repeat):
                for threads in args.threads:
                    s = one_run(extra, threads)
                    per = 1e3 * s["mechanics_time_s"] / max(s["mechanical_updates"], 1)
                    rows.append((load, threads, s["process_wall_s"], s["mechanics_time_s"],
                                 s["mechanical_updates"], per, s))  # fmt: skip
                    print(f"busy {load} threads {threads}: wall {s['process_wall_s']:.1f} s, "
                          f"mechanics {s['mechanics_time_s']:.1f} s over "
                          f"{s['mechanical_updates']} updates ({per:.1f} ms each), "
                          f"{s['n_drained']} drained, {s['springs_removed']} open, "
                          f"V-cycles {s['solver_iterations']}, builds {s['multigrid_builds']}, "
                          f"D_f {s.get('fractal_dimension', float('nan')):.3f}",
                          flush=True)  # fmt: skip
        finally:
            for p in busy:
                p.kill()
    print("\n| busy processes | --threads | median wall (s) | median mechanics (s) | updates | "
          "ms per update |")  # fmt: skip
    print("|---|---|---|---|---|---|")
    for load in args.loads:
        for threads in args.threads:
            sel = [r for r in rows if r[0] == load and r[1] == threads]
            print(f"| {load} | {threads} | {statistics.median(r[2] for r in sel):.1f} | "
                  f"{statistics.median(r[3] for r in sel):.1f} | {sel[0][4]} | "
                  f"{statistics.median(r[5] for r in sel):.1f} |")  # fmt: skip
    if args.json:
        Path(args.json).write_text(json.dumps([r[6] for r in rows], indent=1))


def variant_sets(args: argparse.Namespace) -> list[tuple[str, list[str]]]:
    """Each run's label and its ``--set`` options: ``--variants`` (``defaults`` or
    ``KEY=VALUE,KEY=VALUE``) if given, else one run per ``--values`` solver tolerance;
    ValueError for a variant that is neither."""
    if not args.variants:
        return [(str(v), [f"solid.solver_tolerance={v}"]) for v in args.values]
    out = []
    for text in args.variants:
        pairs = [] if text == "defaults" else [kv for kv in text.split(",") if kv]
        if any("=" not in kv for kv in pairs):
            raise ValueError(f"--variants: {text!r} is not 'defaults' or KEY=VALUE,KEY=VALUE")
        out.append((text, pairs))
    return out


def tolerances(args: argparse.Namespace) -> None:
    variants = variant_sets(args)
    with tempfile.TemporaryDirectory() as tmp:
        procs, outs = [], []
        for i, (_, pairs) in enumerate(variants):
            out = Path(tmp) / f"run-{i}.h5"
            cmd = [sys.executable, "-m", "porenet", "run", str(SCENE), "-o", str(out), "-q",
                   "--threads", "1", "--set", f"stop.max_drained={args.max_drained}",
                   *set_flags(args.set), *set_flags(pairs)]  # fmt: skip
            procs.append((subprocess.Popen(cmd), time.perf_counter()))
            outs.append(out)
        walls = [0.0] * len(procs)
        while not all(walls):
            for i, (proc, t0) in enumerate(procs):
                if not walls[i] and proc.poll() is not None:
                    if proc.returncode != 0:
                        for other, _ in procs:  # no orphans left running
                            other.kill()
                        raise SystemExit(f"a run failed: {proc.args}")
                    walls[i] = time.perf_counter() - t0
            time.sleep(0.2)
        if args.keep:  # the run files, for `series` (one per variant, in their order)
            import shutil

            Path(args.keep).mkdir(parents=True, exist_ok=True)
            for out in outs:
                shutil.copy(out, Path(args.keep) / out.name)
        runs = [read_kept(out) for out in outs]
    label = "settings" if args.variants else "solver_tolerance (a)"
    print_rows(label, [name for name, _ in variants], walls, runs)


def read_kept(path: Path) -> dict:
    """What the tolerance table reads of a run file: its summary, drained order, open
    contacts, final displacements and apertures."""
    import h5py

    with h5py.File(path) as f:
        return {
            "summary": dict(f["summary"].attrs),
            "order": f["invasion/order"][()],
            "removed": f["final/removed_springs"][()],
            "displacement": f["final/displacement"][()],
            "apertures": f["final/apertures"][()],
        }


def print_rows(label: str, names: list[str], walls: list[float], runs: list[dict]) -> None:
    """The tolerance table: each run's cost and how far it ends from the first run's."""
    print(f"| {label} | wall (s) | mechanics (s) | updates | ms per update | "
          "V-cycles | builds | frozen | drained | open contacts | same drained order | same "
          "open contacts | largest displacement difference (a) | largest aperture difference "
          "(a) |")  # fmt: skip
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    first = runs[0]
    import tomllib

    a = tomllib.loads(SCENE.read_text())["lattice"]["pore_size"]  # m
    for name, wall, run in zip(names, walls, runs, strict=True):
        s = run["summary"]
        per = 1e3 * s["mechanics_time_s"] / max(int(s["mechanical_updates"]), 1)
        du = np.abs(run["displacement"] - first["displacement"]).max() / a
        dh = np.abs(run["apertures"] - first["apertures"]).max() / a
        print(f"| {name} | {wall:.1f} | {s['mechanics_time_s']:.1f} | "
              f"{s['mechanical_updates']} | {per:.1f} | {s['solver_iterations']} | "
              f"{s['multigrid_builds']} | {s.get('frozen_contacts', 0)} | {len(run['order'])} | "
              f"{int(np.count_nonzero(run['removed']))} | "
              f"{order_column(first['order'], run['order'])} | "
              f"{contacts_column(first['removed'], run['removed'])} | "
              f"{du:.2g} | {dh:.2g} |")  # fmt: skip


def order_column(reference: np.ndarray, order: np.ndarray, most: int = 8) -> str:
    """The table's "same drained order": ``yes``, or ``no`` with the drain positions
    (1-based) where the two orders differ, up to ``most`` of them (else their count), or the
    two lengths where they differ."""
    if len(order) != len(reference):
        return f"no ({len(order)} drained against {len(reference)})"
    where = np.flatnonzero(order != reference) + 1
    if where.size == 0:
        return "yes"
    if where.size > most:
        return f"no ({where.size} positions)"
    return f"no (at {', '.join(str(i) for i in where)})"


def contacts_column(reference: np.ndarray, removed: np.ndarray) -> str:
    """The table's "same open contacts": ``yes``, or ``no`` with how many contacts are open
    in one run and not in the other."""
    differ = int(np.count_nonzero(np.asarray(removed, bool) != np.asarray(reference, bool)))
    return "yes" if differ == 0 else f"no ({differ} differ)"


def compare(files: list[str]) -> None:
    """``compare``: the tolerance table of run files made apart (the first the reference;
    wall time from each file's summary, so a run resumed from checkpoints counts every
    part)."""
    paths = [Path(f) for f in files]
    missing = [str(p) for p in paths if not p.is_file()]
    if missing:
        raise SystemExit(f"compare: no such run file: {', '.join(missing)}")
    runs = []
    for path in paths:
        try:
            runs.append(read_kept(path))
        except (OSError, KeyError) as exc:
            raise SystemExit(f"compare: {path} is not a finished run file of a solid with "
                             f"displacements ({exc})") from None  # fmt: skip
    sizes = {r["displacement"].shape for r in runs}
    if len(sizes) > 1:
        raise SystemExit(f"compare: the run files are of different lattices ({sorted(sizes)})")
    walls = [float(r["summary"]["wall_time_s"]) for r in runs]
    print_rows("run file", [p.name for p in paths], walls, runs)


def anatomy(max_drained: int, sets: list[str], variants: list[str]) -> None:
    """``anatomy``: the solver's work split into solves an update and V-cycles a solve, for
    each variant of the scene (``defaults``, or ``KEY=VALUE,...`` added to ``--set``), once
    with the hierarchies kept (the default) and once rebuilt before every solve
    (``REBUILD_EDGES`` set to -1 for that run: what a preconditioner that always matched the
    operator would save in V-cycles, and cost in builds). The solves are counted by wrapping
    ``GridSolver.solve``. One thread, in this process, one run after another."""
    from porenet.jit.threads import configure_threads
    from porenet.kinds.mindlin import grid_solver
    from porenet.simulation import Simulation

    configure_threads(1)
    Simulation.from_scene(SCENE, ["lattice.n=40", "stop.max_drained=20"]).run()  # load kernels
    solves = [0]
    original_solve, original_edges = grid_solver.GridSolver.solve, grid_solver.REBUILD_EDGES

    def counted(self, *args):  # type: ignore[no-untyped-def]
        solves[0] += 1
        return original_solve(self, *args)

    print("| variant | hierarchies | mechanics (s) | updates | solves | solves an update | "
          "V-cycles (both components) | V-cycles a solve | builds | drained | open "
          "contacts |")  # fmt: skip
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    grid_solver.GridSolver.solve = counted
    try:
        for text in variants:
            for fresh in (False, True):
                grid_solver.REBUILD_EDGES = -1 if fresh else original_edges
                pairs = [] if text == "defaults" else text.split(",")
                solves[0] = 0
                sim = Simulation.from_scene(SCENE, [f"stop.max_drained={max_drained}", *sets,
                                                    *pairs])  # fmt: skip
                s = sim.run().summary
                updates, v = int(s["mechanical_updates"]), int(s["solver_iterations"])
                print(f"| {text} | {'rebuilt every solve' if fresh else 'kept (default)'} | "
                      f"{s['mechanics_time_s']:.1f} | {updates} | {solves[0]} | "
                      f"{solves[0] / max(updates, 1):.2f} | {v} | {v / max(solves[0], 1):.1f} | "
                      f"{s['multigrid_builds']} | {s['n_drained']} | {s['springs_removed']} |",
                      flush=True)  # fmt: skip
    finally:
        grid_solver.GridSolver.solve = original_solve
        grid_solver.REBUILD_EDGES = original_edges


def profile(max_drained: int, top: int, sets: list[str]) -> None:
    import cProfile
    import pstats

    from porenet.jit.threads import configure_threads
    from porenet.simulation import Simulation

    configure_threads(1)
    Simulation.from_scene(SCENE, ["lattice.n=40", "stop.max_drained=20"]).run()  # load kernels
    sim = Simulation.from_scene(SCENE, [f"stop.max_drained={max_drained}", *sets])
    profiler = cProfile.Profile()
    result = profiler.runcall(sim.run)
    summary = result.summary
    mechanics = summary["mechanics_time_s"]
    stats = pstats.Stats(profiler).stats  # (file, line, name) -> (cc, nc, tottime, ...)
    rows = sorted(((v[2], v[1], k) for k, v in stats.items()), reverse=True)[:top]
    print(f"{summary['mechanical_updates']} updates, mechanics {mechanics:.1f} s "
          f"({1e3 * mechanics / max(summary['mechanical_updates'], 1):.1f} ms an update, one "
          f"thread), V-cycles {summary['solver_iterations']}, builds "
          f"{summary['multigrid_builds']}\n")  # fmt: skip
    print("| function | calls | total (s) | share of the mechanics |")
    print("|---|---|---|---|")
    for tottime, calls, (file, _, name) in rows:
        print(
            f"| {Path(file).stem}.{name} | {calls} | {tottime:.2f} | "
            f"{100 * tottime / mechanics:.1f} % |"
        )


def series(run_file: str, windows: int) -> None:
    """Where in a run the solver's work went: the run file's per-update mechanics series
    (``/mechanics``: V-cycles, sliding contacts, drained pores, open contacts) in
    ``windows`` stretches of equal numbers of updates."""
    import h5py

    try:
        with h5py.File(run_file, "r") as f:
            keys = ("solver_iterations", "sliding_contacts", "drained", "removed_springs")
            m = {k: f["mechanics"][k][()] for k in keys}
    except (OSError, KeyError) as exc:
        raise SystemExit(f"series: {run_file}: not a run file with a /mechanics series "
                         f"of a hertz-mindlin solid ({exc})") from None  # fmt: skip
    cycles = m["solver_iterations"]
    n = len(cycles)
    print(f"{run_file}: {n} updates, {int(cycles.sum())} V-cycles (both components)\n")
    print("| updates | drained pores | open contacts | V-cycles | V-cycles an update (mean, "
          "largest) | contacts sliding (fewest, most) |")  # fmt: skip
    print("|---|---|---|---|---|---|")
    edges = np.linspace(0, n, max(1, min(windows, n)) + 1).astype(int)
    for a, b in itertools.pairwise(edges):
        if b <= a:
            continue
        part = slice(a, b)
        sl = m["sliding_contacts"][part]
        print(f"| {a + 1}-{b} | {int(m['drained'][a])}-{int(m['drained'][b - 1])} | "
              f"{int(m['removed_springs'][a])}-{int(m['removed_springs'][b - 1])} | "
              f"{int(cycles[part].sum())} | {cycles[part].mean():.1f}, {int(cycles[part].max())} | "
              f"{int(sl.min())}, {int(sl.max())} |")  # fmt: skip


def sweep_cost() -> None:
    import tomllib

    from porenet import load_scene
    from porenet.core.cost import estimate_cost
    from porenet.sweep.spec import expand, load_sweep

    sweeps = ROOT / "examples" / "sweeps"
    data = tomllib.loads((sweeps / "fig3.toml").read_text())
    data["base"] = str(SCENE)
    runs = expand(load_sweep(data, base_dir=sweeps))
    total = sum(estimate_cost(load_scene(run.scene)).wall_seconds for run in runs)
    print(
        f"fig3.toml on {SCENE.name}: {len(runs)} runs, {total / 3600:.1f} h of runs by the "
        f"cost model (~{total / 7200:.1f} h on 2 workers)"
    )


def sparse_cost(ns: list[int]) -> None:
    """One sparse direct solve of the system with free rotations at each size: the stiffness
    matrix of the first update of the scene with ``solid.rotation = free``, factored by
    SuperLU as ``porenet.kinds.mindlin.kernels.frictional_sparse.solve`` does it."""
    import resource

    from scipy.sparse.linalg import splu

    from porenet.jit.threads import configure_threads
    from porenet.kinds.mindlin.kernels import frictional_sparse
    from porenet.simulation import Simulation

    configure_threads(1)

    class Captured(Exception):
        pass

    def measure(pat, normal, shear, foundation, *_):
        a = frictional_sparse.matrix(pat, normal, shear, foundation)
        start = time.perf_counter()
        lu = splu(a)
        factor = time.perf_counter() - start
        start = time.perf_counter()
        lu.solve(np.ones(a.shape[0]))
        solve = time.perf_counter() - start
        peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 2**20  # KiB -> GiB
        print(f"| {n} | {a.shape[0]} | {a.nnz} | {lu.L.nnz + lu.U.nnz} | {factor:.2f} | "
              f"{1e3 * solve:.1f} | {peak:.2f} |", flush=True)  # fmt: skip
        raise Captured

    print("| n | unknowns | matrix entries | factor entries (L + U) | factor (s) | solve (ms) "
          "| peak memory so far (GiB) |\n|---|---|---|---|---|---|---|")  # fmt: skip
    original = frictional_sparse.solve
    frictional_sparse.solve = measure
    try:
        for n in sorted(ns):
            sets = [f"lattice.n={n}", "stop.max_drained=2", "solid.rotation=free",
                    "solid.solver=sparse-direct"]  # fmt: skip
            try:
                Simulation.from_scene(SCENE, sets).run()
            except Captured:
                continue
    finally:
        frictional_sparse.solve = original


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = parser.add_subparsers(dest="what", required=True)
    up = sub.add_parser("updates")
    up.add_argument("--n", type=int, default=400)
    up.add_argument("--repeat", type=int, default=5)
    rn = sub.add_parser("run")
    rn.add_argument("--n", type=int, default=None)
    rn.add_argument("--set", action="append", default=[], help="KEY=VALUE for the scene")
    rn.add_argument("--threads", nargs="+", default=["auto"])
    rn.add_argument("--loads", nargs="+", type=int, default=[0])
    rn.add_argument("--repeat", type=int, default=1)
    rn.add_argument("--json", default=None, help="write every run's summary here")
    tl = sub.add_parser("tolerance")
    tl.add_argument("--values", nargs="+", type=float, default=[1e-3, 1e-2])
    tl.add_argument("--max-drained", type=int, default=150)
    tl.add_argument("--variants", nargs="+", default=None,
                    help="runs to compare, the first the reference: 'defaults' or "
                         "KEY=VALUE,KEY=VALUE (replaces --values)")  # fmt: skip
    tl.add_argument("--set", action="append", default=[], help="KEY=VALUE for every run")
    tl.add_argument("--keep", default=None, help="copy the run files (run-0.h5, ...) here")
    pr = sub.add_parser("profile")
    pr.add_argument("--max-drained", type=int, default=60)
    pr.add_argument("--top", type=int, default=16)
    pr.add_argument("--set", action="append", default=[], help="KEY=VALUE for the scene")
    an = sub.add_parser("anatomy")
    an.add_argument("--max-drained", type=int, default=40)
    an.add_argument("--set", action="append", default=[], help="KEY=VALUE for every run")
    an.add_argument("--variants", nargs="+", default=["defaults", "solid.friction=0.3"],
                    help="'defaults' or KEY=VALUE,KEY=VALUE")  # fmt: skip
    sub.add_parser("sweep-cost")
    cp = sub.add_parser("compare")
    cp.add_argument("run_files", nargs="+", help="run files (.h5), the first the reference")
    se = sub.add_parser("series")
    se.add_argument("run_file", help="a run file (.h5) of a hertz-mindlin run")
    se.add_argument("--windows", type=int, default=6, help="stretches of equal updates")
    sp = sub.add_parser("sparse-cost")
    sp.add_argument("--n", type=int, nargs="+", default=[50, 100, 200])
    args = parser.parse_args()
    if args.what == "sparse-cost":
        sparse_cost(args.n)
        return
    if args.what == "series":
        series(args.run_file, args.windows)
        return
    if args.what == "anatomy":
        check_overrides(parser, *(args.set + ([] if v == "defaults" else v.split(","))
                                  for v in args.variants))  # fmt: skip
        anatomy(args.max_drained, args.set, args.variants)
        return
    if args.what == "compare":
        compare(args.run_files)
        return
    if args.what == "sweep-cost":
        sweep_cost()
        return
    if args.what == "profile":
        check_overrides(parser, args.set)
        profile(args.max_drained, args.top, args.set)
        return
    if args.what == "updates":
        updates(args.n, args.repeat)
    elif args.what == "tolerance":
        try:
            variants = variant_sets(args)
        except ValueError as exc:
            parser.error(str(exc))
        check_overrides(parser, *(args.set + pairs for _, pairs in variants))
        tolerances(args)
    else:
        check_overrides(parser, args.set)
        runs(args)


if __name__ == "__main__":
    main()
