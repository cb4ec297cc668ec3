"""Where a sweep stands: :class:`Progress`, given to ``on_progress`` after every finished run,
and its one-line form (docs/sweeps.md, "Progress")."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Progress:
    """Where a sweep stands (given to ``on_progress`` after every finished run)."""

    total: int  # runs in the sweep
    done: int  # finished successfully (this session or before)
    failed: int  # failed (this session or before)
    to_run: int  # runs this session started with
    finished_now: int  # of those, finished (done or failed)
    elapsed_s: float  # since this session's runs started
    workers: int | None
    last: str | None = None  # run id just finished

    @property
    def eta_s(self) -> float | None:
        """Time left: the mean wall time per run finished this session (as seen from the
        sweep, i.e. elapsed / finished, which accounts for parallel workers) times the runs
        left; None before the first run finishes."""
        if self.finished_now == 0:
            return None
        return self.elapsed_s / self.finished_now * (self.to_run - self.finished_now)


def clock(seconds: float) -> str:
    """``mm:ss``, or ``h:mm:ss`` from an hour on."""
    whole = round(seconds)
    h, rest = divmod(whole, 3600)
    m, s = divmod(rest, 60)
    return f"{h}:{m:02d}:{s:02d}" if h else f"{m:02d}:{s:02d}"


def format_progress(p: Progress) -> str:
    """One line: ``12/36 runs, 1 failed, 00:42 elapsed, ETA 01:30``."""
    eta = p.eta_s
    return (
        f"{p.done + p.failed}/{p.total} runs, {p.failed} failed, {clock(p.elapsed_s)} elapsed"
        + (f", ETA {clock(eta)}" if eta is not None else "")
    )


__all__ = ["Progress", "clock", "format_progress"]
