"""Does a shear-stiff contact make the fractures branch? Fig. 5's scene with hertz-mindlin.

    python examples/scripts/fracture_shear.py --records /tmp/shear-100.jsonl \
        --table docs/fracture-shear.md --out docs/figures/fracture-shear.png \
        --patterns docs/figures/fracture-shear-patterns.png          # n = 100, ~40 min
    python examples/scripts/fracture_shear.py --n 400 --nf 10 --ratio 0.1 0.8 --friction none \
        --seeds 1 --records /tmp/shear-400.jsonl --table /tmp/shear-400.md  # ~25 min a run

Runs Fig. 5's scene (``examples/scenes/fig5.toml``: lambda = 0.1, Ca* = 10, viscous
drainage, eps_0 = 0.05) at n pores per side with the solid kind ``hertz-mindlin``
(docs/model.md, "Frictional solid (kind hertz-mindlin)") for each tangential stiffness ratio
K_t / K_n, without sliding ("none") or with a Coulomb friction coefficient, and each fracturing
number, over seeds, to breakthrough. Per point it reports the mean and standard deviation over
seeds of the mass-radius fractal dimension (as examples/scripts/fig5.py), the drained pores,
the springs removed, the longest straight drained run and the mean length of the thin
straight segments (channels one pore wide, at least 5 pores long: the fractures' straight
segments). ``--patterns`` draws, for ``--pattern-seed`` at ``--pattern-nf``, the literal model
(``hertz``), the weak foundation (``hertz``, k_f = 0.02 K_0, docs/paper.md) and every
hertz-mindlin setting side by side. ``--runs DIR`` keeps every run's run file in DIR (named
after its point, :func:`run_file`); ``--patterns`` then draws the runs found there instead of
running them again (a study at n = 400 costs 5-40 min a run).

Every run is appended to ``--records`` (JSON lines) as it ends, and runs already there are
not repeated: an interrupted study resumes where it stopped (a line that is not a record,
half written by a killed process, is named with its file and line, and nothing runs until it
is deleted). Several processes can share a study (one records file each, all of them given
to the report); ``--no-run`` reports what the files hold without running the rest (each row
names its seeds). Each record keeps the run's CPU time (the table's column), how many
contacts it froze (``frozen``, docs/run-file.md's ``frozen_contacts``) and the code that
made it (``code``: the commit of the imported porenet, with ``+dirty`` if porenet/ or
examples/ had uncommitted changes; :func:`code_version`). The n = 400 study's records are
kept in the repository, docs/data/fracture-shear-n400/ (docs/fracture-shear-n400.md says
why). ``--status FILE``
runs nothing and writes which runs of the planned study (``--ratio`` x ``--friction`` x
``--nf`` x ``--seeds``) the records hold, which are missing, and the CPU time the missing
ones should take (a study at n = 400 takes several sessions; docs/fracture-shear-n400.md); a
missing run with sliding at an N_f that no run with sliding reached yet is priced at the
runs without sliding there times the cost model's factor for sliding (docs/cost.md).
``--skip-settled`` runs no third seed at a point whose first two found the same pattern (the
same springs opened, D_f within :data:`fracture_shear_tables.SETTLED_D_F`: above the
crossover every seed opens the full cross), and ``--status`` lists such a seed as settled
rather than missing. ``--by-nf FILE`` tables every run at each N_f and sliding setting
together, whatever its K_t/K_n (the study's answer at a glance). ``--sliding-cost FILE``
runs nothing and tables every run with sliding beside the same run without it, their CPU
times' ratio against the cost model's factor for sliding and the model's constant fitted to
them (docs/cost.md). The reports are written by ``fracture_shear_tables.py`` beside this
script; this one makes the runs; ``fracture_shear_doc.py`` makes the tables of
docs/fracture-shear-n400.md again from the committed records.
With ``--runs``, ``--checkpoint-every 10m`` writes each run's checkpoint beside its run file
(docs/run-file.md, "Checkpoints"), and a study restarted after its process was killed
finishes that run from the checkpoint, with the uninterrupted run's result (the code and
the scene must be the same; anything else is refused, naming the file) and the CPU time of
every part (:class:`CpuCheckpoints`).
``--solver-tolerance T`` makes the runs at another ``solid.solver_tolerance`` (runs of their
own in the records, their tolerance in the run files' names and the table's caption;
docs/accuracy.md, "Where the default tolerance lags").
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from fig5 import make_scene, shape
from fracture_shear_tables import (
    POINT,
    RecordError,
    aggregate,
    draw,
    friction_label,
    line_of,
    planned,
    point_key,
    read_records,
    settled,
    write_by_nf,
    write_sliding_cost,
    write_status,
    write_table,
)

import porenet
from porenet.analysis.features import LONG_RUN, straight_runs
from porenet.cli.checks import check_output_file
from porenet.config.loading import load_scene
from porenet.core.cost import estimate_cost
from porenet.core.errors import ConfigError
from porenet.io.atomic import atomic_output
from porenet.io.checkpoint import (
    CheckpointError,
    CheckpointSchedule,
    checkpoint_path,
    read_header,
    scene_digest,
)
from porenet.jit.threads import configure_threads
from porenet.simulation import Simulation


def solid_of(ratio: float | None, friction: float | None, rotation: str = "held",
             solver_tolerance: float | None = None) -> dict:  # fmt: skip
    """The ``[solid]`` fields of one setting (``ratio`` None: the literal ``hertz``;
    ``solver_tolerance`` None: the solid's default)."""
    if ratio is None:
        return {}
    fields = {"kind": "hertz-mindlin", "shear_stiffness_ratio": ratio, "rotation": rotation}
    if friction is not None:
        fields["friction"] = friction
    if solver_tolerance is not None:
        fields["solver_tolerance"] = solver_tolerance
    return fields


def run_file(runs: Path, n: int, setting: dict, nf: float, seed: int) -> Path:
    """Where ``--runs`` keeps the run file of one point (``setting``: :func:`solid_of`'s
    fields, or ``{"foundation": k_f}`` for the literal model on a foundation)."""
    if "foundation" in setting:
        name = f"hertz-kf{setting['foundation']:g}"
    elif not setting:
        name = "hertz"
    else:
        friction = setting.get("friction")
        sliding = "stick" if friction is None else f"mu{friction:g}"
        name = f"mindlin-r{setting['shear_stiffness_ratio']:g}-{sliding}-{setting['rotation']}"
        if "solver_tolerance" in setting:
            name += f"-tol{setting['solver_tolerance']:g}"
    return runs / f"n{n}-{name}-nf{nf:g}-s{seed}.h5"


def cpu_file_of(checkpoint: Path) -> Path:
    """Where :class:`CpuCheckpoints` keeps the CPU time of the run that wrote
    ``checkpoint``."""
    return checkpoint.with_name(checkpoint.name + ".cpu")


class CpuCheckpoints(CheckpointSchedule):
    """The run's checkpoints (``RUN.h5.checkpoint``, docs/run-file.md, "Checkpoints") and,
    beside each, the CPU time the run used up to it (``RUN.h5.checkpoint.cpu``, JSON), so
    that a run resumed by a later process records its whole CPU time.

    The CPU file is written right after its checkpoint: a process killed between the two
    leaves the previous count, so a resumed run's CPU time can be short by at most one
    interval of ``--checkpoint-every``."""

    def __init__(self, every: CheckpointSchedule, cpu_before: float, started: float) -> None:
        super().__init__(every.path, every.every_seconds, every.every_drained)
        #: CPU time (s) of the processes that ran the run before this one.
        self.cpu_before = cpu_before
        self._started = started  # this process's time.process_time() when it took the run up

    @property
    def cpu_file(self) -> Path:
        return cpu_file_of(self.path)

    def cpu(self) -> float:
        """CPU time of the run so far (s), over every process that ran part of it."""
        return self.cpu_before + time.process_time() - self._started

    def write(self, simulation) -> Path:  # type: ignore[no-untyped-def]
        path = super().write(simulation)
        with atomic_output(self.cpu_file, what="CPU time record") as tmp:
            tmp.write_text(json.dumps({"cpu_s": self.cpu(),
                                       "n_drained": int(simulation.state.n_drained)}))  # fmt: skip
        return path

    def remove(self) -> None:
        super().remove()
        self.cpu_file.unlink(missing_ok=True)


def start_or_resume(scene: dict, output: Path | None,
                    every: str | None) -> tuple[Simulation, CpuCheckpoints | None]:  # fmt: skip
    """The simulation of ``scene`` writing ``output``: resumed from the checkpoint a killed
    process left beside ``output`` if there is one (refused, naming the file, if it was
    written by other code or for another scene), else new; and its checkpoint schedule
    (every ``every``: a duration such as ``10m`` or a number of drained pores, as
    ``porenet run --checkpoint-every``; None: none written)."""
    started = time.process_time()
    if output is None:
        return Simulation.from_scene(scene), None
    path = checkpoint_path(output)
    schedule = CheckpointSchedule(path) if every is None else CheckpointSchedule.parse(every, path)
    if not path.exists():
        sim = Simulation.from_scene(scene, output=output)
        return sim, CpuCheckpoints(schedule, 0.0, started)
    try:
        wanted = scene_digest(load_scene(scene).model_dump(mode="json"))
        if read_header(path).scene_digest != wanted:
            raise CheckpointError("it holds another scene than this run's")
        sim = Simulation.resume(path)
    except CheckpointError as exc:
        print(f"{path}: cannot resume this run from it ({exc}); delete it (and "
              f"{cpu_file_of(path).name}) to make the run afresh", file=sys.stderr)  # fmt: skip
        raise SystemExit(2) from None
    cpu_file = cpu_file_of(path)
    try:
        cpu_before = float(json.loads(cpu_file.read_text())["cpu_s"]) if cpu_file.exists() else 0.0
    except (OSError, ValueError, KeyError, TypeError) as exc:
        print(f"{cpu_file}: not a CPU time record ({exc}); the resumed run's record counts "
              "only the CPU time from here on", file=sys.stderr)  # fmt: skip
        cpu_before = 0.0
    print(f"resuming {output.name} at {sim.state.n_drained} drained pores "
          f"({cpu_before:.0f} s of CPU before)", flush=True)  # fmt: skip
    return sim, CpuCheckpoints(schedule, cpu_before, started)


def measure(n: int, setting: dict, nf: float, seed: int, keep: bool = False,
            output: Path | None = None, checkpoint_every: str | None = None) -> dict:  # fmt: skip
    """One run of Fig. 5's scene with the solid fields ``setting``: its shape and cost
    (the run's data under ``"data"`` if ``keep``; its run file written to ``output`` if
    given, and a checkpoint beside it every ``checkpoint_every``, from which a later call
    resumes). ``wall`` is the run's wall time from its summary (building it included,
    summed over resumed parts), ``cpu`` its CPU time (also summed)."""
    scene = make_scene(n, nf, foundation=setting.pop("foundation", None), seed=seed,
                       solid=setting)  # fmt: skip
    cpu = time.process_time()
    sim, schedule = start_or_resume(scene, output, checkpoint_every)
    res = sim.run(schedule)
    cpu = schedule.cpu() if schedule is not None else time.process_time() - cpu
    return {**describe(res.data, res.summary, n), "wall": res.summary["wall_time_s"],
            "cpu": cpu, **({"data": res.data} if keep else {})}  # fmt: skip


def describe(data, summary: dict, n: int) -> dict:
    """A finished run's shape (:data:`KEYS`) and the solver's counts from its summary."""
    d_f, straight = shape(data, n)
    runs = straight_runs(data.as_grid(data.drained), thin=True)
    long = runs[runs >= LONG_RUN]
    return {
        "d_f": d_f,
        "drained": summary["n_drained"],
        "removed": summary.get("springs_removed", 0),
        "straight": straight,
        "segment": float(long.mean()) if long.size else 0.0,
        "updates": summary.get("mechanical_updates", 0),
        "sliding": summary.get("largest_sliding_contacts", 0),
        "frozen": summary.get("frozen_contacts", 0),
        # the largest force left out of balance on a particle, over the contacts' prestress
        # force F_0 (runs with sliding carry the frozen contacts' imbalance; docs/model.md)
        "residual": summary["largest_balance_residual"] / summary["prestress_force"]
        if "prestress_force" in summary
        else None,
    }


def main(argv: list[str] | None = None) -> None:
    """The script's command line (``argv``: its arguments; None: ``sys.argv``'s)."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=100)
    parser.add_argument("--ratio", type=float, nargs="+", default=[0.1, 0.3, 0.8],
                        help="K_t / K_n values")  # fmt: skip
    parser.add_argument("--friction", nargs="+", default=["none", "0.3"],
                        help="Coulomb coefficients; 'none': no sliding")  # fmt: skip
    parser.add_argument("--rotation", choices=["held", "free"], default="held",
                        help="particle rotations (solid.rotation)")  # fmt: skip
    parser.add_argument("--solver-tolerance", type=float, default=None,
                        help="solid.solver_tolerance (a) of every hertz-mindlin run "
                        "(default: the solid's, 1e-2); part of each run's identity in the "
                        "records")  # fmt: skip
    parser.add_argument("--nf", type=float, nargs="+", default=[0.1, 0.3, 1.0, 3.0, 10.0, 30.0])
    parser.add_argument("--seeds", type=int, nargs="+", default=[1, 2, 3])
    parser.add_argument("--threads", type=int, default=1, help="threads per run (default 1)")
    parser.add_argument("--records", type=Path, nargs="+",
                        help="JSON lines, one per run (resumable): runs found in any of these "
                        "files are not repeated; new ones are appended to the first")  # fmt: skip
    parser.add_argument("--no-run", action="store_true",
                        help="only report the runs already in --records (a study that several "
                        "sessions or machines share); points without one are left out")  # fmt: skip
    parser.add_argument("--table", type=Path, help="markdown table")
    parser.add_argument("--out", type=Path, help="figure: D_f against N_f (PNG)")
    parser.add_argument("--by-nf", type=Path,
                        help="markdown table: per sliding setting and N_f, every run at "
                        "any K_t/K_n together (D_f lowest-highest, springs opened, "
                        "drained)")  # fmt: skip
    parser.add_argument("--patterns", type=Path, help="figure: patterns (PNG)")
    parser.add_argument("--pattern-seed", type=int, default=1)
    parser.add_argument("--pattern-nf", type=float, default=10.0)
    parser.add_argument("--runs", type=Path,
                        help="keep every run's run file in this folder; --patterns draws the "
                        "ones found there instead of running them again")  # fmt: skip
    parser.add_argument("--checkpoint-every", metavar="WHEN",
                        help="with --runs: write each run's checkpoint beside its run file "
                        "this often (90s, 10m, 2h, or a number of drained pores); a run "
                        "whose checkpoint is there when the study is restarted goes on from "
                        "it")  # fmt: skip
    parser.add_argument("--skip-settled", action="store_true",
                        help="run no more seeds at a point whose first two found the same "
                        "pattern (the same springs opened, D_f within 1e-3: above the "
                        "crossover the full cross, whatever the disorder); --status lists "
                        "them as settled, not missing")  # fmt: skip
    parser.add_argument("--status", type=Path,
                        help="run nothing: write to this file (markdown) which runs of the "
                        "study that --ratio, --friction, --nf and --seeds plan are in "
                        "--records, which are missing and their CPU time")  # fmt: skip
    parser.add_argument("--sliding-cost", type=Path,
                        help="run nothing: write to this file (markdown) every run with "
                        "sliding in --records beside the same run without it, their CPU "
                        "times' ratio against the cost model's factor for sliding, and the "
                        "model's constant fitted to them")  # fmt: skip
    args = parser.parse_args(argv)
    try:
        frictions = [None if f == "none" else float(f) for f in args.friction]
    except ValueError:
        parser.error(f"--friction takes numbers or 'none', got {args.friction}")
    if any(r <= 0 for r in args.ratio) or any(v <= 0 for v in args.nf) or args.n < 8:
        parser.error("--ratio and --nf must be > 0 and --n >= 8")
    if args.solver_tolerance is not None and not args.solver_tolerance > 0:
        parser.error("--solver-tolerance must be > 0")
    if any(f is not None and f < 0 for f in frictions):
        parser.error("--friction must be >= 0 or 'none'")
    if args.checkpoint_every is not None:
        if args.runs is None:
            parser.error("--checkpoint-every needs --runs (the checkpoints sit beside the "
                         "run files)")  # fmt: skip
        try:
            CheckpointSchedule.parse(args.checkpoint_every, "-", "--checkpoint-every")
        except ConfigError as exc:
            parser.error(str(exc))
    outputs = {"--table": args.table, "--out": args.out, "--patterns": args.patterns,
               "--by-nf": args.by_nf, "--status": args.status,
               "--sliding-cost": args.sliding_cost}  # fmt: skip
    for flag, path in outputs.items():
        try:
            if path is not None:
                check_output_file(path, flag)
        except ConfigError as exc:
            parser.error(str(exc))
    if args.runs:
        args.runs.mkdir(parents=True, exist_ok=True)
    configure_threads(args.threads)
    try:
        done = read_records(args.records or [])
    except RecordError as exc:
        parser.error(str(exc))
    if args.status:
        write_status(done, args, frictions)
    if args.sliding_cost:
        write_sliding_cost(done, args.sliding_cost, model_sliding_ratio)
    if args.status or args.sliding_cost:
        return
    rows, used = [], []
    for ratio, friction, nf in planned(args, frictions):
        runs = []
        for seed in args.seeds:
            key = point_key(args, ratio, friction, nf, seed)
            if key not in done and args.no_run:
                continue
            if key not in done and args.skip_settled and settled(runs):
                print(
                    f"K_t/K_n {ratio:g} {friction_label(friction)} N_f {nf:g}: seed {seed} "
                    f"not run (seeds {','.join(str(r['seed']) for r in runs)} settled it)"
                )
                continue
            if key not in done:
                setting = solid_of(ratio, friction, args.rotation, args.solver_tolerance)
                out = run_file(args.runs, args.n, setting, nf, seed) if args.runs else None
                rec = measure(args.n, setting, nf, seed, output=out,
                              checkpoint_every=args.checkpoint_every)  # fmt: skip
                done[key] = dict(zip(POINT, key, strict=True), **rec, code=code_version())
                if args.records:
                    append_record(args.records[0], done[key])
            runs.append(done[key])
        if not runs:
            continue
        used += runs
        rows.append(aggregate(runs, ratio=ratio, friction=friction, nf=nf))
        print(line_of(rows[-1]), flush=True)
    if args.table:
        write_table(rows, args)
    if args.by_nf:
        write_by_nf(used, args)
    if args.out:
        draw(rows, args.n, args.out)
        print(f"figure: {args.out}")
    if args.patterns:
        draw_patterns(args, frictions)
        print(f"figure: {args.patterns}")


def model_sliding_ratio(record: dict) -> float:
    """What the cost model (``porenet plan``, docs/cost.md) estimates a recorded run with
    sliding to cost over the same run without: its wall-time estimates of the two scenes."""

    def wall(friction: float | None) -> float:
        setting = solid_of(record["ratio"], friction, record["rotation"],
                           record["solver_tolerance"])  # fmt: skip
        scene = make_scene(record["n"], record["nf"], seed=record["seed"], solid=setting)
        return estimate_cost(load_scene(scene)).wall_seconds

    return wall(record["friction"]) / wall(None)


def code_version(package: Path | None = None, script: Path | None = None) -> str:
    """The code a run is made with, for its record: the commit of the checkout the imported
    ``porenet`` package sits in (``+dirty`` if its ``porenet/`` or this script's
    ``examples/`` differ from their commits; `` script <commit>`` appended if this script sits
    in another checkout at another commit, as when a study runs a worktree's script with an
    editable install's package), or ``porenet <version>`` when the package is not in a git
    checkout (an installed wheel). Runs of different code can differ in round-off (or more,
    where a solver changed), so a table that mixes them can say so. ``package`` and
    ``script`` (folders) default to the imported package's and this script's."""
    package = package or Path(porenet.__file__).resolve().parent
    script = script or Path(__file__).resolve().parent

    def git(where: Path, *args: str) -> str:
        out = subprocess.run(["git", "-C", str(where), *args], capture_output=True, text=True,
                             check=True)  # fmt: skip
        return out.stdout.strip()

    try:
        commit = git(package, "rev-parse", "--short=7", "HEAD")
        dirty = git(package, "status", "--porcelain", "--", ".")
    except (OSError, subprocess.CalledProcessError):
        return f"porenet {porenet.__version__}"
    try:
        own = git(script, "rev-parse", "--short=7", "HEAD")
        dirty += git(script, "status", "--porcelain", "--", "..")
    except (OSError, subprocess.CalledProcessError):
        own = commit  # a script copied out of its checkout: the package's commit names it
    return commit + ("+dirty" if dirty else "") + (f" script {own}" if own != commit else "")


def append_record(records: Path, record: dict) -> None:
    """Append one run's record as a line of ``records``, on a line of its own even if the
    file's last line lost its newline (an edited file)."""
    ends = not records.exists() or records.stat().st_size == 0
    if not ends:
        with records.open("rb") as f:
            f.seek(-1, 2)
            ends = f.read(1) == b"\n"
    with records.open("a") as f:
        f.write(("" if ends else "\n") + json.dumps(record) + "\n")


def draw_patterns(args: argparse.Namespace, frictions: list[float | None]) -> None:
    """``--pattern-seed`` at ``--pattern-nf``: literal model, weak foundation, every shear
    setting."""
    from matplotlib.figure import Figure

    from porenet.viz.pattern import plot_pattern, save_figure

    settings = [("hertz (the paper's model)", {}), ("hertz, k_f = 0.02 K_0", {"foundation": 0.02})]
    settings += [(f"K_t/K_n = {r:g}, {friction_label(f)}",
                  solid_of(r, f, args.rotation, args.solver_tolerance))
                 for r in args.ratio for f in frictions]  # fmt: skip
    cols = min(4, len(settings))
    n_rows = -(-len(settings) // cols)
    fig = Figure(figsize=(4.4 * cols, 3.8 * n_rows), dpi=110, layout="constrained")
    axes = fig.subplots(n_rows, cols, squeeze=False).ravel()
    for ax, (label, setting) in zip(axes, settings, strict=False):
        data = kept_run(args, setting)
        plot_pattern(data, ax=ax, title=f"{label}\nD_f = {shape(data, args.n)[0]:.2f}")
    for ax in axes[len(settings) :]:
        ax.set_axis_off()
    fig.suptitle(f"n = {args.n}, N_f = {args.pattern_nf:g}, Ca* = 10, seed {args.pattern_seed}",
                 fontsize=10)  # fmt: skip
    save_figure(fig, args.patterns)


def kept_run(args: argparse.Namespace, setting: dict):
    """``--pattern-seed`` of ``setting`` at ``--pattern-nf``: read from ``--runs`` if a
    finished run is there (its run file is written whole, only after the run ends), run
    otherwise (and kept there)."""
    from porenet import read_run

    seed = args.pattern_seed
    path = run_file(args.runs, args.n, setting, args.pattern_nf, seed) if args.runs else None
    if path is not None and path.exists():
        print(f"pattern from {path}", flush=True)
        return read_run(path)
    return measure(args.n, dict(setting), args.pattern_nf, seed, keep=True, output=path,
                   checkpoint_every=args.checkpoint_every)["data"]  # fmt: skip


if __name__ == "__main__":
    main()
