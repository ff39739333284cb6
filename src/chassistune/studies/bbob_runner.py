"""`run_plan`: a BBOB plan's runs on a study executor, each recorded in the study store as it
finishes (DIR/study.sqlite); runs already there are skipped, a store of another plan refused."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import Any

from chassistune.errors import InputError
from chassistune.studies.bbob import BBOB_KIND, BBOBPlan
from chassistune.studies.executors import Executor
from chassistune.studies.lock import study_lock
from chassistune.studies.runner import check_out_dir
from chassistune.studies.store import Store, store_path

Progress = Callable[[int, int], None]
"""progress(done, total) after each finished run."""


def run_plan(
    plan: BBOBPlan,
    out_dir: str | Path,
    executor: Executor,
    progress: Progress | None = None,
) -> int:
    """Do the plan's runs not yet in DIR/study.sqlite on `executor` (serial, process or Dask:
    the same numbers on each), recording each as it finishes; the number of runs done now.
    Refuses a store made from another plan."""
    check_out_dir(out_dir)
    specs = list(plan.runs())
    with study_lock(out_dir):
        finished: dict[str, Any] = {}
        if store_path(out_dir).exists():
            with Store.open(out_dir, "out") as old:
                finished = old.finished()
                if old.meta().get("study") not in (None, plan.name):
                    raise InputError("out", f"{str(out_dir)!r} holds another study")
        todo = {}
        for spec in specs:
            if spec.key not in finished:
                todo[spec.key] = spec
            elif finished[spec.key][0] != spec.spec_hash:
                raise InputError(
                    "out",
                    f"{str(out_dir)!r} already holds run {spec.key!r} made with other "
                    "settings (budget, population or seed); use a new --out folder",
                )
        done = len(specs) - len(todo)
        with Store.create(out_dir, {"study": plan.name, "kind": BBOB_KIND}) as store:
            for result in executor.results(list(todo.values())):
                store.record(todo[result.key], result)
                done += 1
                if progress is not None:
                    progress(done, len(specs))
    return len(todo)
