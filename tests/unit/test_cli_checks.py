"""What the command checks before it works, and how it reports what no check foresaw
(porenet/cli/checks.py; docs/reliability.md, "Memory and picture size", "Exit status")."""

from __future__ import annotations

import errno

import pytest

from porenet.cli import checks as cli_checks
from porenet.cli.main import main
from porenet.core.errors import ConfigError

SCENE = '[lattice]\nn = 10\ndisorder = 0.3\n[fluid]\nkind = "invasion-percolation"\n'


@pytest.fixture
def proc_files(tmp_path, monkeypatch):
    """Point the memory readers at files under tmp_path, with no address-space limit."""
    meminfo = tmp_path / "meminfo"
    meminfo.write_text("MemTotal:       24683664 kB\nMemAvailable:    4000000 kB\n")
    cgroup = tmp_path / "cgroup"
    cgroup.mkdir()
    (tmp_path / "self-cgroup").write_text("0::/\n")
    monkeypatch.setattr(cli_checks, "MEMINFO", meminfo)
    monkeypatch.setattr(cli_checks, "CGROUP_ROOT", cgroup)
    monkeypatch.setattr(cli_checks, "PROC_SELF_CGROUP", tmp_path / "self-cgroup")
    monkeypatch.setattr(cli_checks, "_address_space_available", lambda: None)
    return cgroup


def test_available_memory_is_the_least_of_meminfo_and_the_cgroup(proc_files):
    assert cli_checks.available_memory() == (4_096_000_000, "MemAvailable in /proc/meminfo")
    (proc_files / "memory.max").write_text("max\n")  # no limit
    assert cli_checks.available_memory()[0] == 4_096_000_000
    (proc_files / "memory.max").write_text("2000000000\n")
    (proc_files / "memory.current").write_text("500000000\n")
    assert cli_checks.available_memory() == (1_500_000_000, "the cgroup's memory.max")


def test_a_cgroup_v1_limit(proc_files):
    v1 = proc_files / "memory"
    v1.mkdir()
    (v1 / "memory.limit_in_bytes").write_text(str(2**63 - 4096))  # no limit
    assert cli_checks.available_memory()[0] == 4_096_000_000
    (v1 / "memory.limit_in_bytes").write_text("3000000000")
    (v1 / "memory.usage_in_bytes").write_text("1000000000")
    assert cli_checks.available_memory() == (2_000_000_000, "the cgroup's memory.max")


def test_nothing_readable_means_no_refusal(tmp_path, monkeypatch):
    monkeypatch.setattr(cli_checks, "MEMINFO", tmp_path / "absent")
    monkeypatch.setattr(cli_checks, "CGROUP_ROOT", tmp_path / "absent")
    monkeypatch.setattr(cli_checks, "PROC_SELF_CGROUP", tmp_path / "absent")
    monkeypatch.setattr(cli_checks, "_address_space_available", lambda: None)
    assert cli_checks.available_memory() is None


@pytest.fixture
def little_memory(monkeypatch):
    """1 kB available: less than the 10 x 10 scene's ~24 kB."""
    monkeypatch.setattr(cli_checks, "available_memory", lambda: (1000, "a test"))


def test_a_scene_larger_than_memory_is_refused_before_it_runs(
    write_scene, tmp_path, capsys, little_memory
):
    out = tmp_path / "o.h5"
    assert main(["run", str(write_scene(SCENE)), "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert "lattice.n = 10 needs ~24 kB of memory (the plan's estimate, docs/cost.md)" in err
    assert "more than the 1 kB available (a test)" in err
    assert "reduce lattice.n or pass --ignore-memory to try anyway" in err
    assert not out.exists()


def test_ignore_memory_runs_anyway_and_says_so(write_scene, tmp_path, caplog, little_memory):
    out = tmp_path / "o.h5"
    with caplog.at_level("WARNING"):
        assert main(["run", str(write_scene(SCENE)), "-o", str(out), "-q", "--ignore-memory"]) == 0
    assert any("--ignore-memory: trying anyway" in r.getMessage() for r in caplog.records)
    assert out.is_file()


def test_running_out_of_memory_is_one_line_not_an_internal_error(
    write_scene, tmp_path, capsys, monkeypatch
):
    from porenet.simulation import Simulation

    def exhausted(self, *args):
        raise MemoryError

    monkeypatch.setattr(Simulation, "run", exhausted)
    out = tmp_path / "o.h5"
    assert main(["run", str(write_scene(SCENE)), "-o", str(out), "-q"]) == 1
    err = capsys.readouterr().err
    assert err.startswith("porenet run: error: out of memory") and "reduce lattice.n" in err
    assert "internal error" not in err and not out.exists()


def test_an_unforeseen_os_error_names_the_file(write_scene, tmp_path, capsys, monkeypatch):
    from porenet.simulation import Simulation

    def broken(self, *args):
        raise OSError(errno.EIO, "Input/output error", "/data/disk")

    monkeypatch.setattr(Simulation, "run", broken)
    assert main(["run", str(write_scene(SCENE)), "-o", str(tmp_path / "o.h5"), "-q"]) == 1
    assert capsys.readouterr().err == "porenet run: error: /data/disk: Input/output error\n"


def test_an_interrupted_command_says_so(tmp_path, capsys, monkeypatch):
    from porenet.io import runfile

    def interrupted(path):
        raise KeyboardInterrupt

    monkeypatch.setattr(runfile, "check_run_file", interrupted)
    (tmp_path / "r.h5").write_bytes(b"")
    assert main(["plot", str(tmp_path / "r.h5")]) == 130
    assert capsys.readouterr().err == "porenet plot: interrupted\n"


class _Figure:
    def get_size_inches(self):
        return (5.0, 4.3)


def test_a_picture_larger_than_memory_is_refused(monkeypatch):
    monkeypatch.setattr(cli_checks, "available_memory", lambda: (1_000_000, "a test"))
    cli_checks.check_picture_size(_Figure(), 100)  # 500 x 430 x 4 bytes = 0.86 MB
    with pytest.raises(ConfigError) as info:
        cli_checks.check_picture_size(_Figure(), 300)
    assert str(info.value) == (
        "--dpi 300: the picture would be 1,500 x 1,290 pixels (5 x 4.3 in), ~7.7 MB of "
        "memory, more than the 1 MB available; use --dpi 107 or less"
    )


@pytest.mark.parametrize("dpi", [0.0, -1.0, float("nan"), float("inf")])
def test_a_dpi_that_is_not_a_positive_number(dpi):
    with pytest.raises(ConfigError, match="must be a positive number of dots per inch"):
        cli_checks.check_dpi(dpi)


def test_help_states_the_exit_statuses(capsys):
    with pytest.raises(SystemExit) as info:
        main(["--help"])
    assert info.value.code == 0
    out = capsys.readouterr().out
    assert "exit status:" in out and "130  interrupted" in out and "--traceback" in out
    assert "2    bad usage or input" in out


def test_plan_says_when_run_would_refuse_the_scene(write_scene, capsys, little_memory):
    assert main(["plan", str(write_scene(SCENE))]) == 0
    last = capsys.readouterr().out.splitlines()[-1]
    assert last.startswith("memory: lattice.n = 10 needs ~24 kB of memory")
    assert last.endswith("porenet run refuses it without --ignore-memory")


def test_permissions_are_named_even_where_root_bypasses_them(tmp_path, monkeypatch):
    """The chmod cases of tests/unit/test_reliability.py are skipped as root; their messages
    are checked here with the permission checks answering "no"."""
    import os
    from pathlib import Path

    from porenet.config.loading import read_toml
    from porenet.core.errors import RunFileError
    from porenet.io.runfile import check_readable

    (tmp_path / "run.h5").write_bytes(b"")
    monkeypatch.setattr(os, "access", lambda path, mode: False)
    with pytest.raises(ConfigError, match=r"-o .*out.h5: directory .* may not be written"):
        cli_checks.check_output_file(tmp_path / "out.h5", "-o")
    with pytest.raises(RunFileError, match=r"cannot read run file .*run.h5: permission denied"):
        check_readable(tmp_path / "run.h5")

    def denied(self, *args, **kwargs):
        raise PermissionError(13, "Permission denied")

    monkeypatch.setattr(Path, "open", denied)
    with pytest.raises(ConfigError, match=r"scene.toml: permission denied; make the scene"):
        read_toml(tmp_path / "scene.toml")
