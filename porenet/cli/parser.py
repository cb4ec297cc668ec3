"""The ``porenet`` command's arguments: every command, its flags and their help.

:func:`build_parser` only describes the command line; :mod:`porenet.cli.main` runs what it parses
(``args.command`` names the command). Kept apart so that the help a user reads is in one
place and ``cli.py`` holds only what each command does. Imports nothing heavy.
"""

from __future__ import annotations

import argparse

from porenet._version import __version__
from porenet.plot_kinds import PLOT_KIND_DESCRIPTIONS


def add_scene_args(p: argparse.ArgumentParser) -> None:
    p.add_argument("scene", nargs="?", help="scene file (TOML)")
    p.add_argument("--example", metavar="NAME", help="use a scene shipped with porenet")
    p.add_argument(
        "--set",
        dest="overrides",
        action="append",
        default=[],
        metavar="KEY=VALUE",
        help="override a dotted key of the scene, e.g. --set lattice.n=64 (repeatable); "
        "an empty VALUE removes the key (its default applies)",
    )


def add_checkpoint_arg(
    p: argparse.ArgumentParser,
    default: str | None = None,
    resumed_by: str = "`porenet resume` finishes a killed run from it",
) -> None:
    p.add_argument(
        "--checkpoint-every",
        metavar="WHEN",
        help="write a checkpoint beside the run file (OUT.h5.checkpoint) every WHEN: a "
        f"duration (90s, 10m, 2h) or a number of drained pores (5000); {resumed_by}"
        + (f" (default {default})" if default else ""),
    )


def build_parser() -> argparse.ArgumentParser:
    from porenet.cli.checks import EXIT_STATUS_HELP

    parser = argparse.ArgumentParser(
        prog="porenet",
        description="Pore-scale drainage in deformable disordered media.",
        epilog=EXIT_STATUS_HELP,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("--version", action="version", version=f"porenet {__version__}")
    parser.add_argument("-v", "--verbose", action="count", default=0, help="more logging")
    parser.add_argument("--traceback", action="store_true", help="show tracebacks on errors")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")

    p = sub.add_parser("run", help="run a scene and write a run file")
    add_scene_args(p)
    p.add_argument("-o", "--output", help="run file to write (default: SCENE_STEM.h5); an "
                   "existing porenet run file there is replaced, any other file only with "
                   "--overwrite")  # fmt: skip
    p.add_argument("--overwrite", action="store_true",
                   help="replace the -o file even if it is not a porenet run file")  # fmt: skip
    p.add_argument("--plot", metavar="PNG", help="also save the pattern as a picture")
    p.add_argument(
        "--ignore-memory",
        action="store_true",
        help="run even if the plan's memory estimate exceeds the memory available "
        "(otherwise refused with exit status 2 before anything is allocated)",
    )
    p.add_argument("-q", "--quiet", action="store_true", help="print nothing on success")
    p.add_argument(
        "--threads",
        metavar="N",
        help="threads of the parallel kernels: a number, or 'auto' (the default: the run "
        "measures itself on 1 thread and on every core and keeps the faster); results do "
        "not depend on it",
    )
    add_checkpoint_arg(p)

    p = sub.add_parser(
        "resume",
        help="finish a run from its checkpoint (porenet run --checkpoint-every)",
        description="Go on with a run from the checkpoint it left (OUT.h5.checkpoint) and "
        "write its run file: the result is the one the uninterrupted run gives, to the bit "
        '(docs/run-file.md, "Checkpoints"). The checkpoint is removed when the run ends.',
    )
    p.add_argument("checkpoint", help="checkpoint file (OUT.h5.checkpoint)")
    p.add_argument("-o", "--output", help="run file to write (default: the run's own -o)")
    p.add_argument("--overwrite", action="store_true",
                   help="replace the -o file even if it is not a porenet run file")  # fmt: skip
    p.add_argument("--plot", metavar="PNG", help="also save the pattern as a picture")
    p.add_argument("-q", "--quiet", action="store_true", help="print nothing on success")
    p.add_argument("--threads", metavar="N", help="as for `porenet run`")
    add_checkpoint_arg(p, default="10m")

    p = sub.add_parser(
        "compile",
        help="compile every kernel now (once per machine; e.g. for a cluster or a container)",
        description="Compile (or load from numba's cache) every kernel of porenet's built-in "
        "models by running tiny scenes, so that no later run on this machine compiles.",
    )
    p.add_argument(
        "--jobs",
        type=int,
        metavar="N",
        help="compile in N processes at once (default 1; the cores to spare)",
    )
    p.add_argument("-q", "--quiet", action="store_true", help="print nothing on success")

    p = sub.add_parser("validate", help="check a scene without running it")
    add_scene_args(p)
    p.add_argument("--show", action="store_true", help="print the validated scene as JSON")

    p = sub.add_parser("plan", help="show the effects and models a scene calls for")
    add_scene_args(p)

    p = sub.add_parser("plugins", help="list every registered kind and its package")
    p.add_argument("--json", action="store_true", help="machine-readable output")

    p = sub.add_parser(
        "plot",
        help="draw a figure of a run file (pattern, pressure, fractal fit, mechanics, ...)",
        description="Draw a figure of a run file. Kinds:\n"
        + "\n".join(f"  {k:<11} {d}" for k, d in PLOT_KIND_DESCRIPTIONS.items()),
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("runfile", help="run file (HDF5)")
    p.add_argument(
        "-k",
        "--kind",
        choices=list(PLOT_KIND_DESCRIPTIONS),
        metavar="KIND",
        help=f"what to draw: {', '.join(PLOT_KIND_DESCRIPTIONS)} (default pattern; see above)",
    )
    p.add_argument(
        "-o",
        "--output",
        help="picture to write, format from the suffix: png, pdf, svg, ... "
        "(default: RUNFILE.png for the pattern, RUNFILE-KIND.png otherwise)",
    )
    p.add_argument(
        "--dpi", type=float, help="resolution in dots per inch, a positive number (default 300)"
    )
    p.add_argument("--pressure", action="store_true", help="same as --kind pressure")

    p = sub.add_parser("classify", help="label a run's pattern (CF, VF, FR, ...) and store it")
    p.add_argument("runfile", help="run file (HDF5)")
    p.add_argument(
        "--classifier",
        metavar="KIND",
        help="classifier kind (default: the run's, else rules); see `porenet plugins`",
    )
    p.add_argument(
        "--no-store", action="store_true", help="print only; leave the run file unchanged"
    )
    p.add_argument("--json", action="store_true", help="machine-readable output")

    p = sub.add_parser(
        "export",
        help="write an XDMF file for ParaView that points into a run file",
        description="Write RUN.xdmf beside the run file: pores as points, throats as cells, "
        "the per-pore and per-throat fields, snapshots as time steps. It points into the "
        "run file (nothing numeric is copied); booleans, the drain index and flat views of "
        "grid-shaped fields go into a small sidecar, RUN.xdmf.h5. Open it with `paraview "
        'RUN.xdmf` (docs/run-file.md, "ParaView (XDMF export)").',
    )
    p.add_argument("runfile", help="run file (HDF5); only read")
    p.add_argument(
        "--format", choices=["xdmf"], default="xdmf", help="what to write (default xdmf)"
    )
    p.add_argument(
        "-o",
        "--output",
        help="XDMF file to write (default: RUNFILE with the suffix .xdmf, beside it); its "
        "sidecar is OUTPUT.h5. Files porenet export wrote are replaced, others only with "
        "--overwrite",
    )
    p.add_argument(
        "--overwrite",
        action="store_true",
        help="replace the -o file and its sidecar even if porenet export did not write them",
    )

    p = sub.add_parser(
        "phase-diagram",
        help="draw a sweep's regimes on Ca-lambda (rigid) or N_f-Ca* (deformable) axes",
    )
    p.add_argument("dir", metavar="DIR", help="output directory of `porenet sweep`")
    p.add_argument("-o", "--output", required=True, help="picture to write (png, pdf, svg, ...)")
    p.add_argument(
        "--axes",
        choices=["auto", "ca-lambda", "nf-castar"],
        default="auto",
        help="ca-lambda: x = lambda, y = Ca (Fig. 2); nf-castar: x = Ca*, y = N_f (Fig. 3); "
        "auto: nf-castar when the sweep has a fracturing number (default)",
    )
    p.add_argument("--table", metavar="MD", help="also write the points as a markdown table")
    p.add_argument(
        "--dpi", type=float, help="resolution in dots per inch, a positive number (default 300)"
    )

    p = sub.add_parser(
        "sweep",
        help="run many scenes from a sweep file (resumable; local processes or dask)",
        description="Run every point x replicate of SWEEP.toml into DIR (docs/sweeps.md): "
        "DIR/runs/*.h5, DIR/summary.csv, DIR/sweep.json. Re-running the same command resumes; "
        "a failing run is recorded and the sweep goes on.",
    )
    p.add_argument("sweep", metavar="SWEEP.toml", help="sweep file (TOML)")
    p.add_argument("-o", "--output", required=True, metavar="DIR", help="output directory")
    p.add_argument(
        "--workers",
        type=int,
        metavar="N",
        help="parallel runs: local processes, or the LocalCluster's workers with --dask-local "
        "(default: the number of CPUs, at most the runs to do; 1 runs in this process)",
    )
    where = p.add_mutually_exclusive_group()
    where.add_argument(
        "--scheduler", metavar="ADDRESS", help="submit to a dask.distributed scheduler"
    )
    where.add_argument(
        "--dask-local", action="store_true", help="start a dask LocalCluster and use it"
    )
    p.add_argument(
        "--retry-failed", action="store_true", help="run again the runs that failed before"
    )
    add_checkpoint_arg(
        p, resumed_by="re-running the sweep goes on with each killed run from its checkpoint"
    )
    p.add_argument(
        "-q", "--quiet", action="store_true", help="no progress and no final line on success"
    )

    p = sub.add_parser("schema", help="print the scene's JSON Schema (for editors)")
    return parser
