"""The n = 400 frictional study's records and reports, for ``fracture_shear.py``.

A record is one finished run (a JSON line, :data:`POINT` its identity); this module reads the
records files (:func:`read_records`) and writes what ``fracture_shear.py`` reports from them
without running anything: the table per point (:func:`write_table`), every run per N_f
(:func:`write_by_nf`), the study's status (:func:`write_status`), what sliding costs
against the cost model (:func:`write_sliding_cost`) and the figure of D_f against N_f
(:func:`draw`). The runs themselves, checkpoints and pattern figures stay in
``fracture_shear.py``.
"""

from __future__ import annotations

import argparse
import itertools
import json
import statistics
from collections.abc import Callable, Iterator
from pathlib import Path

from fig5 import LAMBDA

from porenet.kinds.mindlin.cost import MINDLIN_SLIDING, sliding_factor
from porenet.kinds.viscous.cost import fracture_weight

#: The shape of a run that a table row averages over its seeds.
KEYS = ("d_f", "drained", "removed", "straight", "segment")

#: ``--skip-settled``: a point's runs found the same pattern when they opened the same number
#: of springs and their D_f differ by at most this much.
SETTLED_D_F = 1e-3

#: What identifies a run in the records.
POINT = ("n", "ratio", "friction", "rotation", "solver_tolerance", "nf", "seed")


def planned(args: argparse.Namespace, frictions: list[float | None]) -> Iterator[tuple]:
    """The study's points, (K_t/K_n, friction, N_f), in the order of its tables."""
    return itertools.product(args.ratio, frictions, args.nf)


def point_key(args: argparse.Namespace, ratio: float, friction: float | None, nf: float,
              seed: int) -> tuple:  # fmt: skip
    """A run's identity in the records (the fields of :data:`POINT`)."""
    return (args.n, ratio, friction, args.rotation, args.solver_tolerance, nf, seed)


def settled(runs: list[dict]) -> bool:
    """Whether a point's runs (two or more seeds) found the same fracture: the same number of
    springs opened, at least one, and D_f within :data:`SETTLED_D_F` (``--skip-settled``).
    Below the crossover no spring opens and every seed fingers differently, whatever its D_f
    (two seeds at N_f = 0.3 agreed to 1e-3 by chance where a third differed by 0.024), so
    there a third seed is always due."""
    d_f = [r["d_f"] for r in runs]
    return (
        len(runs) >= 2
        and len({r["removed"] for r in runs}) == 1
        and runs[0]["removed"] > 0
        and (max(d_f) - min(d_f) <= SETTLED_D_F)
    )


def write_status(done: dict, args: argparse.Namespace, frictions: list[float | None]) -> None:
    """``--status``: the planned study's runs found in the records and those missing, each
    missing one priced at the mean CPU time of the recorded runs at its point (its setting
    and N_f), else at the same sliding and N_f with another K_t/K_n, else (with sliding) at
    the runs without sliding at its K_t/K_n and N_f (or another K_t/K_n) times what the cost
    model says sliding multiplies an update's cost by
    (:func:`porenet.kinds.mindlin.cost.sliding_factor`), else unknown. With ``--skip-settled`` a
    seed after the ones that settled its point is listed as settled, neither missing nor priced."""

    def cpu_at(**match: float | str | None) -> list[float]:
        match |= {"n": args.n, "rotation": args.rotation,
                  "solver_tolerance": args.solver_tolerance}  # fmt: skip
        return [cpu_of(r) for r in done.values() if all(r[k] == v for k, v in match.items())]

    def price(ratio: float, friction: float | None, nf: float) -> float | None:
        cpu = cpu_at(ratio=ratio, friction=friction, nf=nf) or cpu_at(friction=friction, nf=nf)
        if cpu:
            return statistics.fmean(cpu)
        if friction is None:
            return None
        cpu = cpu_at(ratio=ratio, friction=None, nf=nf) or cpu_at(friction=None, nf=nf)
        return statistics.fmean(cpu) * sliding_factor(ratio, fracture_weight(nf)) if cpu else None

    lines = [
        f"The study at n = {args.n} (rotations {args.rotation}{tolerance_label(args)}): the "
        "runs that --ratio, --friction, --nf and --seeds plan, those in the records and the "
        "CPU time of those missing (`python examples/scripts/fracture_shear.py --status`; a "
        "missing run is priced at its point's recorded mean, else at the same sliding and "
        "N_f with another K_t/K_n, else with sliding at the runs without it times the cost "
        "model's factor for sliding, docs/cost.md; one thread a run"
        + (
            "; a seed after two that found the same pattern is settled, not run"
            if args.skip_settled
            else ""
        )
        + ").",
        "",
        "| K_t/K_n | sliding | N_f | seeds done | seeds missing | seeds settled | CPU done (s) "
        "| CPU missing (s, estimate) |",
        "|---|---|---|---|---|---|---|---|",
    ]
    spent = todo = 0.0
    n_done = n_missing = n_settled = unpriced = 0
    for ratio, friction, nf in planned(args, frictions):
        have, missing, skipped, here = [], [], [], 0.0
        for seed in args.seeds:
            key = point_key(args, ratio, friction, nf, seed)
            runs = [done[point_key(args, ratio, friction, nf, s)] for s in have]
            if key in done:
                have.append(seed)
                here += cpu_of(done[key])
            elif args.skip_settled and settled(runs):
                skipped.append(seed)
            else:
                missing.append(seed)
        each = price(ratio, friction, nf) if missing else None
        cost = each * len(missing) if each is not None else 0.0
        if missing and each is None:
            unpriced += len(missing)
        spent += here
        todo += cost
        n_done, n_missing = n_done + len(have), n_missing + len(missing)
        n_settled += len(skipped)
        estimate = "unknown" if missing and each is None else f"{cost:.0f}" if missing else ""
        lines.append(
            f"| {ratio:g} | {friction_label(friction)} | {nf:g} | "
            f"{','.join(map(str, have)) or '-'} | {','.join(map(str, missing)) or '-'} "
            f"| {','.join(map(str, skipped)) or '-'} | {here:.0f} | {estimate} |"
        )
    summary = (
        f"{n_done} of {n_done + n_missing + n_settled} runs done ({spent / 3600:.1f} h of CPU); "
        f"{n_missing} missing, ~{todo / 3600:.1f} h of CPU"
        + (f" plus {unpriced} with no recorded run to price them by" if unpriced else "")
        + (f"; {n_settled} settled (not run)" if n_settled else "")
    )
    args.status.write_text("\n".join([*lines, "", summary]) + "\n")
    print(summary)
    print(f"status: {args.status}")


def aggregate(runs: list[dict], **point: float | None) -> dict:
    """Mean and standard deviation over seeds of :data:`KEYS`, the mean wall and CPU time,
    the seeds, the most sliding contacts and the codes that made the runs."""
    row = dict(point)
    for key in KEYS:
        values = [r[key] for r in runs]
        row[key] = statistics.fmean(values)
        row[key + "_sd"] = statistics.pstdev(values) if len(values) > 1 else 0.0
    row["wall"] = statistics.fmean(r["wall"] for r in runs)
    row["cpu"] = statistics.fmean(cpu_of(r) for r in runs)
    row["seeds"] = ",".join(str(r["seed"]) for r in runs)
    row["sliding"] = max(r["sliding"] for r in runs)
    # the code of each run, in seed order ("-": a record made before records named it)
    row["code"] = ",".join(dict.fromkeys(r.get("code", "-") for r in runs))
    return row


def cpu_of(record: dict) -> float:
    """A run's CPU time (s); its wall time in records made before CPU time was kept (one
    thread: the same unless the run was paused or shared a core)."""
    return record.get("cpu", record["wall"])


def friction_label(friction: float | None) -> str:
    return "no sliding" if friction is None else f"mu = {friction:g}"


def line_of(r: dict) -> str:
    return (f"K_t/K_n {r['ratio']:<4g} {friction_label(r['friction']):<10} N_f {r['nf']:<5g} "
            f"D_f {r['d_f']:.3f} +- {r['d_f_sd']:.3f}  drained {r['drained']:7.0f}  removed "
            f"{r['removed']:6.0f}  straight {r['straight']:5.0f}  segment {r['segment']:5.1f}  "
            f"{r['wall']:6.1f} s/run  seeds {r['seeds']}")  # fmt: skip


def tolerance_label(args: argparse.Namespace) -> str:
    """``, solver_tolerance T a`` when ``--solver-tolerance`` is given, else nothing."""
    tol = args.solver_tolerance
    return "" if tol is None else f", solver_tolerance {tol:g} a"


def write_table(rows: list[dict], args: argparse.Namespace) -> None:
    lines = [
        f"n = {args.n}, lambda = {LAMBDA}, Ca* = 10, solid kind hertz-mindlin (rotations "
        f"{args.rotation}{tolerance_label(args)}), to breakthrough; mean +- standard "
        "deviation over the seeds of each row, CPU time of one run on one thread (`python "
        "examples/scripts/fracture_shear.py`).",
        "",
        "| K_t/K_n | sliding | N_f | D_f (mass-radius) | drained pores | springs removed | "
        "longest straight run | mean straight segment | most sliding contacts | CPU (s/run) | "
        "seeds | code |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    lines += [
        f"| {r['ratio']:g} | {friction_label(r['friction'])} | {r['nf']:g} | {r['d_f']:.3f} +- "
        f"{r['d_f_sd']:.3f} | {r['drained']:.0f} | {r['removed']:.0f} | {r['straight']:.0f} | "
        f"{r['segment']:.1f} | {r['sliding']} | {r['cpu']:.1f} | {r['seeds']} | {r['code']} |"
        for r in rows
    ]
    args.table.write_text("\n".join(lines) + "\n")
    print(f"table: {args.table}")


def write_by_nf(runs: list[dict], args: argparse.Namespace) -> None:
    """``--by-nf``: the runs of every K_t/K_n together, per sliding setting and N_f: whether
    any setting comes near a D_f, whatever its stiffness ratio."""

    def span(values: list[float], digits: int) -> str:
        lo, hi = min(values), max(values)
        return f"{lo:.{digits}f}" if lo == hi else f"{lo:.{digits}f}-{hi:.{digits}f}"

    lines = [
        f"n = {args.n} (rotations {args.rotation}{tolerance_label(args)}): every run of the "
        "records at each N_f, all K_t/K_n together, one line per sliding setting (`python "
        "examples/scripts/fracture_shear.py --by-nf`).",
        "",
        "| sliding | N_f | runs | K_t/K_n | D_f (lowest-highest) | springs opened | drained "
        "pores |",
        "|---|---|---|---|---|---|---|",
    ]
    settings = sorted({(r["friction"] is not None, r["friction"] or 0.0, r["nf"]) for r in runs})
    for sliding, friction, nf in settings:
        here = [r for r in runs if (r["friction"] is not None) == sliding
                and (r["friction"] or 0.0) == friction and r["nf"] == nf]  # fmt: skip
        ratios = ", ".join(f"{x:g}" for x in sorted({r["ratio"] for r in here}))
        lines.append(
            f"| {friction_label(here[0]['friction'])} | {nf:g} | {len(here)} | {ratios} | "
            f"{span([r['d_f'] for r in here], 3)} | {span([r['removed'] for r in here], 0)} | "
            f"{span([r['drained'] for r in here], 0)} |"
        )
    args.by_nf.write_text("\n".join(lines) + "\n")
    print(f"table: {args.by_nf}")


def draw(rows: list[dict], n: int, out: Path) -> None:
    """D_f against N_f, one curve per stiffness ratio, one panel per sliding setting."""
    from matplotlib.figure import Figure

    from porenet.viz.pattern import save_figure

    frictions = list(dict.fromkeys(r["friction"] for r in rows))
    fig = Figure(figsize=(4.5 * len(frictions), 3.6), dpi=130, layout="constrained")
    axes = fig.subplots(1, len(frictions), sharey=True, squeeze=False)[0]
    for ax, friction in zip(axes, frictions, strict=True):
        for i, ratio in enumerate(dict.fromkeys(r["ratio"] for r in rows)):
            mine = [r for r in rows if r["ratio"] == ratio and r["friction"] == friction]
            ax.errorbar([r["nf"] for r in mine], [r["d_f"] for r in mine],
                        yerr=[r["d_f_sd"] for r in mine], marker="o", ms=4, capsize=2,
                        color=f"C{i}", label=f"K_t/K_n = {ratio:g}")  # fmt: skip
        for value, name in ((1.43, "FR (paper)"), (1.64, "VF (paper)")):
            ax.axhline(value, color="k", lw=0.6, ls=":")
            ax.annotate(name, (0.02, value), xycoords=("axes fraction", "data"), fontsize=7,
                        xytext=(0, 2), textcoords="offset points")  # fmt: skip
        ax.set_xscale("log")
        ax.set_xlabel("fracturing number N_f")
        ax.set_title(friction_label(friction), fontsize=9)
    axes[0].set_ylabel("D_f (mass-radius)")
    axes[0].legend(fontsize=7, loc="lower left")
    fig.suptitle(f"Fig. 5's scene at n = {n} with hertz-mindlin contacts", fontsize=10)
    save_figure(fig, out)


class RecordError(ValueError):
    """A records file holds a line that is not a run's record (the message names the file
    and line)."""


def read_records(paths: list[Path]) -> dict[tuple, dict]:
    """Every run of the records files ``paths`` (missing files are skipped), keyed by its
    identity (:data:`POINT`); where two records share one, the later counts.

    Raises
    ------
    RecordError
        A line is not a run's record: a process killed while writing leaves such a line.
    """
    done: dict[tuple, dict] = {}
    for records in paths:
        if not records.exists():
            continue
        for number, line in enumerate(records.read_text().splitlines(), 1):
            if not line.strip():
                continue
            try:
                rec = {"rotation": "held", "solver_tolerance": None, **json.loads(line)}
                done[tuple(rec[k] for k in POINT)] = rec
            except (json.JSONDecodeError, TypeError, KeyError) as exc:
                why = (exc.msg if isinstance(exc, json.JSONDecodeError)
                       else f"no {exc.args[0]!r} field" if isinstance(exc, KeyError)
                       else "not a JSON object")  # fmt: skip
                raise RecordError(
                    f"{records}, line {number}: not a run's record ({why}); a process killed "
                    "while writing leaves such a line: delete it, and its run is made again"
                ) from None
    return done


def write_sliding_cost(done: dict[tuple, dict], out: Path,
                       model_ratio: Callable[[dict], float]) -> None:  # fmt: skip
    """``--sliding-cost``: every run with sliding beside the run without it at the same
    point and seed (same n, K_t/K_n, rotation, solver tolerance, N_f): their CPU times, the
    ratio, what the cost model estimates that ratio to be (``model_ratio(record)``: its
    whole-run estimate with sliding over the one without, of which only the mechanics carry
    the factor ``1 + c sqrt(K_t/K_n) w``, :func:`porenet.kinds.mindlin.cost.sliding_factor`) and the
    codes that made the two. Below the table, the constant ``c`` fitted to the points the
    model says sliding makes dearer (above the crossover): the model's ratio is ``1 + c x``
    with ``x`` from its ratio at today's constant, and the c that keeps the worst point's
    median ratio over its seeds closest is :func:`fit_sliding_constant`'s; with it, how far
    the worst single pair is off. The median, not each pair: the model sees a point, not a
    seed, and one seed's run can cost ~1.4x another's at the same point (K_t/K_n 0.8 at
    N_f = 3: 1.52x to 2.10x; the 1.52x pair's run without sliding made twice, to the last
    digit, in 517 and 526 s), so a fit to the worst pair is set by the seeds' spread
    (decision in docs/fracture-shear-n400.md, "What sliding costs")."""
    pairs = []
    for rec in done.values():
        if rec["friction"] is None:
            continue
        key = tuple(None if k == "friction" else rec[k] for k in POINT)
        if key in done:
            pairs.append((rec, done[key]))
    pairs.sort(key=lambda p: (p[0]["n"], p[0]["ratio"], p[0]["friction"], p[0]["nf"],
                              p[0]["seed"]))  # fmt: skip
    lines = [
        "Each run with sliding beside the same run without it (same point and seed; `python "
        "examples/scripts/fracture_shear.py --sliding-cost`): CPU time of one thread, their "
        "ratio and the cost model's estimate of it (`porenet plan`'s wall time with sliding "
        "over without; only the mechanics carry the factor `1 + c sqrt(K_t/K_n) w`, docs/cost.md, "
        f"c = {MINDLIN_SLIDING:g}); code: the commits that made the two runs ('-': a record "
        "made before records named it).",
        "",
        "| n | K_t/K_n | sliding | N_f | seed | CPU without (s) | CPU with (s) | ratio | cost "
        "model | code (without, with) |",
        "|---|---|---|---|---|---|---|---|---|---|",
    ]
    fits: dict[tuple, tuple[float, list[float]]] = {}  # a point: its x, its seeds' ratios
    for slide, stick in pairs:
        ratio, model = cpu_of(slide) / cpu_of(stick), model_ratio(slide)
        if model > 1:
            point = tuple(slide[k] for k in POINT if k != "seed")
            fits.setdefault(point, ((model - 1) / MINDLIN_SLIDING, []))[1].append(ratio)
        lines.append(
            f"| {slide['n']} | {slide['ratio']:g} | {friction_label(slide['friction'])} | "
            f"{slide['nf']:g} | {slide['seed']} | {cpu_of(stick):.0f} | {cpu_of(slide):.0f} | "
            f"{ratio:.2f} | {model:.2f} | "
            f"{stick.get('code', '-')}, {slide.get('code', '-')} |"
        )
    if fits:
        c, worst = fit_sliding_constant([(x, statistics.median(r)) for x, r in fits.values()])
        worst_pair = worst_factor([(x, one) for x, r in fits.values() for one in r], c)
        above = sum(len(r) for _, r in fits.values())
        points = f"{len(fits)} point" + ("s" if len(fits) != 1 else "")
        summary = (
            f"{len(pairs)} pairs; c fitted to the medians over the seeds of the {points} "
            f"above the crossover ({above} pairs): c = {c:.2f}, every point's median "
            f"within {worst:.2f}x of the model's estimate, every pair within {worst_pair:.2f}x"
        )
    else:
        summary = f"{len(pairs)} pairs; none above the crossover to fit c by"
    out.write_text("\n".join([*lines, "", summary]) + "\n")
    print(summary)
    print(f"sliding cost: {out}")


def worst_factor(points: list[tuple[float, float]], c: float) -> float:
    """The largest factor between the cost model's sliding ratio ``1 + c x`` and the measured
    one over ``points`` (``(x, measured ratio)``), either way."""
    return max(max(m / (1 + c * x), (1 + c * x) / m) for x, m in points)


def fit_sliding_constant(points: list[tuple[float, float]]) -> tuple[float, float]:
    """The constant ``c >= 0`` of the cost model's sliding ratio ``1 + c x`` that makes
    :func:`worst_factor` over ``points`` (``(x, measured ratio)``) smallest, and that
    factor: an estimate for planning runs should be off by as little as possible at its
    worst, not on average. Found by scanning ``c`` in steps of 0.01 up to twice the largest
    single-point fit (the worst factor is piecewise monotone in ``c``, so the scan is within
    a step of the optimum)."""
    top = 2 * max(max(m - 1, 0.0) / x for x, m in points) + 0.01
    grid = [i / 100 for i in range(int(top * 100) + 1)]
    best = min(grid, key=lambda c: worst_factor(points, c))
    return best, worst_factor(points, best)
