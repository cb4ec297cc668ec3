"""Every example scene in examples/scenes validates (plugin scenes when the plugin loads), and the
example scripts run; the fracture study's bookkeeping (its script's records, resumption and
the tables of its page) is marked ``study``: ``pytest -m study`` runs it (docs/verification.md)."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

from porenet.config.loading import load_scene, read_toml
from porenet.hooks import build_registry

#: The example scripts (they import each other by name, as when run from their folder).
SCRIPTS = Path(__file__).resolve().parents[2] / "examples" / "scripts"

SCENES = sorted((Path(__file__).resolve().parents[2] / "examples" / "scenes").glob("*.toml"))


@pytest.mark.parametrize("path", SCENES, ids=[p.stem for p in SCENES])
def test_example_scene_validates(path):
    registry = build_registry()
    kind = read_toml(path)["lattice"].get("kind", "square")
    if ("lattice", kind) not in registry:
        import sys

        sys.path.insert(0, str(path.parents[2] / "plugins" / "porenet-correlated" / "src"))
        import porenet_correlated.plugin

        registry = build_registry(extra_plugins={"correlated": porenet_correlated.plugin})
    load_scene(path, registry=registry)


def test_fig5_script_runs_on_a_small_lattice(tmp_path):
    import subprocess
    import sys

    script = SCRIPTS / "fig5.py"
    table = tmp_path / "fig5.md"
    out = subprocess.run(
        [sys.executable, str(script), "--n", "20", "--nf", "10", "0.01", "--table", str(table)],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert out.returncode == 0, out.stderr
    assert "N_f = 10" in out.stdout and "rigid" in out.stdout
    assert table.read_text().count("\n| ") == 4  # the header row and three runs


def test_accuracy_seeds_script_runs_on_a_small_lattice(tmp_path):
    import subprocess
    import sys

    script = SCRIPTS / "accuracy_seeds.py"
    table = tmp_path / "seeds.md"
    args = ["--n", "12", "--ca", "1e-4", "--seeds", "1", "--table", str(table)]
    out = subprocess.run(
        [sys.executable, str(script), *args], capture_output=True, text=True, timeout=300
    )
    assert out.returncode == 0, out.stderr
    rows = [line for line in table.read_text().splitlines() if line.startswith("| ")]
    assert len(rows) == 1 + 5  # the header and every setting
    assert "| explicit, tight (reference) | 1.000 | 1.000 | 0.00e+00 |" in table.read_text()


def _scripts_importable() -> None:
    """Make :data:`SCRIPTS` importable (once on ``sys.path``, however many tests ask)."""
    import sys

    if str(SCRIPTS) not in sys.path:
        sys.path.insert(0, str(SCRIPTS))


def _script(name: str, *args: str) -> str:
    import subprocess
    import sys

    script = SCRIPTS / name
    out = subprocess.run(
        [sys.executable, str(script), *args], capture_output=True, text=True, timeout=300
    )
    assert out.returncode == 0, out.stderr
    return out.stdout


@pytest.mark.study
def test_fracture_shear_script_runs_and_resumes(tmp_path):
    records, table = tmp_path / "runs.jsonl", tmp_path / "shear.md"
    args = ["--n", "16", "--ratio", "0.5", "--friction", "none", "--nf", "10", "--seeds", "1",
            "--records", str(records), "--table", str(table)]  # fmt: skip
    first = _script("fracture_shear.py", *args)
    assert "K_t/K_n 0.5" in first and len(records.read_text().splitlines()) == 1
    again = _script("fracture_shear.py", *args)  # every run recorded: none runs again
    assert len(records.read_text().splitlines()) == 1
    assert again.splitlines()[0] == first.splitlines()[0]
    assert table.read_text().count("\n| 0.5 | no sliding | 10 |") == 1
    # a new run's record goes on a line of its own even after an edit dropped the last newline
    records.write_text(records.read_text().rstrip("\n"))
    _script("fracture_shear.py", *args[:7], "10", "3", *args[8:])
    assert [json.loads(line)["nf"] for line in records.read_text().splitlines()] == [10.0, 3.0]
    # each record names the code that made it: the imported porenet's commit (``+dirty`` if
    # porenet/ or examples/ differ from it, the script's commit after it if that differs), or
    # the package's version outside a git checkout
    code = json.loads(records.read_text().splitlines()[0])["code"]
    assert re.fullmatch(r"porenet \S+|[0-9a-f]{7}(\+dirty)?( script [0-9a-f]{7})?", code), code


@pytest.mark.study
def test_fracture_shear_status_lists_the_missing_runs_and_prices_them(tmp_path):
    # a study at n = 400 spans sessions: --status says what the records hold and what is left
    point = {
        "n": 400,
        "ratio": 0.5,
        "friction": None,
        "rotation": "held",
        "d_f": 1.0,
        "drained": 700,
        "removed": 790,
        "straight": 398,
        "segment": 190.0,
        "sliding": 0,
    }
    records, status = tmp_path / "r.jsonl", tmp_path / "status.md"
    lines = [
        point | {"nf": 1.0, "seed": 1, "cpu": 300.0, "wall": 500.0},
        point | {"nf": 1.0, "seed": 2, "wall": 100.0},  # made before CPU was recorded
        point | {"ratio": 0.8, "nf": 3.0, "seed": 1, "cpu": 900.0, "wall": 950.0},
    ]
    records.write_text("".join(json.dumps(line) + "\n" for line in lines))
    out = _script("fracture_shear.py", "--n", "400", "--ratio", "0.5", "--friction", "none",
                  "--nf", "1", "3", "10", "--seeds", "1", "2", "--records", str(records),
                  "--status", str(status))  # fmt: skip
    rows = status.read_text().splitlines()
    assert "| 0.5 | no sliding | 1 | 1,2 | - | - | 400 |  |" in rows
    assert "| 0.5 | no sliding | 3 | - | 1,2 | - | 0 | 1800 |" in rows  # priced at K_t/K_n = 0.8
    assert "| 0.5 | no sliding | 10 | - | 1,2 | - | 0 | unknown |" in rows
    assert out.startswith("2 of 6 runs done (0.1 h of CPU); 4 missing, ~0.5 h of CPU plus 2 ")
    assert records.read_text().count("\n") == 3  # nothing ran


@pytest.mark.study
def test_fracture_shear_status_prices_sliding_by_the_cost_model_and_skips_settled_seeds(
    tmp_path,
):
    # with sliding and no run at that N_f yet: the run without sliding times the cost model's
    # factor; with --skip-settled a third seed after two that found the same cross is not due
    from porenet.kinds.mindlin.cost import MINDLIN_SLIDING, sliding_factor
    from porenet.kinds.viscous.cost import fracture_weight

    cross = {"n": 400, "ratio": 0.5, "friction": None, "rotation": "held", "nf": 10.0,
             "d_f": 1.0111, "drained": 790, "removed": 798, "straight": 398, "segment": 197.0,
             "sliding": 0, "wall": 1100.0}  # fmt: skip
    finger = cross | {"nf": 0.3, "removed": 0}
    lines = [cross | {"seed": 1, "cpu": 1000.0}, cross | {"seed": 2, "cpu": 1200.0,
                                                          "d_f": 1.0115, "drained": 789},
             finger | {"seed": 1, "cpu": 900.0, "d_f": 1.69},
             finger | {"seed": 2, "cpu": 900.0, "d_f": 1.6905}]  # fmt: skip
    records, status = tmp_path / "r.jsonl", tmp_path / "status.md"
    records.write_text("".join(json.dumps(line) + "\n" for line in lines))
    args = ["--n", "400", "--ratio", "0.5", "--nf", "0.3", "10", "--records", str(records),
            "--status", str(status)]  # fmt: skip
    out = _script("fracture_shear.py", *args, "--friction", "none", "0.3", "--skip-settled")
    rows = status.read_text().splitlines()
    assert "| 0.5 | no sliding | 10 | 1,2 | - | 3 | 2200 |  |" in rows  # settled: same cross
    # fingering: no spring opened, so never settled, even with D_f within SETTLED_D_F
    assert "| 0.5 | no sliding | 0.3 | 1,2 | 3 | - | 1800 | 900 |" in rows
    factor = sliding_factor(0.5, fracture_weight(10.0))
    assert factor == pytest.approx(1 + 0.5**0.5 * MINDLIN_SLIDING)  # w = 1 at N_f = 10
    assert f"| 0.5 | mu = 0.3 | 10 | - | 1,2,3 | - | 0 | {3 * 1100.0 * factor:.0f} |" in rows
    assert out.startswith("4 of 12 runs done") and "; 1 settled (not run)" in out
    # without the flag the third seed is missing, as before
    _script("fracture_shear.py", *args, "--friction", "none")
    assert "| 0.5 | no sliding | 10 | 1,2 | 3 | - | 2200 | 1100 |" in status.read_text()
    # and a study run with the flag does not make the settled point's third seed
    made = _script("fracture_shear.py", "--n", "400", "--ratio", "0.5", "--friction", "none",
                   "--nf", "10", "--records", str(records), "--skip-settled")  # fmt: skip
    assert "N_f 10: seed 3 not run (seeds 1,2 settled it)" in made
    assert records.read_text().count("\n") == 4
    # --by-nf: every run at an N_f together, whatever its K_t/K_n
    by_nf = tmp_path / "by-nf.md"
    other = cross | {"ratio": 0.8, "seed": 1, "d_f": 1.05}
    records.write_text(records.read_text() + json.dumps(other) + "\n")
    _script("fracture_shear.py", "--n", "400", "--ratio", "0.5", "0.8", "--friction", "none",
            "--nf", "0.3", "10", "--records", str(records), "--no-run",
            "--by-nf", str(by_nf))  # fmt: skip
    rows = by_nf.read_text().splitlines()
    assert "| no sliding | 0.3 | 2 | 0.5 | 1.690-1.690 | 0 | 790 |" in rows
    assert "| no sliding | 10 | 3 | 0.5, 0.8 | 1.011-1.050 | 798 | 789-790 |" in rows


@pytest.mark.study
def test_fracture_shear_sliding_cost_pairs_runs_and_fits_the_cost_model(tmp_path):
    # each run with sliding beside the same point and seed without it, against the cost
    # model's whole-run estimate of that ratio; c fitted to keep the worst pair closest
    from porenet.core.cost import estimate_cost
    from porenet.kinds.mindlin.cost import MINDLIN_SLIDING

    _scripts_importable()
    from fig5 import make_scene

    def model(ratio: float, nf: float) -> float:  # porenet plan's estimate, with over without
        solid = {"kind": "hertz-mindlin", "shear_stiffness_ratio": ratio, "rotation": "held"}
        walls = [estimate_cost(load_scene(make_scene(400, nf, seed=1, solid=solid | extra)))
                 .wall_seconds for extra in ({"friction": 0.3}, {})]  # fmt: skip
        return walls[0] / walls[1]

    # the runs with sliding cost exactly what the model says with c = 2 in place of its own
    exact = {p: 1 + 2 * (model(*p) - 1) / MINDLIN_SLIDING for p in [(0.1, 10.0), (0.8, 3.0)]}
    run = {"n": 400, "rotation": "held", "d_f": 1.01, "drained": 790, "removed": 798,
           "straight": 398, "segment": 197.0, "sliding": 0, "wall": 1.0}  # fmt: skip
    lines = [
        run | {"ratio": 0.1, "friction": None, "nf": 10.0, "seed": 1, "cpu": 1000.0},
        run
        | {
            "ratio": 0.1,
            "friction": 0.3,
            "nf": 10.0,
            "seed": 1,
            "code": "abc1234",
            "cpu": 1000.0 * exact[0.1, 10.0],
        },
        run | {"ratio": 0.8, "friction": None, "nf": 3.0, "seed": 1, "cpu": 500.0},
        run
        | {
            "ratio": 0.8,
            "friction": 0.3,
            "nf": 3.0,
            "seed": 1,
            "cpu": 500.0 * exact[0.8, 3.0],
        },
        run | {"ratio": 0.8, "friction": None, "nf": 0.1, "seed": 1, "cpu": 800.0},
        run | {"ratio": 0.8, "friction": 0.3, "nf": 0.1, "seed": 1, "cpu": 840.0},
        run | {"ratio": 0.5, "friction": 0.3, "nf": 1.0, "seed": 1, "cpu": 900.0},  # alone
    ]
    records, out = tmp_path / "r.jsonl", tmp_path / "cost.md"
    records.write_text("".join(json.dumps(line) + "\n" for line in lines))
    printed = _script("fracture_shear.py", "--records", str(records), "--sliding-cost", str(out))
    rows = out.read_text().splitlines()
    first = f"| 400 | 0.1 | mu = 0.3 | 10 | 1 | 1000 | {1000 * exact[0.1, 10.0]:.0f} | "
    assert f"{first}{exact[0.1, 10.0]:.2f} | {model(0.1, 10.0):.2f} | -, abc1234 |" in rows
    # below the crossover the model says sliding costs nothing more: shown, not fitted
    assert "| 400 | 0.8 | mu = 0.3 | 0.1 | 1 | 800 | 840 | 1.05 | 1.00 | -, - |" in rows
    assert sum(row.startswith("| 400 |") for row in rows) == 3  # the lone run has no pair
    assert (
        "3 pairs; c fitted to the medians over the seeds of the 2 points above the crossover "
        "(2 pairs): c = 2.00, every point's median within 1.00x of the model's estimate, "
        "every pair within 1.00x" in printed
    )
    assert records.read_text().count("\n") == len(lines)  # nothing ran


@pytest.mark.study
def test_sliding_cost_fits_each_points_median_not_its_worst_seed(tmp_path):
    # one point, three seeds costing 1.5x, 2x and 4x: the model sees the point, not the seed,
    # so c follows the median (1 + c x = 2), and the summary says how far the seeds stray
    from porenet.kinds.mindlin.cost import MINDLIN_SLIDING

    _scripts_importable()
    from fracture_shear_tables import POINT, write_sliding_cost

    x = 0.5  # the model's (ratio - 1) / c at this point
    done = {}
    for seed, cost in [(1, 1.5), (2, 2.0), (3, 4.0)]:
        for friction, cpu in [(None, 100.0), (0.3, 100.0 * cost)]:
            rec = {"n": 400, "ratio": 0.8, "friction": friction, "rotation": "held",
                   "solver_tolerance": None, "nf": 3.0, "seed": seed, "cpu": cpu,
                   "wall": cpu}  # fmt: skip
            done[tuple(rec[k] for k in POINT)] = rec
    out = tmp_path / "cost.md"
    write_sliding_cost(done, out, lambda rec: 1 + MINDLIN_SLIDING * x)
    summary = out.read_text().splitlines()[-1]
    assert "the 1 point above the crossover (3 pairs): c = 2.00" in summary
    assert "every point's median within 1.00x" in summary
    assert "every pair within 2.00x" in summary  # the 4x seed against the model's 2x


@pytest.mark.study
@pytest.mark.parametrize(
    "flag", ["--table", "--out", "--patterns", "--by-nf", "--status", "--sliding-cost"]
)
def test_fracture_shear_names_an_output_in_a_missing_folder(tmp_path, flag):
    # before anything runs or is read: the flag and the folder named, no traceback
    import subprocess
    import sys

    script = SCRIPTS / "fracture_shear.py"
    out = subprocess.run([sys.executable, str(script), "--no-run", flag,
                          str(tmp_path / "missing" / "x.md")],
                         capture_output=True, text=True, timeout=300)  # fmt: skip
    assert out.returncode == 2 and "Traceback" not in out.stderr
    assert f"{flag} " in out.stderr and "directory does not exist" in out.stderr


@pytest.mark.study
def test_fracture_shear_names_a_broken_record_and_runs_nothing(tmp_path):
    # a run killed while its record was written leaves half a line: the study must say where,
    # not append the next record to it or raise a traceback
    import subprocess
    import sys

    records, status = tmp_path / "r.jsonl", tmp_path / "status.md"
    records.write_text('\n{"n": 400, "ratio": 0.5, "fric')
    script = SCRIPTS / "fracture_shear.py"
    out = subprocess.run([sys.executable, str(script), "--records", str(records), "--status",
                          str(status)], capture_output=True, text=True, timeout=300)  # fmt: skip
    assert out.returncode == 2 and "Traceback" not in out.stderr
    assert f"{records}, line 2: not a run's record (Unterminated string" in out.stderr
    assert not status.exists() and records.read_text().count("\n") == 1


@pytest.mark.study
def test_fracture_shear_keeps_run_files_and_draws_patterns_from_them(tmp_path):
    runs, figure = tmp_path / "runs", tmp_path / "patterns.png"
    args = ["--n", "12", "--ratio", "0.5", "--friction", "none", "--nf", "10", "--seeds", "1",
            "--records", str(tmp_path / "r.jsonl"), "--runs", str(runs)]  # fmt: skip
    first = _script("fracture_shear.py", *args)
    kept = runs / "n12-mindlin-r0.5-stick-held-nf10-s1.h5"
    assert kept.exists() and "D_f" in first
    # the pattern of the recorded run is read, not run again; the two hertz panels are run
    # (and kept) because they are not there yet
    out = _script("fracture_shear.py", *args, "--no-run", "--patterns", str(figure))
    assert f"pattern from {kept}" in out and figure.exists()
    assert sorted(p.name for p in runs.iterdir()) == [
        "n12-hertz-kf0.02-nf10-s1.h5",
        "n12-hertz-nf10-s1.h5",
        kept.name,
    ]


def _crashed_run(runs: Path, nf: float, point_nf: float) -> Path:
    """The checkpoint a study process killed mid-run leaves for the point (n = 16, K_t/K_n =
    0.5 with sliding, seed 1, N_f ``point_nf``), written by a run of Fig. 5's scene at
    ``nf`` stopped after a third of its drained pores; returns the checkpoint's path."""

    _scripts_importable()
    from fig5 import make_scene

    from porenet.io.checkpoint import checkpoint_path
    from porenet.simulation import Simulation
    from porenet.testing.runs import Killed, KilledAfterCheckpoint

    solid = {"kind": "hertz-mindlin", "shear_stiffness_ratio": 0.5, "rotation": "held",
             "friction": 0.3}  # fmt: skip
    scene = make_scene(16, nf, seed=1, solid=solid)
    drained = Simulation.from_scene(scene).run().summary["n_drained"]
    runs.mkdir()
    output = runs / f"n16-mindlin-r0.5-mu0.3-held-nf{point_nf:g}-s1.h5"
    path = checkpoint_path(output)
    with pytest.raises(Killed):
        Simulation.from_scene(scene, output=output).run(
            KilledAfterCheckpoint(path, every_drained=max(drained // 3, 1))
        )
    return path


@pytest.mark.study
def test_fracture_shear_resumes_a_killed_run_from_its_checkpoint(tmp_path):
    # a run at n = 400 takes hours: a study process killed mid-run (a session's end) leaves
    # the run's checkpoint, and the restarted study finishes that run from it, with the
    # uninterrupted run's result and the CPU time of both parts
    runs = tmp_path / "runs"
    path = _crashed_run(runs, 10.0, 10.0)
    path.with_name(path.name + ".cpu").write_text(json.dumps({"cpu_s": 1000.0}))
    point = ["--n", "16", "--ratio", "0.5", "--friction", "0.3", "--nf", "10", "--seeds", "1"]
    out = _script("fracture_shear.py", *point, "--records", str(tmp_path / "resumed.jsonl"),
                  "--runs", str(runs), "--checkpoint-every", "1")  # fmt: skip
    assert "resuming n16-mindlin-r0.5-mu0.3-held-nf10-s1.h5 at " in out
    assert "(1000 s of CPU before)" in out
    assert sorted(p.name for p in runs.iterdir()) == [path.name.removesuffix(".checkpoint")]
    _script("fracture_shear.py", *point, "--records", str(tmp_path / "straight.jsonl"))
    resumed, straight = (json.loads((tmp_path / name).read_text())
                         for name in ("resumed.jsonl", "straight.jsonl"))  # fmt: skip
    for key in ("d_f", "drained", "removed", "straight", "segment", "updates", "sliding",
                "frozen", "residual"):  # fmt: skip
        assert resumed[key] == straight[key], key
    assert resumed["cpu"] > 1000.0 > straight["cpu"]


@pytest.mark.study
def test_fracture_shear_resumes_past_a_damaged_cpu_record(tmp_path):
    # the CPU file beside a checkpoint is the script's own, written atomically; one damaged
    # by hand is named and the run still resumes, its record counting this process's CPU
    import subprocess
    import sys

    runs = tmp_path / "runs"
    path = _crashed_run(runs, 10.0, 10.0)
    cpu_file = path.with_name(path.name + ".cpu")
    cpu_file.write_text('{"cpu_s": ')
    script = SCRIPTS / "fracture_shear.py"
    out = subprocess.run(
        [sys.executable, str(script), "--n", "16", "--ratio", "0.5", "--friction", "0.3",
         "--nf", "10", "--seeds", "1", "--records", str(tmp_path / "r.jsonl"), "--runs",
         str(runs)],
        capture_output=True, text=True, timeout=300,
    )  # fmt: skip
    assert out.returncode == 0 and "Traceback" not in out.stderr, out.stderr
    assert f"{cpu_file}: not a CPU time record" in out.stderr
    assert "(0 s of CPU before)" in out.stdout and not cpu_file.exists()


@pytest.mark.study
def test_fracture_shear_refuses_a_checkpoint_of_another_scene(tmp_path):
    # a checkpoint at a point's place that holds another scene (here N_f = 3 where N_f = 10
    # belongs) is named and left alone, and nothing is recorded
    import subprocess
    import sys

    runs, records = tmp_path / "runs", tmp_path / "r.jsonl"
    path = _crashed_run(runs, 3.0, 10.0)
    script = SCRIPTS / "fracture_shear.py"
    out = subprocess.run(
        [sys.executable, str(script), "--n", "16", "--ratio", "0.5", "--friction", "0.3",
         "--nf", "10", "--seeds", "1", "--records", str(records), "--runs", str(runs)],
        capture_output=True, text=True, timeout=300,
    )  # fmt: skip
    assert out.returncode == 2 and "Traceback" not in out.stderr
    assert f"{path}: cannot resume this run from it (it holds another scene" in out.stderr
    assert path.exists() and not records.exists()


@pytest.mark.study
def test_fracture_shear_checkpoints_need_run_files(tmp_path):
    import subprocess
    import sys

    script = SCRIPTS / "fracture_shear.py"
    for extra, message in ((["--checkpoint-every", "10m"], "--checkpoint-every needs --runs"),
                           (["--runs", str(tmp_path), "--checkpoint-every", "soon"],
                            "--checkpoint-every 'soon': give a duration")):  # fmt: skip
        out = subprocess.run([sys.executable, str(script), "--n", "16", *extra],
                             capture_output=True, text=True, timeout=300)  # fmt: skip
        assert out.returncode == 2 and "Traceback" not in out.stderr
        assert message in out.stderr


@pytest.mark.study
def test_fracture_shear_solver_tolerance_is_part_of_a_runs_identity(tmp_path):
    # the study's scene at another solver tolerance is another run: recorded beside the
    # default's, its run file named after it, and the table says which tolerance it used
    records, runs, table = tmp_path / "r.jsonl", tmp_path / "runs", tmp_path / "t.md"
    args = ["--n", "12", "--ratio", "0.5", "--friction", "none", "--nf", "10", "--seeds", "1",
            "--records", str(records), "--runs", str(runs)]  # fmt: skip
    _script("fracture_shear.py", *args)
    _script("fracture_shear.py", *args, "--solver-tolerance", "1e-3", "--table", str(table))
    recs = [json.loads(line) for line in records.read_text().splitlines()]
    assert [r["solver_tolerance"] for r in recs] == [None, 1e-3]
    assert sorted(p.name for p in runs.iterdir()) == [
        "n12-mindlin-r0.5-stick-held-nf10-s1.h5",
        "n12-mindlin-r0.5-stick-held-tol0.001-nf10-s1.h5",
    ]
    assert "(rotations held, solver_tolerance 0.001 a)" in table.read_text()
    again = _script("fracture_shear.py", *args, "--solver-tolerance", "1e-3")  # recorded
    assert len(records.read_text().splitlines()) == 2 and "D_f" in again


@pytest.mark.study
def test_crack_tip_opening_finds_the_straight_ahead_opening_of_an_elastic_medium():
    # docs/paper.md, "Frictional contacts": the chain opens only the throat ahead of the tip,
    # a shear-stiff medium opens the crack's line further ahead, more on a larger lattice
    rows = {}
    for line in _script("crack_tip_opening.py", "--n", "17", "25", "--length", "3").splitlines():
        cells = [c.strip() for c in line.strip("|").split("|")]
        if len(cells) == 6 and cells[1].isdigit():
            rows[(cells[0], int(cells[1]))] = int(cells[5])
    assert rows[("hertz (the paper's model)", 17)] == rows[("hertz (the paper's model)", 25)] == 1
    for ratio in ("0.1", "0.8"):
        label = f"hertz-mindlin, K_t/K_n = {ratio}"
        assert 1 < rows[(label, 17)] < rows[(label, 25)]


@pytest.mark.study
def test_carried_imbalance_comes_from_the_tolerances():
    # docs/accuracy.md, "With sliding": solved tightly and every change of sliding mode solved
    # again, the force left out of balance is the solver's round-off; a slip tolerance of 1e-2 a
    # carries up to 4 K_t delta a particle (K_t delta = 0.075 F_0 at the prestress; x2 for
    # contacts stiffened by compression)
    out = _script("carried_imbalance.py", "--n", "12", "--ratio", "0.5", "--nf", "3",
                  "--solver-tolerance", "1e-6", "--slip", "0", "1e-2")  # fmt: skip
    rows = [dict(zip(line.split()[::2], line.split()[1::2], strict=True))
            for line in out.splitlines() if line.startswith("solver")]  # fmt: skip
    exact, slip = (float(r["largest"]) for r in rows)
    assert exact < 1e-4 and 100 * exact < slip < 4 * 0.075 * 2
    assert rows[0]["drained"] == rows[1]["drained"]


@pytest.mark.study
def test_fit_sliding_constant_minimises_the_worst_factor():
    # two points that disagree: c = 1 fits the first exactly, c = 3 the second; the fit sits
    # where both are off by the same factor, and no c on a fine scan does better

    _scripts_importable()
    from fracture_shear_tables import fit_sliding_constant

    points = [(1.0, 2.0), (1.0, 4.0)]
    c, worst = fit_sliding_constant(points)
    assert worst == pytest.approx(2**0.5, rel=1e-2)  # 1 + c = sqrt(8): each off by sqrt 2
    assert c == pytest.approx(8**0.5 - 1, abs=0.01)
    for other in (0.5, 1.0, 1.5, 2.5, 3.0):
        assert max(max(m / (1 + other * x), (1 + other * x) / m) for x, m in points) >= worst


@pytest.mark.study
def test_code_version_names_the_imported_package_and_a_script_elsewhere(tmp_path):
    # a study runs a worktree's script; the record must name the code of the porenet it
    # imported (an editable install can point at another checkout), and the script's commit
    # where it differs
    import subprocess

    _scripts_importable()
    from fracture_shear import code_version

    import porenet

    def checkout(name: str, files: list[str]) -> str:
        root = tmp_path / name
        for f in files:
            (root / f).parent.mkdir(parents=True, exist_ok=True)
            (root / f).write_text(name)
        git = ["git", "-C", str(root), "-c", "user.name=t", "-c", "user.email=t@t"]
        subprocess.run([*git, "init", "-q"], check=True)
        subprocess.run([*git, "add", "."], check=True)
        subprocess.run([*git, "commit", "-q", "-m", name], check=True)
        return subprocess.run([*git, "rev-parse", "--short=7", "HEAD"], check=True,
                              capture_output=True, text=True).stdout.strip()  # fmt: skip

    a = checkout("a", ["porenet/core.py", "examples/scripts/s.py"])
    b = checkout("b", ["porenet/core.py", "examples/scripts/s.py"])
    package, script = tmp_path / "a" / "porenet", tmp_path / "b" / "examples" / "scripts"
    assert code_version(package, tmp_path / "a" / "examples" / "scripts") == a
    assert code_version(package, script) == f"{a} script {b}"
    (package / "core.py").write_text("changed")
    assert code_version(package, script) == f"{a}+dirty script {b}"
    (script / "s.py").write_text("changed")  # the script's own examples/ count too
    assert code_version(tmp_path / "b" / "porenet", script) == f"{b}+dirty"
    plain = tmp_path / "wheel" / "porenet"
    plain.mkdir(parents=True)
    assert code_version(plain, plain) == f"porenet {porenet.__version__}"


def _doc_script():
    _scripts_importable()
    import fracture_shear_doc

    return fracture_shear_doc


@pytest.mark.study
def test_fracture_shear_n400_page_tables_are_what_its_committed_records_give(capsys):
    # docs/fracture-shear-n400.md's marked tables, made again from docs/data/: a record
    # committed without its tables (or a change to the cost model that prices them) fails
    # here, naming the table and the command that makes it again
    doc = _doc_script()
    assert doc.main(["--check"]) == 0, capsys.readouterr().out


@pytest.mark.study
def test_fracture_shear_doc_names_a_stale_table_and_rewrites_only_the_tables(tmp_path, capsys):
    doc = _doc_script()
    records = tmp_path / "records"
    records.mkdir()
    (records / "a.jsonl").write_text(doc.RECORDS.joinpath("no-sliding.jsonl").read_text())
    page = tmp_path / "page.md"
    text = ("# prose kept\n\n<!-- table: by N_f, committed records -->\nstale\n"
            "<!-- end table -->\n\nmore prose\n")  # fmt: skip
    page.write_text(text)
    args = ["--page", str(page), "--records", str(records)]
    assert doc.main([*args, "--check"]) == 1
    assert "table 'by N_f, committed records' differs" in capsys.readouterr().out
    assert page.read_text() == text  # --check writes nothing
    assert doc.main(args) == 0
    made = page.read_text()
    assert made.startswith("# prose kept\n\n<!-- table: by N_f, committed records -->\n| sliding")
    assert made.endswith("<!-- end table -->\n\nmore prose\n") and "stale" not in made
    assert "| no sliding | 1 | 12 |" in made  # the records' twelve runs at N_f = 1
    assert doc.main([*args, "--check"]) == 0
    for bad, says in (("<!-- table: nonsense -->\nx\n<!-- end table -->\n", "'nonsense' is not"),
                      ("<!-- table: sliding cost -->\nx\n", "has no")):  # fmt: skip
        page.write_text(bad)
        with pytest.raises(SystemExit):
            doc.main(args)
        assert says in capsys.readouterr().err
        assert page.read_text() == bad  # nothing written
    page.write_bytes(b"\xff\xfe not text")
    with pytest.raises(SystemExit):
        doc.main(args)
    assert "is not UTF-8 text" in capsys.readouterr().err
