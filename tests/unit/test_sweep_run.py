"""Running sweeps: outputs, resume, failures, refusal to mix sweeps, executors, the CLI."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import numpy as np
import pytest

from porenet.cli.main import main
from porenet.core.errors import ConfigError
from porenet.io.runfile import read_run
from porenet.sweep import runner
from porenet.sweep.executors import Executor, LocalExecutor
from porenet.sweep.runner import SweepInterrupted, run_sweep

ROOT = Path(__file__).resolve().parents[2]
DEMO = ROOT / "examples" / "sweeps" / "demo.toml"

IP_SWEEP = """
name = "ip"
replicates = 2
[base]
lattice = { n = 20, disorder = 0.3 }
fluid = { kind = "invasion-percolation" }
[[axes]]
key = "lattice.n"
values = [18, 22]
[[axes]]
key = "fluid.trapping"
values = [true, false]
"""

#: A viscous point that fails at once (NumericalError: more steps needed than max_steps).
FAILING_SWEEP = """
name = "fails"
[base]
lattice = { n = 16, disorder = 0.3 }
fluid = { kind = "viscous", capillary_number = 1e-2 }
[[axes]]
key = "fluid.max_steps"
values = [1, 1000000]
"""

HEADER = [
    "run_id",
    "lattice.n",
    "fluid.trapping",
    "seed",
    "status",
    "fractal_dimension",
    "fractal_dimension_error",
    "regime",
    "regime_confidence",
    "capillary_number_measured",
    "wall_time_s",
    "run_file",
    "error",
]


def _sweep(tmp_path, text=IP_SWEEP, name="sweep.toml"):
    path = tmp_path / name
    path.write_text(text)
    return path


def _rows(out):
    with (Path(out) / "summary.csv").open(newline="") as f:
        return list(csv.DictReader(f))


def _mtimes(out):
    return {p.name: p.stat().st_mtime_ns for p in (Path(out) / "runs").iterdir()}


def test_outputs_summary_and_resume(tmp_path):
    out = tmp_path / "out"
    report = run_sweep(_sweep(tmp_path), out, workers=1)
    assert (report.total, report.done, report.failed, report.ran) == (8, 8, 0, 8)
    resolved = json.loads((out / "sweep.json").read_text())
    assert [r["run_id"] for r in resolved["runs"]][:3] == ["p0000-r00", "p0000-r01", "p0001-r00"]
    assert resolved["columns"] == ["lattice.n", "fluid.trapping"]
    with (out / "summary.csv").open() as f:
        assert next(csv.reader(f)) == HEADER
    rows = _rows(out)
    assert [r["status"] for r in rows] == ["done"] * 8
    assert rows[2]["lattice.n"] == "18" and rows[2]["fluid.trapping"] == "false"
    for row, run in zip(rows, resolved["runs"], strict=True):
        data = read_run(out / row["run_file"])
        assert data.scene == run["scene"] and int(row["seed"]) == data.summary["seed"]
        assert float(row["fractal_dimension"]) == data.summary["fractal_dimension"]
        assert row["regime"] == data.summary["regime"] and row["capillary_number_measured"] == ""
    before, table = _mtimes(out), (out / "summary.csv").read_text()
    again = run_sweep(_sweep(tmp_path), out, workers=1)
    assert (again.ran, again.skipped, again.done) == (0, 8, 8)
    assert _mtimes(out) == before  # nothing ran again
    assert (out / "summary.csv").read_text() == table  # rows read back from the run files


def test_failed_run_is_recorded_and_the_sweep_goes_on(tmp_path):
    out = tmp_path / "out"
    report = run_sweep(_sweep(tmp_path, FAILING_SWEEP), out, workers=1)
    assert (report.done, report.failed) == (1, 1)
    bad, good = _rows(out)
    assert bad["status"] == "failed" and bad["run_file"] == ""
    assert bad["error"].startswith("NumericalError: viscous model") and "\n" not in bad["error"]
    assert good["status"] == "done" and float(good["capillary_number_measured"]) > 0
    record = (out / "runs" / "p0000-r00.error.txt").read_text()
    assert record.startswith(bad["error"]) and "Traceback" in record
    assert not (out / "runs" / "p0000-r00.h5").exists()
    before = _mtimes(out)
    again = run_sweep(_sweep(tmp_path, FAILING_SWEEP), out, workers=1)
    assert (again.ran, again.failed) == (0, 1) and _mtimes(out) == before
    assert _rows(out)[0]["error"] == bad["error"]
    retried = run_sweep(_sweep(tmp_path, FAILING_SWEEP), out, workers=1, retry_failed=True)
    assert (retried.ran, retried.failed) == (1, 1)


def test_an_edited_sweep_is_refused_naming_the_run(tmp_path):
    out = tmp_path / "out"
    run_sweep(_sweep(tmp_path), out, workers=1)
    edited = _sweep(tmp_path, IP_SWEEP.replace("disorder = 0.3", "disorder = 0.4"))
    before = {p: p.read_bytes() for p in (out / "sweep.json", out / "summary.csv")}
    with pytest.raises(ConfigError) as info:
        run_sweep(edited, out, workers=1)
    message = str(info.value)
    assert "p0000-r00" in message and "lattice.disorder: 0.3 -> 0.4" in message
    assert "new output directory" in message
    assert {p: p.read_bytes() for p in before} == before  # nothing rewritten
    fewer = _sweep(tmp_path, IP_SWEEP.replace("values = [18, 22]", "values = [18]"))
    with pytest.raises(ConfigError, match=r"p0002-r00.h5: not a run of .* new output directory"):
        run_sweep(fewer, out, workers=1)
    # growing the first axis at its end and the replicates keeps every finished run valid
    grown = IP_SWEEP.replace("[18, 22]", "[18, 22, 16]").replace("replicates = 2", "replicates = 3")
    report = run_sweep(_sweep(tmp_path, grown), out, workers=1)
    assert (report.total, report.skipped, report.ran) == (18, 8, 10)


def test_cli_sweep_quiet_and_final_line(tmp_path, capsys):
    path = _sweep(tmp_path)
    assert main(["sweep", str(path), "-o", str(tmp_path / "o"), "--workers", "1"]) == 0
    captured = capsys.readouterr()
    assert "8 runs: 8 done, 0 failed" in captured.out
    # stderr is not a terminal here: one progress line per finished run, as for a log file
    lines = [x for x in captured.err.splitlines() if " finished; " in x]
    assert len(lines) == 8 and lines[-1].split("finished; ")[1].startswith("8/8 runs, 0 failed")
    assert main(["sweep", str(path), "-o", str(tmp_path / "o"), "-q"]) == 0
    captured = capsys.readouterr()
    assert captured.out == "" and " finished; " not in captured.err


def test_cli_failures_and_errors(tmp_path, capsys):
    bad = _sweep(tmp_path, FAILING_SWEEP)
    assert main(["sweep", str(bad), "-o", str(tmp_path / "f"), "--workers", "1"]) == 0
    captured = capsys.readouterr()
    assert "1 done, 1 failed" in captured.out and "1 run(s) failed" in captured.err
    invalid = _sweep(tmp_path, "replicates = 0\n", "invalid.toml")
    assert main(["sweep", str(invalid), "-o", str(tmp_path / "i")]) == 2
    err = capsys.readouterr().err
    assert f"{invalid}: replicates = 0" in err and "Traceback" not in err
    assert not (tmp_path / "i").exists()  # nothing runs, nothing is written
    assert main(["sweep", str(bad), "-o", str(tmp_path / "w"), "--workers", "0"]) == 2
    with pytest.raises(SystemExit):
        main(["sweep", str(bad), "-o", "x", "--dask-local", "--scheduler", "tcp://h:1"])


def test_ctrl_c_stops_keeps_finished_runs_and_resumes(tmp_path, monkeypatch, capsys):
    calls = []
    real = runner.execute_run

    def interrupted_on_third(task):
        calls.append(task.run_id)
        if len(calls) == 3:
            raise KeyboardInterrupt
        return real(task)

    monkeypatch.setattr(runner, "execute_run", interrupted_on_third)
    out = tmp_path / "out"
    assert main(["sweep", str(_sweep(tmp_path)), "-o", str(out), "--workers", "1"]) == 130
    err = capsys.readouterr().err
    assert "2 of 8 runs finished" in err and "re-running the same command resumes" in err
    assert [r["run_id"] for r in _rows(out)] == ["p0000-r00", "p0000-r01"]
    assert sorted(p.name for p in (out / "runs").iterdir()) == ["p0000-r00.h5", "p0000-r01.h5"]
    monkeypatch.setattr(runner, "execute_run", real)
    report = run_sweep(_sweep(tmp_path), out, workers=1)
    assert (report.ran, report.skipped, report.done) == (6, 2, 8)
    with pytest.raises(SweepInterrupted):  # the library raises; the CLI exits 130
        monkeypatch.setattr(runner, "execute_run", interrupted_on_third)
        calls.clear()
        run_sweep(_sweep(tmp_path), tmp_path / "out2", workers=1)


def test_an_executor_failure_is_recorded_and_retried_next_time(tmp_path):
    class Broken(Executor):
        workers = 1

        def run(self, tasks, fn):
            for task in tasks:
                yield task, RuntimeError("worker died")

    out = tmp_path / "out"
    report = run_sweep(_sweep(tmp_path), out, executor=Broken())
    assert report.failed == 8 and _rows(out)[0]["error"] == "executor: RuntimeError: worker died"
    assert list((out / "runs").iterdir()) == []  # no error records: not the runs' fault
    assert run_sweep(_sweep(tmp_path), out, workers=1).ran == 8


def _drained(out):
    return {p.name: read_run(p).drained for p in sorted((Path(out) / "runs").glob("*.h5"))}


def _without_wall_time(out):
    return [{k: v for k, v in r.items() if k != "wall_time_s"} for r in _rows(out)]


def test_results_do_not_depend_on_the_executor(tmp_path):
    """1 worker (in process) vs 2 local processes vs a 2-worker dask LocalCluster: the same
    run files and summary rows, bit for bit (apart from wall times)."""
    path = _sweep(tmp_path)
    run_sweep(path, tmp_path / "one", workers=1)
    with LocalExecutor(2) as pool:
        report = run_sweep(path, tmp_path / "two", executor=pool)
    assert report.executor == "2 local worker processes" and report.done == 8
    reference, table = _drained(tmp_path / "one"), _without_wall_time(tmp_path / "one")
    two = _drained(tmp_path / "two")
    assert reference.keys() == two.keys()
    assert all(np.array_equal(reference[k], two[k]) for k in reference)
    assert _without_wall_time(tmp_path / "two") == table
    pytest.importorskip("distributed")
    report = run_sweep(path, tmp_path / "dask", dask_local=True, workers=2)
    assert report.executor == "dask LocalCluster of 2 workers" and report.done == 8
    dask = _drained(tmp_path / "dask")
    assert all(np.array_equal(reference[k], dask[k]) for k in reference)
    assert _without_wall_time(tmp_path / "dask") == table


def test_demo_sweep_runs(tmp_path, capsys):
    out = tmp_path / "demo"
    assert main(["sweep", str(DEMO), "-o", str(out), "--workers", "2"]) == 0
    rows = _rows(out)
    assert len(rows) == 8 and {r["status"] for r in rows} == {"done"}
    assert list(rows[0])[:5] == [
        "run_id",
        "lattice.disorder",
        "ca_star",
        "fluid.capillary_number",
        "seed",
    ]
    for r in rows:
        ca, measured = float(r["fluid.capillary_number"]), float(r["capillary_number_measured"])
        assert measured == pytest.approx(ca, rel=0.05)


def test_progress_is_reported_with_an_eta(tmp_path):
    seen = []
    run_sweep(_sweep(tmp_path), tmp_path / "out", workers=1, on_progress=seen.append)
    assert [p.finished_now for p in seen] == list(range(9))
    assert seen[0].eta_s is None and seen[-1].eta_s == 0.0 and seen[-1].done == 8
    line = runner.format_progress(seen[4])
    assert line.startswith("4/8 runs, 0 failed, ") and "ETA" in line


def test_each_run_gets_its_share_of_the_cores(monkeypatch):
    from porenet.sweep.executors import LocalExecutor, SerialExecutor

    monkeypatch.setattr(runner.os, "cpu_count", lambda: 8)
    assert runner.threads_per_run(SerialExecutor(), None) == 8
    assert runner.threads_per_run(LocalExecutor(3), None) == 2
    assert runner.threads_per_run(LocalExecutor(16), None) == 1  # never below one
    assert runner.threads_per_run(LocalExecutor(2), "tcp://remote:8786") == 1  # cores unknown
    assert runner.threads_per_run(None, None) == 1
