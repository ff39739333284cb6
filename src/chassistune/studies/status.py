"""`study status DIR`: what a study folder holds against its config (done, failed, missing)."""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

from chassistune.studies.lock import holder
from chassistune.studies.records import RunStatus
from chassistune.studies.spec import StudyConfig, parse_config, plan_study
from chassistune.studies.store import open_study


@dataclass(frozen=True)
class StudyStatus:
    """Counts of a study folder's runs and the config they come from."""

    name: str
    config: StudyConfig
    total: int
    completed: int
    failed: int
    missing: int
    scenarios: list[str]
    optimizers: list[str]
    running_pid: str | None
    """The PID of a driver holding the folder's lock, if one is running now."""


def study_status(study_dir: str | Path) -> StudyStatus:
    """Read DIR/study.sqlite (InputError naming DIR when it is not a study folder)."""
    with open_study(study_dir) as store:
        meta = store.meta()
        finished = store.finished()
    plan = plan_study(parse_config(json.loads(meta["config"])))
    keys = {r.key for r in plan.runs}
    done = [s for k, (_, s) in finished.items() if k in keys]
    completed = sum(s is RunStatus.COMPLETED for s in done)
    return StudyStatus(
        plan.config.study.name,
        plan.config,
        len(plan.runs),
        completed,
        len(done) - completed,
        len(plan.runs) - len(done),
        plan.scenarios,
        plan.optimizers,
        holder(study_dir),
    )
