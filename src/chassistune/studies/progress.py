"""Progress of a study on stderr: a rich bar on a terminal, elsewhere one line every 30 s.

Off a terminal (a log file, CI, `nohup`) a bar is noise, but silence for the ten minutes of a
long study looks like a hang: a line with the runs done so far every `PERIOD_S` instead.
"""

from __future__ import annotations

import sys
import threading
import time
from collections.abc import Callable

from chassistune.studies.runner import Progress, StudyOutcome

PERIOD_S = 30.0
"""Seconds between two progress lines off a terminal."""

Say = Callable[[str], None]


def _stderr_line(text: str) -> None:
    sys.stderr.write(text + "\n")
    sys.stderr.flush()


def with_progress(
    run: Callable[[Progress], StudyOutcome],
    label: str,
    say: Say = _stderr_line,
    period_s: float | None = None,
) -> StudyOutcome:
    """Call `run` with a progress callback: a rich bar on stderr when it is a terminal, else a
    line through `say` every `period_s` (default `PERIOD_S`: runs done, failed, elapsed)."""
    if sys.stderr.isatty():
        return _with_bar(run, label)
    counts: list[int] = []
    stop = threading.Event()
    t0 = time.monotonic()

    def tick() -> None:
        while not stop.wait(PERIOD_S if period_s is None else period_s):
            if counts:
                done, failed, total = counts
                say(
                    f"{label}: {done} of {total} runs done, {failed} failed "
                    f"({time.monotonic() - t0:.0f} s)"
                )

    ticker = threading.Thread(target=tick, name="progress", daemon=True)
    ticker.start()
    try:
        return run(
            lambda done, failed, total: counts.__setitem__(slice(None), [done, failed, total])
        )
    finally:
        stop.set()
        ticker.join()


def _with_bar(run: Callable[[Progress], StudyOutcome], label: str) -> StudyOutcome:
    """Runs done, failures, elapsed and ETA as a transient rich bar on stderr."""
    from rich.console import Console
    from rich.progress import (
        BarColumn,
        MofNCompleteColumn,
        TextColumn,
        TimeElapsedColumn,
        TimeRemainingColumn,
    )
    from rich.progress import Progress as Bar

    with Bar(
        TextColumn("{task.description}"),
        BarColumn(),
        MofNCompleteColumn(),
        TextColumn("runs, {task.fields[failed]} failed"),
        TimeElapsedColumn(),
        TextColumn("ETA"),
        TimeRemainingColumn(),
        console=Console(stderr=True),
        transient=True,
    ) as bar:
        task = bar.add_task(label, total=None, failed=0)
        started: list[bool] = []

        def update(done: int, failed: int, total: int) -> None:
            if not started:  # runs finished earlier must not count in the speed (ETA)
                started.append(True)
                bar.reset(task, total=total, completed=done, failed=failed)
            bar.update(task, completed=done, total=total, failed=failed)

        return run(update)
