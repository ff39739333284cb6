"""The study driver: plan -> pending runs -> executor -> store, with a progress bar.

Resume rule: runs already in the store are skipped, whether `completed` or `failed` (a failed run
is deterministic: it would fail the same way again; `retry_failed=True` redoes them). Runs that
were in flight when a study was killed left no row and are redone. A store whose run of the same
key was made from a different spec (the config changed under the same name) is refused.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from chassistune.errors import InputError
from chassistune.studies.executors import Executor
from chassistune.studies.lock import study_lock
from chassistune.studies.records import RunStatus
from chassistune.studies.spec import RunSpec, StudyPlan
from chassistune.studies.store import STORE_NAME, Store, store_path

Progress = Callable[[int, int, int], None]
"""progress(done, failed, total), called once at the start and after every finished run."""


@dataclass(frozen=True)
class StudyOutcome:
    """What a `run_study` call did."""

    total: int
    skipped: int
    completed: int
    failed: int
    wall_time_s: float
    store: Path


def check_out_dir(out_dir: str | Path) -> None:
    """Refuse an output folder that cannot hold a study (before anything is written)."""
    p = Path(out_dir)
    if p.exists() and not p.is_dir():
        raise InputError("out", f"{str(p)!r} exists and is not a folder")
    if not p.exists() and not p.resolve().parent.is_dir():
        raise InputError("out", f"folder {str(p.resolve().parent)!r} does not exist")
    if p.is_dir() and (p / STORE_NAME).exists() and not (p / STORE_NAME).is_file():
        raise InputError("out", f"{str(p / STORE_NAME)!r} is not a file")


def pending_runs(plan: StudyPlan, out_dir: str | Path, retry_failed: bool = False) -> list[RunSpec]:
    """The plan's runs that still have to be done (reading an existing store, never creating)."""
    if not store_path(out_dir).exists():
        return list(plan.runs)
    with Store.open(out_dir, "out") as store:
        finished = store.finished()
        name = store.meta().get("study")
    if name is not None and name != plan.config.study.name:
        raise InputError(
            "out",
            f"{str(out_dir)!r} holds the study {name!r}, not "
            f"{plan.config.study.name!r}; use a new --out folder",
        )
    todo = []
    for spec in plan.runs:
        if spec.key not in finished:
            todo.append(spec)
            continue
        spec_hash, status = finished[spec.key]
        if spec_hash != spec.spec_hash:
            raise InputError(
                "out",
                f"{str(out_dir)!r} already holds run {spec.key!r} made "
                "from a different config; use a new --out folder",
            )
        if retry_failed and status is not RunStatus.COMPLETED:
            todo.append(spec)
    return todo


def run_study(
    plan: StudyPlan,
    out_dir: str | Path,
    executor: Executor,
    retry_failed: bool = False,
    progress: Progress | None = None,
) -> StudyOutcome:
    """Do the plan's pending runs on `executor`, recording each in DIR/study.sqlite."""
    check_out_dir(out_dir)
    with study_lock(out_dir):
        return _run_locked(plan, out_dir, executor, retry_failed, progress)


def _run_locked(
    plan: StudyPlan,
    out_dir: str | Path,
    executor: Executor,
    retry_failed: bool,
    progress: Progress | None,
) -> StudyOutcome:
    todo = pending_runs(plan, out_dir, retry_failed)
    specs = {s.key: s for s in todo}
    total, skipped = len(plan.runs), len(plan.runs) - len(todo)
    completed = failed = 0
    t0 = time.perf_counter()
    meta = {
        "study": plan.config.study.name,
        "config": plan.config_json(),
        "scenarios": "\n".join(plan.scenarios),
        "optimizers": "\n".join(plan.optimizers),
    }
    with Store.create(out_dir, meta) as store:
        if progress is not None:
            progress(skipped, 0, total)
        for result in executor.results(todo):
            store.record(specs[result.key], result)
            if result.completed:
                completed += 1
            else:
                failed += 1
            if progress is not None:
                progress(skipped + completed + failed, failed, total)
    return StudyOutcome(
        total, skipped, completed, failed, time.perf_counter() - t0, store_path(out_dir)
    )


def rich_progress(run: Callable[[Progress], StudyOutcome], label: str) -> StudyOutcome:
    """Call `run` with a rich progress bar on stderr: runs done, failures, elapsed, ETA (only
    on a terminal: elsewhere a bar is noise, and rich would leave an empty line)."""
    import sys

    if not sys.stderr.isatty():
        return run(lambda done, failed, total: None)
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
