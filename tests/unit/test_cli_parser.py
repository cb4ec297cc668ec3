"""The command line's description (porenet.cli.parser) and what runs it (porenet.cli.main) agree:
every command the parser offers has its function, and no function is unreachable."""

from __future__ import annotations

import re
import subprocess
import sys

import pytest

from porenet.cli.main import COMMANDS
from porenet.cli.parser import build_parser


def test_every_command_has_its_function_and_every_function_its_command(
    capsys: pytest.CaptureFixture[str],
) -> None:
    with pytest.raises(SystemExit):  # argparse lists the commands it knows
        build_parser().parse_args(["no-such-command"])
    offered = re.search(r"invalid choice: 'no-such-command' \(choose from (.*)\)",
                        capsys.readouterr().err)  # fmt: skip
    assert offered is not None
    assert set(re.findall(r"'([a-z-]+)'", offered.group(1))) == set(COMMANDS)


def test_the_parser_imports_nothing_heavy() -> None:
    code = (
        "import sys, porenet.cli.parser as p; p.build_parser(); "
        "print(sorted(m for m in ('numpy', 'numba', 'scipy', 'h5py', 'matplotlib') "
        "if m in sys.modules))"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "[]"
