"""Fixtures of the unit tests: small file systems to fill (disk full, read-only)."""

from __future__ import annotations

import os
import shutil
import subprocess
from collections.abc import Callable, Iterator
from pathlib import Path

import pytest


def mount_tmpfs(directory: Path, size: str = "64k", readonly: bool = False) -> str | None:
    """Mount a tmpfs of ``size`` on ``directory`` (created); None on success, else why not
    (not root, no ``mount``, no permission in this container)."""
    if os.geteuid() != 0:
        return "mounting a tmpfs needs root"
    if shutil.which("mount") is None:
        return "no mount command"
    directory.mkdir(parents=True, exist_ok=True)
    options = f"size={size}" + (",ro" if readonly else "")
    proc = subprocess.run(
        ["mount", "-t", "tmpfs", "-o", options, "tmpfs", str(directory)],
        capture_output=True,
        text=True,
        check=False,
    )
    return None if proc.returncode == 0 else f"cannot mount a tmpfs: {proc.stderr.strip()}"


def fill(directory: Path, leave: int = 2048) -> None:
    """Fill the file system of ``directory`` until at most ``leave`` bytes are free."""
    free = shutil.disk_usage(directory).free
    with (directory / "filler").open("wb") as fh:
        try:
            fh.write(b"\0" * max(0, free - leave))
            fh.flush()
        except OSError:
            pass


@pytest.fixture
def tmpfs() -> Iterator[Callable[..., Path]]:
    """``tmpfs(directory, size="64k", readonly=False, full=False)`` mounts a small tmpfs there
    (``full``: filled to ~2 kB free; ``readonly``: remounted read-only after ``files`` are
    copied in) and returns the directory; skips the test where it cannot (not root, or a
    container without the permission). Unmounted at the end."""
    mounted: list[Path] = []

    def make(
        directory: Path,
        size: str = "64k",
        *,
        readonly: bool = False,
        full: bool = False,
        files: tuple[Path, ...] = (),
    ) -> Path:
        why = mount_tmpfs(directory, size)
        if why is not None:
            pytest.skip(why)
        mounted.append(directory)
        for path in files:
            shutil.copy(path, directory / path.name)
        if full:
            fill(directory)
        if readonly:
            subprocess.run(["mount", "-o", "remount,ro", str(directory)], check=True)
        return directory

    yield make
    for directory in reversed(mounted):
        subprocess.run(["umount", "-l", str(directory)], check=False)
