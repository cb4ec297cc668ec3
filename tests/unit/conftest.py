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


class Mounts:
    """``mounts(directory, size="64k", readonly=False, full=False, files=())`` mounts a small
    tmpfs on ``directory`` (``files`` copied in; ``full``: then filled to ~2 kB free;
    ``readonly``: then remounted read-only) and returns it; skips where it cannot (not root,
    or a container without the permission). :meth:`unmount_all` undoes every mount."""

    def __init__(self) -> None:
        self.mounted: list[Path] = []

    def __call__(
        self,
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
        self.mounted.append(directory)
        for path in files:
            shutil.copy(path, directory / path.name)
        if full:
            fill(directory)
        if readonly:
            subprocess.run(["mount", "-o", "remount,ro", str(directory)], check=True)
        return directory

    def unmount_all(self) -> None:
        for directory in reversed(self.mounted):
            subprocess.run(["umount", "-l", str(directory)], check=False)
        self.mounted.clear()


@pytest.fixture
def tmpfs() -> Iterator[Callable[..., Path]]:
    """A :class:`Mounts` for one test, unmounted at its end."""
    mounts = Mounts()
    yield mounts
    mounts.unmount_all()


@pytest.fixture(scope="module")
def module_tmpfs() -> Iterator[Mounts]:
    """A :class:`Mounts` for a whole test module, unmounted at its end."""
    mounts = Mounts()
    yield mounts
    mounts.unmount_all()
