"""The study driver: plan -> pending runs -> executor -> store.

Resume rule: runs already in the store are skipped, whether `completed` or `failed` (a failed run
is deterministic: it would fail the same way again; `retry_failed=True` redoes them). Runs that
were in flight when a study was killed left no row and are redone. A store whose run of the same
key was made from a different spec (the config changed under the same name) is refused, and so
is a damaged or read-only store, before any run. A run that finished while another process held
the store's lock past the wait is kept in DIR/unrecorded/ and stored by the next call.
"""

from __future__ import annotations

import os
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from chassistune.errors import InputError
from chassistune.studies import unrecorded
from chassistune.studies.executors import Executor
from chassistune.studies.lock import study_lock
from chassistune.studies.records import RunResult, RunStatus
from chassistune.studies.spec import RunSpec, StudyPlan
from chassistune.studies.store import (
    STORE_NAME,
    Notice,
    Store,
    StoreBusy,
    damaged_error,
    store_path,
)

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
    completed_in_study: int
    """Runs of the study completed now or before (0: every run of the study failed)."""


def check_out_dir(out_dir: str | Path) -> None:
    """Refuse an output folder that cannot hold a study (before anything is written)."""
    p = Path(out_dir)
    if p.exists() and not p.is_dir():
        raise InputError("out", f"{str(p)!r} exists and is not a folder")
    if not p.exists() and not p.resolve().parent.is_dir():
        raise InputError("out", f"folder {str(p.resolve().parent)!r} does not exist")
    if p.is_dir() and (p / STORE_NAME).exists() and not (p / STORE_NAME).is_file():
        raise InputError("out", f"{str(p / STORE_NAME)!r} is not a file")
    for name in (STORE_NAME, f"{STORE_NAME}-wal", f"{STORE_NAME}-shm"):
        if (p / name).is_file() and _read_only(p / name):
            raise InputError(
                "out",
                f"{str(p / name)!r} is read-only: a study run adds its runs to it; make it "
                "writable or use a new --out folder",
            )


def _read_only(path: Path) -> bool:
    """Whether `path` cannot be written: its mode (for this user) or a read-only file system."""
    return not os.access(path, os.W_OK) or bool(os.statvfs(path).f_flag & os.ST_RDONLY)


def pending_runs(plan: StudyPlan, out_dir: str | Path, retry_failed: bool = False) -> list[RunSpec]:
    """The plan's runs that still have to be done (reading an existing store, never creating;
    InputError for a damaged store, naming the first damaged run)."""
    if not store_path(out_dir).exists():
        return list(plan.runs)
    with Store.open(out_dir, "out") as store:
        damaged = store.scan(integrity=True).damaged
        if damaged:
            raise damaged_error(store.path, damaged, "out")
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
    notice: Notice | None = None,
) -> StudyOutcome:
    """Do the plan's pending runs on `executor`, recording each in DIR/study.sqlite (`notice`
    hears of a wait for the store's lock)."""
    check_out_dir(out_dir)
    with study_lock(out_dir):
        return _run_locked(plan, out_dir, executor, retry_failed, progress, notice)


def _run_locked(
    plan: StudyPlan,
    out_dir: str | Path,
    executor: Executor,
    retry_failed: bool,
    progress: Progress | None,
    notice: Notice | None,
) -> StudyOutcome:
    todo = pending_runs(plan, out_dir, retry_failed)
    kept = unrecorded.kept(out_dir)
    completed = failed = 0
    t0 = time.perf_counter()
    meta = {
        "study": plan.config.study.name,
        "config": plan.config_json(),
        "scenarios": "\n".join(plan.scenarios),
        "optimizers": "\n".join(plan.optimizers),
    }
    with Store.create(out_dir, meta, notice) as store:
        stored = _store_kept(store, kept, plan, todo)
        todo = [s for s in todo if s.key not in stored]
        specs = {s.key: s for s in todo}
        total, skipped = len(plan.runs), len(plan.runs) - len(todo)
        if progress is not None:
            progress(skipped, 0, total)
        for result in executor.results(todo):
            _record(store, out_dir, specs[result.key], result)
            if result.completed:
                completed += 1
            else:
                failed += 1
            if progress is not None:
                progress(skipped + completed + failed, failed, total)
        store.check_present()
        in_study = sum(r.completed for r in store.scan().records)
    return StudyOutcome(
        total, skipped, completed, failed, time.perf_counter() - t0, store.path, in_study
    )


def _store_kept(
    store: Store,
    kept: list[tuple[Path, RunSpec, RunResult]],
    plan: StudyPlan,
    todo: list[RunSpec],
) -> set[str]:
    """Record the kept runs (DIR/unrecorded/) that the plan still needs, and remove the files of
    the plan's runs; the keys recorded. Runs of another config stay where they are."""
    in_plan = {s.key: s for s in plan.runs}
    wanted = {s.key for s in todo}
    stored = set()
    for path, spec, result in kept:
        if in_plan.get(spec.key) != spec:
            continue
        if spec.key in wanted:
            store.record(spec, result)
            stored.add(spec.key)
        path.unlink()
    return stored


def _record(store: Store, out_dir: str | Path, spec: RunSpec, result: RunResult) -> None:
    """`store.record`, keeping the run in DIR/unrecorded/ when the store's lock is held too long."""
    try:
        store.record(spec, result)
    except StoreBusy as exc:
        path = unrecorded.keep(out_dir, spec, result)
        raise InputError(
            exc.field,
            f"{exc.problem}; run {spec.key!r} that just finished is kept in {str(path)!r} "
            "and stored by the next `study run`",
        ) from None
