"""`study status DIR`: what a study folder holds against its config (done, failed, missing)."""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

from chassistune.errors import InputError
from chassistune.studies import unrecorded
from chassistune.studies.lock import holder
from chassistune.studies.spec import StudyConfig, parse_config, plan_study
from chassistune.studies.store import Damage, open_study


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
    damaged: list[Damage]
    """Stored runs that do not read back (counted as missing: a rerun into a new folder redoes
    them)."""
    others: int
    """Stored runs of an earlier config (a scenario since renamed): not part of the study."""
    kept: int
    """Finished runs waiting in DIR/unrecorded/ (the store was locked): the next run stores
    them."""


def study_status(study_dir: str | Path) -> StudyStatus:
    """Read DIR/study.sqlite (InputError naming DIR when it is not a study folder or its
    file or config is damaged; damaged runs are listed, not raised)."""
    with open_study(study_dir) as store:
        meta = store.meta()
        scan = store.scan(integrity=True)
        path = store.path
    try:
        config = json.loads(meta["config"])
    except (KeyError, ValueError) as exc:
        raise InputError("DIR", f"{str(path)!r} holds no readable config ({exc})") from None
    plan = plan_study(parse_config(config))
    completed = sum(r.completed for r in scan.records)
    return StudyStatus(
        plan.config.study.name,
        plan.config,
        len(plan.runs),
        completed,
        len(scan.records) - completed,
        len(plan.runs) - len(scan.records),
        plan.scenarios,
        plan.optimizers,
        holder(study_dir),
        scan.damaged,
        scan.others,
        len(unrecorded.kept(study_dir)),
    )
