"""The ``porenet`` command.

Exit status (docs/reliability.md, "Exit status"): 0 done; 1 the command failed although its
input was acceptable (numerical trouble, a full disk, out of memory); 2 bad usage or input
(the message names the scene field, the file or the flag); 130 interrupted. Errors are one
readable paragraph, never a traceback; pass ``--traceback`` to see one for a bug report.
Checks made before any work starts are in :mod:`porenet.cli.checks`.
"""

from __future__ import annotations

import argparse
import json
import logging
import sys
import time
from pathlib import Path
from typing import TYPE_CHECKING, Any

from porenet.cli.interrupts import interrupts
from porenet.core.errors import ConfigError, OutputError, RunFileError

if TYPE_CHECKING:  # pragma: no cover
    from porenet.io.checkpoint import CheckpointSchedule

log = logging.getLogger("porenet")


def _scene_source(args: argparse.Namespace) -> Path:
    from porenet.config.loading import example_path

    if args.example:
        if args.scene:
            raise ConfigError("give either a SCENE file or --example NAME, not both")
        return example_path(args.example)
    if not args.scene:
        raise ConfigError("no scene given: pass a SCENE.toml or --example quickstart")
    return Path(args.scene)


def cmd_run(args: argparse.Namespace) -> int:
    from porenet.cli import checks as cli_checks
    from porenet.config.loading import load_scene
    from porenet.core.plan import make_plan
    from porenet.hooks import get_registry

    source = _scene_source(args)
    output = Path(args.output) if args.output else Path(f"{source.stem}.h5")
    cli_checks.check_run_output(output, args.overwrite)
    if args.plot:
        cli_checks.check_picture_output(Path(args.plot), "--plot")
    progress = not args.quiet
    registry = get_registry()
    scene = load_scene(source, args.overrides, registry=registry)
    note = cli_checks.check_memory(make_plan(scene, registry), ignore=args.ignore_memory)
    if note is not None:
        log.warning("%s", note)
    cli_checks.apply_threads(args.threads)  # imports numba: once the scene is accepted
    checkpoints = _checkpoints(args, output)
    from porenet.simulation import Simulation  # numerics only once the scene is accepted

    sim = Simulation.from_scene(scene, output=output, progress=progress, registry=registry)
    _report(args, source.name, sim.run(checkpoints))
    return 0


def _checkpoints(args: argparse.Namespace, output: Path) -> CheckpointSchedule | None:
    """The schedule of ``--checkpoint-every`` (None without it). A checkpoint already where
    this run would keep its own is never replaced silently (docs/run-file.md, "Checkpoints")."""
    from porenet.io.checkpoint import (
        CheckpointError,
        CheckpointSchedule,
        checkpoint_path,
        read_header,
    )

    path = checkpoint_path(output)
    if path.exists() and not args.overwrite:
        try:
            held = f"holds a checkpoint of {read_header(path).describe()}"
        except CheckpointError:
            held = "exists"
        raise ConfigError(
            f"{path} {held}; go on with `porenet resume {path}`, or pass --overwrite to start "
            "afresh (the checkpoint is replaced)"
        )
    if args.checkpoint_every is None:
        # none written; one left by an earlier run (replaced with --overwrite) goes at the end
        return CheckpointSchedule(path) if path.exists() else None
    return CheckpointSchedule.parse(args.checkpoint_every, path)


def cmd_resume(args: argparse.Namespace) -> int:
    from porenet.cli import checks as cli_checks
    from porenet.io.checkpoint import CheckpointSchedule, checkpoint_path
    from porenet.simulation import Simulation

    path = Path(args.checkpoint)
    cli_checks.apply_threads(args.threads)
    sim = Simulation.resume(path, output=args.output, progress=not args.quiet)
    output = sim.plan.output
    if output is not None:
        cli_checks.check_run_output(Path(output), args.overwrite)
    # the resumed run keeps a checkpoint too (every 10 minutes unless told otherwise), beside
    # its run file; it is removed when the run ends
    target = checkpoint_path(output) if output is not None else path
    schedule = CheckpointSchedule.parse(args.checkpoint_every or "10m", target)
    if not args.quiet:
        print(f"resuming {path}: " + _describe_resume(sim), file=sys.stderr)
    result = sim.run(schedule)
    if target != path:
        path.unlink(missing_ok=True)
    _report(args, sim.plan.scene.name, result)
    return 0


def _describe_resume(sim: Any) -> str:
    state = sim.state
    return (
        f"scene {sim.plan.scene.name!r} at {state.n_drained:,} drained pores, step "
        f"{state.step:,}, {sim.wall_time():.0f} s of wall time so far"
    )


def _report(args: argparse.Namespace, name: str, result: Any) -> None:
    """The lines ``run`` and ``resume`` print when a run ends (unless ``-q``), and the
    picture of ``--plot``."""
    s = result.summary
    if not args.quiet:
        print(
            f"{name}: {s['stop_reason']} after {s['n_drained']} drained pores "
            f"({100 * s['drained_fraction']:.2f} %), trapped {100 * s['trapped_fraction']:.2f} %, "
            f"{s['wall_time_s']:.3f} s"
        )
        if s.get("capillary_number_measured") is not None:
            t_end = result.data.invasion_time[-1] if result.data.invasion_time is not None else 0
            print(
                f"  model time {t_end:.4g} s, {s['time_steps']} steps, Ca measured "
                f"{s['capillary_number_measured']:.4g} (requested {s['capillary_number']:.4g}), "
                f"volume balance {s['volume_balance_error']:.1e}"
            )
        if s.get("classifier") is not None:
            from porenet.analysis.classify import describe

            print(f"  pattern: {describe(s)}")
        if result.path is not None:
            print(f"run file: {result.path}")
    if args.plot:
        from porenet.viz.pattern import plot_pattern, save_figure

        save_figure(plot_pattern(result.data), args.plot)
        if not args.quiet:
            print(f"figure: {args.plot}")


def cmd_compile(args: argparse.Namespace) -> int:
    from porenet.jit.warmup import compile_all

    t0 = time.perf_counter()

    def done(name: str, seconds: float) -> None:
        if not args.quiet:
            state = f"compiled in {seconds:.1f} s" if seconds > 0 else "already compiled"
            print(f"{name}: {state}", flush=True)

    if args.jobs is not None and args.jobs < 1:
        raise ConfigError(f"--jobs {args.jobs}: must be at least 1")
    total = compile_all(on_done=done, jobs=args.jobs or 1)
    if not args.quiet:
        print(
            f"porenet compile: {total:.1f} s of compilation, {time.perf_counter() - t0:.1f} s "
            "of wall time; later runs on this machine load the kernels from the cache"
        )
    return 0


def cmd_validate(args: argparse.Namespace) -> int:
    from porenet.config.loading import load_scene

    source = _scene_source(args)
    scene = load_scene(source, args.overrides)
    if args.show:
        print(json.dumps(scene.model_dump(mode="json"), indent=2))
    else:
        print(f"{source}: valid")
    return 0


def cmd_plan(args: argparse.Namespace) -> int:
    from porenet.config.loading import load_scene
    from porenet.core.plan import make_plan
    from porenet.hooks import get_registry

    source = _scene_source(args)
    registry = get_registry()
    scene = load_scene(source, args.overrides, registry=registry)
    plan = make_plan(scene, registry)
    print(plan.describe())
    from porenet.cli.checks import check_memory

    too_large = check_memory(plan, ignore=True)
    if too_large is not None:
        print(f"memory: {too_large.split('; ')[0]}; porenet run refuses it without --ignore-memory")
    return 0


def cmd_plugins(args: argparse.Namespace) -> int:
    from porenet.hooks import get_registry

    registry = get_registry()
    header = ("family", "kind", "package", "plugin")
    rows = [(e.family, e.kind, e.package, e.plugin) for e in registry]
    if args.json:
        print(json.dumps([dict(zip(header, r, strict=True)) for r in rows]))
        return 0
    widths = [max(len(r[i]) for r in [header, *rows]) for i in range(len(header))]
    for r in [header, *rows]:
        print("  ".join(c.ljust(w) for c, w in zip(r, widths, strict=True)).rstrip())
    for name, message in registry.failures:
        print(f"failed: {name}: {message}", file=sys.stderr)
    return 0


def cmd_plot(args: argparse.Namespace) -> int:
    from porenet.cli import checks as cli_checks
    from porenet.io.runfile import check_run_file

    if args.pressure and args.kind not in (None, "pressure"):
        raise ConfigError(f"--pressure means --kind pressure; it cannot go with --kind {args.kind}")
    kind = "pressure" if args.pressure else (args.kind or "pattern")
    run = Path(args.runfile)
    default = run.with_name(f"{run.stem}.png" if kind == "pattern" else f"{run.stem}-{kind}.png")
    out = Path(args.output) if args.output else default
    cli_checks.check_dpi(args.dpi)
    check_run_file(run)  # its header only: before matplotlib is imported
    cli_checks.check_picture_output(out, "-o")
    from porenet.io.runfile import read_run
    from porenet.viz.figures import make_figure, missing
    from porenet.viz.pattern import save_figure

    data = read_run(run)
    lack = missing(data, kind)
    if lack is not None:
        raise ConfigError(f"--kind {kind}: {run} {lack}")
    try:
        fig = make_figure(data, kind)
    except ValueError as exc:
        raise ConfigError(f"--kind {kind}: {run}: {exc}") from exc
    dpi = cli_checks.dpi_of(args.dpi)
    cli_checks.check_picture_size(fig, dpi)
    save_figure(fig, out, dpi=dpi)
    print(f"figure: {out}")
    return 0


def cmd_classify(args: argparse.Namespace) -> int:
    from porenet.analysis.classify import classify_run, describe
    from porenet.core.kinds import builds_nothing
    from porenet.hooks import get_registry
    from porenet.io.runfile import read_run, update_summary

    data = read_run(args.runfile)
    registry = get_registry()
    default = registry.default("classifier")
    kind = args.classifier or (data.scene.get("classifier") or {}).get("kind", default)
    if ("classifier", kind) in registry and builds_nothing(registry.get("classifier", kind).config):
        kind = default  # the run skipped classification; classifying now is what was asked
    if kind is None or ("classifier", kind) not in registry:
        known = ", ".join(sorted(e.kind for e in registry if e.family == "classifier"))
        raise ConfigError(f"--classifier {kind}: unknown classifier kind (known: {known})")
    entry = registry.get("classifier", kind)
    config = entry.config()
    if data.scene.get("classifier", {}).get("kind") == kind:
        try:  # the run's settings
            config = entry.config.model_validate(data.scene["classifier"])
        except ValueError as exc:  # pydantic's ValidationError
            raise RunFileError(
                f"{args.runfile}: its [classifier] settings are not valid ({exc}); pass "
                "--classifier KIND to use a classifier's defaults"
            ) from None
    verdict = classify_run(data, entry.load()(config), kind)  # type: ignore[misc]
    if not args.no_store:
        try:
            update_summary(args.runfile, verdict)
        except OutputError as exc:
            raise OutputError(f"{exc} (or --no-store to print the label only)") from exc
    if args.json:
        print(json.dumps(verdict))
    else:
        print(f"{args.runfile}: {describe(verdict)}")
    return 0


def cmd_export(args: argparse.Namespace) -> int:
    from porenet.cli import checks as cli_checks
    from porenet.io.runfile import check_run_file
    from porenet.io.xdmf import check_not_run_file, default_output, export_xdmf

    run = Path(args.runfile)
    out = Path(args.output) if args.output else default_output(run)
    check_run_file(run)  # its header only: a missing or foreign file before anything else
    check_not_run_file(run, out)
    cli_checks.check_export_output(out, args.overwrite)
    xdmf, sidecar = export_xdmf(run, out)
    print(f"xdmf: {xdmf} (with {sidecar}; open it with `paraview {xdmf}`)")
    return 0


def cmd_phase_diagram(args: argparse.Namespace) -> int:
    from porenet.cli import checks as cli_checks

    cli_checks.check_dpi(args.dpi)
    directory = Path(args.dir)
    if not directory.is_dir():
        state = "is not a directory" if directory.exists() else "does not exist"
        raise ConfigError(f"{directory}: {state}; give the output directory of `porenet sweep`")
    if args.table:
        cli_checks.check_output_file(Path(args.table), "--table")
    out = Path(args.output)
    cli_checks.check_picture_output(out, "-o")
    from porenet.analysis.phase import phase_points, points_table
    from porenet.io.atomic import atomic_write_bytes
    from porenet.sweep.records import read_summary
    from porenet.viz.pattern import save_figure
    from porenet.viz.phase import plot_phase_diagram

    table = read_summary(directory)
    fig = plot_phase_diagram(table, axes=args.axes)
    dpi = cli_checks.dpi_of(args.dpi)
    cli_checks.check_picture_size(fig, dpi)
    save_figure(fig, out, dpi=dpi)
    print(f"figure: {out}")
    if args.table:
        _, points = phase_points(table, args.axes)
        text = points_table(points).encode("utf-8")
        atomic_write_bytes(args.table, text, what="table")
        print(f"table: {args.table}")
    return 0


def cmd_sweep(args: argparse.Namespace) -> int:
    from porenet.sweep.runner import Progress, SweepInterrupted, format_progress, run_sweep

    width = 0

    def show(p: Progress) -> None:  # one line, redrawn in place (terminal only)
        nonlocal width
        line = f"{Path(args.sweep).name}: {format_progress(p)}"
        sys.stderr.write("\r" + line.ljust(width))
        sys.stderr.flush()
        width = len(line)

    def log_line(p: Progress) -> None:  # a log (not a terminal): one line per finished run
        if p.last is not None:
            print(f"{Path(args.sweep).name}: {p.last} finished; {format_progress(p)}",
                  file=sys.stderr, flush=True)  # fmt: skip

    tty = sys.stderr.isatty()
    try:
        report = run_sweep(
            args.sweep,
            args.output,
            workers=args.workers,
            scheduler=args.scheduler,
            dask_local=args.dask_local,
            retry_failed=args.retry_failed,
            checkpoint_every=args.checkpoint_every,
            on_progress=None if args.quiet else show if tty else log_line,
        )
    except SweepInterrupted as exc:
        print(f"{chr(10) if width else ''}porenet sweep: {exc}", file=sys.stderr)
        return exc.exit_status
    finally:
        if width:
            sys.stderr.write("\n")
    if not args.quiet:
        print(f"{Path(args.sweep).name}: {report.describe()}")
    if report.failed:
        print(
            f"porenet sweep: {report.failed} run(s) failed: see the error column of "
            f"{report.summary_path} and {report.out_dir / 'runs'}/*.error.txt "
            "(--retry-failed runs them again)",
            file=sys.stderr,
        )
    return 0


def cmd_schema(args: argparse.Namespace) -> int:
    from porenet.config.scene import scene_model
    from porenet.hooks import get_registry

    print(json.dumps(scene_model(get_registry()).model_json_schema(), indent=2))
    return 0


#: What each command of :func:`porenet.cli.parser.build_parser` runs.
COMMANDS = {
    "run": cmd_run,
    "resume": cmd_resume,
    "compile": cmd_compile,
    "validate": cmd_validate,
    "plan": cmd_plan,
    "plugins": cmd_plugins,
    "plot": cmd_plot,
    "classify": cmd_classify,
    "export": cmd_export,
    "phase-diagram": cmd_phase_diagram,
    "sweep": cmd_sweep,
    "schema": cmd_schema,
}


def main(argv: list[str] | None = None) -> int:
    """Run the ``porenet`` command and return its exit status (module docstring)."""
    from porenet.cli.parser import build_parser

    parser = build_parser()
    args = parser.parse_args(argv)  # bad usage: argparse prints it and exits with 2
    level = logging.WARNING - 10 * min(args.verbose, 2)
    logging.basicConfig(level=level, format="%(levelname)s %(name)s: %(message)s")
    with interrupts() as interrupted:
        try:
            status = int(COMMANDS[args.command](args))
            if interrupted():  # caught and cleared in a library's C code (numpy's ctypes check)
                done = " and its output is complete" if status == 0 else ""
                print(f"porenet {args.command}: Ctrl-C was lost inside a library while it "
                      "started (docs/reliability.md, \"Exit status\"); the command went on to "
                      f"its end{done}", file=sys.stderr)  # fmt: skip
            return status
        except Exception as exc:
            if interrupted():  # an error that followed Ctrl-C is its consequence
                return _interrupted(args.command)
            if args.traceback and not isinstance(exc, BrokenPipeError):
                raise
            from porenet.cli.checks import report

            status, message = report(exc, args.command)
            if message is not None:
                print(message, file=sys.stderr)
            return status
        except KeyboardInterrupt:
            return _interrupted(args.command)


def _interrupted(command: str) -> int:
    written = "; no run file was written" if command in ("run", "resume") else ""
    print(f"porenet {command}: interrupted{written}", file=sys.stderr)
    return 130
